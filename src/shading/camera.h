// The perspective camera: a pinhole, or a thin lens when the aperture radius is positive, with
// a shutter interval. Generates camera rays with a footprint: a cone whose width at the lens is
// the aperture diameter shrinking to one pixel at the focus distance (a pinhole: width 0 and
// one pixel's angle), so a ray's level of detail makes micro-quads about a pixel in size where
// it meets them, and out-of-focus geometry is diced coarser.
// Immutable after construction; generate() is const and thread-safe.
#pragma once
#include <cmath>
#include <numbers>
#include "core/vec.h"

namespace rayes {

struct CameraRay {
  Vec3 org, dir;      // dir is unit
  float coneWidth;    // footprint width at org
  float coneSpread;   // footprint growth per unit distance (may be negative toward the focus)
  float time;         // in [shutterOpen, shutterClose]
};

class PerspectiveCamera {
 public:
  PerspectiveCamera() = default;
  // fovYDegrees: vertical field of view. Requires a non-degenerate frame (the scene loader
  // rejects look-at == position and up parallel to the view direction). apertureRadius 0 is a
  // pinhole; focusDistance > 0 is measured along the view axis.
  PerspectiveCamera(Vec3 position, Vec3 lookAt, Vec3 up, float fovYDegrees, int width, int height,
                    float apertureRadius = 0, float focusDistance = 1, float shutterOpen = 0,
                    float shutterClose = 0)
      : pos_(position), width_(width), height_(height), aperture_(apertureRadius),
        focus_(focusDistance), open_(shutterOpen), close_(shutterClose) {
    forward_ = normalize(lookAt - position);
    right_ = normalize(cross(forward_, up));
    up_ = cross(right_, forward_);
    tanHalf_ = std::tan(0.5f * fovYDegrees * std::numbers::pi_v<float> / 180.0f);
    aspect_ = float(width) / float(height);
    pixelSpread_ = 2.0f * tanHalf_ / float(height);
  }

  // Ray through film position (px, py) in pixels (0,0 = top left corner), lens sample
  // (lu, lv) in [0,1)^2 and shutter sample ts in [0,1).
  CameraRay generate(float px, float py, float lu, float lv, float ts) const {
    const float sx = (2.0f * px / float(width_) - 1.0f) * tanHalf_ * aspect_;
    const float sy = (1.0f - 2.0f * py / float(height_)) * tanHalf_;
    const Vec3 pinholeDir = forward_ + right_ * sx + up_ * sy;  // reaches the focus plane at t = focus
    CameraRay r;
    r.time = open_ + (close_ - open_) * ts;
    if (!(aperture_ > 0)) {
      r.org = pos_;
      r.dir = normalize(pinholeDir);
      r.coneWidth = 0;
      r.coneSpread = pixelSpread_;
      return r;
    }
    // Concentric mapping of the unit square to the disk (Shirley-Chiu): area preserving and
    // finite at the centre and the edges.
    const float a = 2 * lu - 1, b = 2 * lv - 1;
    float rad = 0, phi = 0;
    if (a != 0 || b != 0) {
      const float q = std::numbers::pi_v<float> / 4;
      if (std::fabs(a) > std::fabs(b)) { rad = a; phi = q * (b / a); }
      else { rad = b; phi = 2 * q - q * (a / b); }
    }
    const Vec3 lens = right_ * (aperture_ * rad * std::cos(phi)) + up_ * (aperture_ * rad * std::sin(phi));
    const Vec3 focusPoint = pos_ + pinholeDir * focus_;
    r.org = pos_ + lens;
    const Vec3 d = focusPoint - r.org;
    const float dist = length(d);
    r.dir = d * (1.0f / dist);
    r.coneWidth = 0;
    r.coneSpread = pixelSpread_;
    return r;
  }

  float apertureRadius() const { return aperture_; }
  Vec3 position() const { return pos_; }
  Vec3 forward() const { return forward_; }
  // Footprint growth of a camera ray per unit distance: one pixel's angle (the ray's coneSpread).
  float pixelSpread() const { return pixelSpread_; }

 private:
  Vec3 pos_, forward_{0, 0, -1}, right_{1, 0, 0}, up_{0, 1, 0};
  float tanHalf_ = 1, aspect_ = 1, pixelSpread_ = 0;
  int width_ = 1, height_ = 1;
  float aperture_ = 0, focus_ = 1, open_ = 0, close_ = 0;
};

}  // namespace rayes
