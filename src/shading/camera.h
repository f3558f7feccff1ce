// The perspective pinhole camera (v1 scene format). Generates camera rays with a footprint:
// a cone of zero width at the eye whose spread is one pixel's angle, so a ray's level of
// detail makes micro-quads about a pixel in size where it meets them.
#pragma once
#include <cmath>
#include <numbers>
#include "core/vec.h"

namespace rayes {

class PerspectiveCamera {
 public:
  PerspectiveCamera() = default;
  // fovYDegrees: vertical field of view. Requires a non-degenerate frame (the scene loader
  // rejects look-at == position and up parallel to the view direction).
  PerspectiveCamera(Vec3 position, Vec3 lookAt, Vec3 up, float fovYDegrees, int width, int height)
      : pos_(position), width_(width), height_(height) {
    forward_ = normalize(lookAt - position);
    right_ = normalize(cross(forward_, up));
    up_ = cross(right_, forward_);
    tanHalf_ = std::tan(0.5f * fovYDegrees * std::numbers::pi_v<float> / 180.0f);
    aspect_ = float(width) / float(height);
    pixelSpread_ = 2.0f * tanHalf_ / float(height);
  }
  // Ray through film position (px, py) in pixels (0,0 = top left corner). Direction is unit.
  void generate(float px, float py, Vec3& org, Vec3& dir) const {
    const float sx = (2.0f * px / float(width_) - 1.0f) * tanHalf_ * aspect_;
    const float sy = (1.0f - 2.0f * py / float(height_)) * tanHalf_;
    org = pos_;
    dir = normalize(forward_ + right_ * sx + up_ * sy);
  }
  float pixelSpread() const { return pixelSpread_; }
  Vec3 position() const { return pos_; }
  Vec3 forward() const { return forward_; }

 private:
  Vec3 pos_, forward_{0, 0, -1}, right_{1, 0, 0}, up_{0, 1, 0};
  float tanHalf_ = 1, aspect_ = 1, pixelSpread_ = 0;
  int width_ = 1, height_ = 1;
};

}  // namespace rayes
