// Reading MGF (the Materials and Geometry Format of LBNL, Greg Ward 1995), the format of the classic
// radiosity test scenes. Geometry becomes the core's primitives (polygon, sphere, cylinder, cone,
// ring; tori and prisms as polygons), materials become modified Phong materials. The conversions are
// documented in docs/mgf.md; whatever is dropped or approximated is listed in Scene::dropped.
#pragma once
#include <hr/scene.h>

namespace hr {

/// Appends the MGF file's materials and objects to scene, every object transformed by xf (on top of
/// the file's own xf contexts). where prefixes messages ("scene.json: objects[2]: "). Throws InputError
/// naming the file, line and entity on any error.
void readMgf(const std::string& path, Scene& scene, const glm::dmat4& xf = glm::dmat4(1.0), const std::string& where = "");

/// The same from text already in memory (path names it in messages and anchors includes).
void parseMgf(const std::string& text, const std::string& path, Scene& scene);

/// A scene made of one MGF file (no cameras: callers frame one).
Scene loadMgfScene(const std::string& path);

/// MGF colour (CIE x, y chromaticity, luminance Y) to linear RGB with Rec. 709 primaries and MGF's
/// equal-energy white (so x = y = 1/3 maps to grey); negative components (out of gamut) clip to 0.
Rgb cieToRgb(double x, double y, double Y);

}  // namespace hr
