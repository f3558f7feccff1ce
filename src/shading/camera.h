// The perspective camera: a pinhole, or a thin lens when the aperture radius is positive, with
// a shutter interval. Generates camera rays with a footprint: a cone whose width at the lens is
// the aperture diameter shrinking to one pixel at the focus distance (a pinhole: width 0 and
// one pixel's angle), so a ray's level of detail makes micro-quads about a pixel in size where
// it meets them, and out-of-focus geometry is diced coarser.
// Immutable after construction; generate() is const and thread-safe.
#pragma once
#include <cmath>
#include <numbers>
#include "core/disk_mapping.h"
#include "core/vec.h"

namespace rayes {

struct CameraRay {
  Vec3 org, dir;      // dir is unit
  float coneWidth;    // footprint width at org
  float coneSpread;   // footprint growth per unit distance (may be negative toward the focus)
  float time;         // in [shutterOpen, shutterClose]
};

// A scene point seen from the camera, for light tracing (PerspectiveCamera::connect).
struct CameraConnection {
  Vec3 lens;          // the point on the lens (the pinhole for aperture 0)
  float px, py;       // the film position in pixels whose camera ray passes lens -> x
  float importance;   // W / d²: the splat is radiance toward the lens x |cos at x| x this
  float coneWidth, coneSpread;  // the footprint at x shrinking toward the lens (as a camera ray's)
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
    r.time = timeAt(ts);
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

  // Shutter time of the sample ts in [0, 1).
  float timeAt(float ts) const { return open_ + (close_ - open_) * ts; }

  // Connects scene point x to the lens point (lu, lv) (sampled as generate() samples it).
  // Returns false when x is not in front of the lens or not on the film.
  //
  // The importance. generate() picks a film position uniformly in the pixel, i.e. uniformly
  // on the pixel's piece of the image plane at distance 1 in front of the lens centre (the
  // whole plane has area A = 4 tan²(fov/2) aspect, a pixel A / N of it), and a lens point
  // uniformly; a pixel's value is the mean radiance over those rays. Through the focus plane
  // at distance F the ray hits a point q with density N / (A F²) on the pixel's part of that
  // plane; the ray lens -> q -> x turns dA_q into dA_x by
  //   dA_q = |cos_x| dA_x / d² · (F / cos θ)² / cos θ,
  // with θ the angle between the ray and the view axis and d = |x - lens|. So, per lens
  // sample, a pixel's value is ∫ L(x -> lens) |cos_x| N / (A cos³θ d²) dA_x over the points
  // it sees. The N goes into the film's splat scale: a light path adds to one pixel, and
  // N x (light paths per pixel) paths estimate the image, so the film divides the splat sums
  // by the light paths per pixel and the importance here is 1 / (A cos³θ d²) -- the
  // pinhole's 1 / (A cos⁴θ) per unit image-plane area, times cos θ / d² from the lens's solid
  // angle to x's area. A thin lens needs no extra factor: the lens is sampled with
  // generate()'s own density.
  bool connect(Vec3 x, float lu, float lv, CameraConnection& out) const {
    out.lens = pos_;
    if (aperture_ > 0) {
      float dx, dy;
      concentricDisk(lu, lv, dx, dy);
      out.lens = pos_ + right_ * (aperture_ * dx) + up_ * (aperture_ * dy);
    }
    const Vec3 d = x - out.lens;
    const float d2 = dot(d, d), along = dot(d, forward_);
    if (!(d2 > 0) || !(along > 0) || !std::isfinite(d2)) return false;
    // Where the ray crosses the focus plane, as an image-plane position at distance 1.
    const float focus = aperture_ > 0 ? focus_ : 1.0f;
    const Vec3 q = out.lens - pos_ + d * (focus / along);
    const float sx = dot(q, right_) / focus, sy = dot(q, up_) / focus;
    out.px = (sx / (tanHalf_ * aspect_) + 1.0f) * 0.5f * float(width_);
    out.py = (1.0f - sy / tanHalf_) * 0.5f * float(height_);
    if (!(out.px >= 0 && out.px < float(width_) && out.py >= 0 && out.py < float(height_))) return false;
    const float dist = std::sqrt(d2);
    const float cosTheta = along / dist;
    const float area = 4.0f * tanHalf_ * tanHalf_ * aspect_;
    out.importance = 1.0f / (area * cosTheta * cosTheta * cosTheta * d2);
    out.coneWidth = pixelSpread_ * dist;
    out.coneSpread = -pixelSpread_;
    return std::isfinite(out.importance);
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
