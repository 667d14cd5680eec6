// The camera a scene without one gets. Framing the bounding box from outside shows nothing of a closed
// room but the back of its walls, so candidates inside the box are scored against the outside view
// by probing the scene with a coarse grid of primary rays: the camera that sees the most surfaces
// from their front side, not right at the eye, wins. Hosts differ in how they trace a ray, so each
// passes its own probe; the choice is deterministic (a fixed grid, ties go to the earlier candidate).
#pragma once
#include <hr/scene.h>
#include <hr/visibility.h>

#include <functional>

namespace hr {

/// What a probe ray met first: nothing (hit false), or a surface at distance t, front side or not.
struct ProbeHit {
  bool hit = false;
  double t = 0.0;
  bool front = false;
};
using ViewProbe = std::function<ProbeHit(const Vec3& org, const Vec3& dir)>;

/// Sums over a scene's surfaces from which its up axis is guessed.
struct UpEvidence {
  Vec3 emitterNormals{0.0};  // area-weighted normals of the emitters
  double emitterArea = 0.0;
  Vec3 alignedArea{0.0};     // [k]: area of surfaces whose normal is within 25 degrees of axis k
  void add(const Vec3& n, double area, bool emitter);
};

/// Lamps hang from ceilings and face down, so minus the emitters' normal sum gives up when the sum is
/// coherent (its length at least 0.3 of the emitters' area) and one axis holds at least 0.8 of it
/// (a lamp tilted 45 degrees decides nothing).
/// Otherwise (globe lamps, a lamp on each wall)
/// floors, ceilings and table tops make the horizontal area the largest: that axis, taken positive
/// (MGF's z-up and the JSON scenes' y-up both are).
Vec3 upAxis(const UpEvidence& e);

/// Of a 32 x 24 grid of the camera's primary rays: the fraction that meet a surface's front side
/// farther than 2 % of the box's diagonal from the eye, and the fraction that meet nothing.
struct ViewScore {
  double front = 0.0, escaped = 0.0;
};
ViewScore scoreView(const Camera& c, const Aabb& box, const ViewProbe& probe);

/// The box framed from outside, 30 degrees above its horizon (a floor is not seen edge-on), unless an eye inside the box (near each side
/// wall in turn, at 60 % of the height, looking across) is enclosed (at most 2 % of its rays escape)
/// and sees more front sides (by 0.05): then the best such eye. An open scene keeps the framing.
Camera autoCamera(const Aabb& box, const Vec3& up, const ViewProbe& probe);

/// autoCamera for a tessellated scene (the BRIGHT-like host, the path tracer, tests).
Camera autoCamera(const Scene& scene, const std::vector<Patch>& patches, const Visibility& vis);

}  // namespace hr
