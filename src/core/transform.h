// Affine transforms (3x4 row-major matrices) for placing shapes. Applied to control points:
// an affine map of a Bézier or bilinear patch's control points maps the surface exactly.
#pragma once
#include <cmath>
#include <numbers>
#include "core/vec.h"

namespace rayes {

struct Transform {
  float m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};

  Vec3 point(Vec3 p) const {
    return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
            m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
  }
  // this * o: first o, then this.
  Transform operator*(const Transform& o) const {
    Transform r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) {
        float s = j == 3 ? m[i][3] : 0.0f;
        for (int k = 0; k < 3; ++k) s += m[i][k] * o.m[k][j];
        r.m[i][j] = s;
      }
    return r;
  }
  float determinant() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }
  static Transform translate(Vec3 t) {
    Transform r; r.m[0][3] = t.x; r.m[1][3] = t.y; r.m[2][3] = t.z; return r;
  }
  static Transform scale(Vec3 s) {
    Transform r; r.m[0][0] = s.x; r.m[1][1] = s.y; r.m[2][2] = s.z; return r;
  }
  // Rotation by `degrees` about the unit `axis` (right-handed).
  static Transform rotate(Vec3 axis, float degrees) {
    const Vec3 a = normalize(axis);
    const float th = degrees * std::numbers::pi_v<float> / 180.0f;
    const float c = std::cos(th), s = std::sin(th), t = 1 - c;
    Transform r;
    r.m[0][0] = t * a.x * a.x + c;       r.m[0][1] = t * a.x * a.y - s * a.z; r.m[0][2] = t * a.x * a.z + s * a.y;
    r.m[1][0] = t * a.x * a.y + s * a.z; r.m[1][1] = t * a.y * a.y + c;       r.m[1][2] = t * a.y * a.z - s * a.x;
    r.m[2][0] = t * a.x * a.z - s * a.y; r.m[2][1] = t * a.y * a.z + s * a.x; r.m[2][2] = t * a.z * a.z + c;
    return r;
  }
};

}  // namespace rayes
