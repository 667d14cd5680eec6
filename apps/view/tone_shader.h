// Per-pixel tone mapping on the GPU, the same curve as the PNG writer (hr::toneMap8): each vertex
// carries linear radiance (W/(m^2 sr)) as a vertex attribute, the rasteriser interpolates it exactly
// as hr::render interpolates a leaf's corners, and the fragment shader multiplies by the session's
// exposure, applies Reinhard's x/(1+x) and the sRGB curve. Back faces are black (surfaces emit and
// reflect from their front only, as in hr::render). Colours interpolated after tone mapping would
// bend every gradient; this keeps the viewer's stills equal to the renderer's.
#pragma once
#include <vtkActor.h>

namespace view {

/// Installs the shader on an actor whose mapper is a vtkOpenGLPolyDataMapper over poly data with the
/// point array "diffuse_radiance" and, when glossy, "glossy_radiance" (3 floats each).
void installToneShader(vtkActor* actor, bool glossy, double exposure);
/// The exposure (the radiance that maps to 0.18 before Reinhard is 1/exposure).
void setExposure(vtkActor* actor, double exposure);
/// Weight of the glossy attribute: 1 shows the extension's light, 0 the diffuse-only display.
void setGlossyWeight(vtkActor* actor, double weight);

}  // namespace view
