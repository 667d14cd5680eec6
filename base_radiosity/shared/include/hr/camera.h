// Primary rays of a pinhole camera, shared by the radiosity renderer and the reference path tracer
// so that both see exactly the same pixels.
#pragma once
#include <hr/scene.h>

#include <cmath>

namespace hr {

class CameraRays {
 public:
  explicit CameraRays(const Camera& c)
      : eye_(c.eye), width_(c.width), height_(c.height) {
    f_ = glm::normalize(c.lookAt - c.eye);
    r_ = glm::normalize(glm::cross(f_, c.up));
    u_ = glm::cross(r_, f_);
    th_ = std::tan(0.5 * c.fovYDeg * kPi / 180.0);
    aspect_ = double(c.width) / c.height;
  }
  const Vec3& origin() const { return eye_; }
  /// Unit direction through the continuous image position (x, y): x in [0, width) from the left,
  /// y in [0, height) from the top; pixel (i, j) covers [i, i+1) x [j, j+1).
  Vec3 dir(double x, double y) const {
    double px = (2.0 * x / width_ - 1.0) * th_ * aspect_;
    double py = (1.0 - 2.0 * y / height_) * th_;
    return glm::normalize(f_ + px * r_ + py * u_);
  }

 private:
  Vec3 eye_, f_, r_, u_;
  double th_, aspect_;
  int width_, height_;
};

}  // namespace hr
