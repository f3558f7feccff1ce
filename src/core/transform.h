// Affine transforms (3x4 row-major matrices) for placing shapes. Applied to control points:
// an affine map of a Bézier or bilinear patch's control points maps the surface exactly.
//
// Two precisions, one implementation: `TransformD` (double) is what a scene description is
// composed in -- a shape's steps, its motion keyframes, and the move into the render frame
// (scene/scene.h, RenderFrame) -- so that a translation of 10^6 and the camera's -10^6 cancel
// before anything is rounded to float; `point` then rounds each coordinate once. `Transform`
// (float) is what render-time code keeps (a medium's index map, a forest's placement): it is
// made from a TransformD that already places things in the render frame.
#pragma once
#include <cmath>
#include <numbers>
#include "core/vec.h"

namespace rayes {

template <class T>
struct BasicTransform {
  T m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};

  BasicTransform() = default;
  // Rounds (double -> float) or widens (float -> double) every entry.
  template <class U>
  explicit BasicTransform(const BasicTransform<U>& o) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) m[i][j] = T(o.m[i][j]);
  }

  // Computed in T, rounded to float once per coordinate.
  Vec3 point(Vec3 p) const {
    const T x = p.x, y = p.y, z = p.z;
    return {float(m[0][0] * x + m[0][1] * y + m[0][2] * z + m[0][3]),
            float(m[1][0] * x + m[1][1] * y + m[1][2] * z + m[1][3]),
            float(m[2][0] * x + m[2][1] * y + m[2][2] * z + m[2][3])};
  }
  // A double point mapped in T, rounded to float once per coordinate.
  Vec3 roundedPoint(Vec3d p) const { return pointD(p).toFloat(); }
  // Computed in T and kept in double (for T = double: no rounding to float at all).
  Vec3d pointD(Vec3d p) const {
    return {double(m[0][0] * T(p.x) + m[0][1] * T(p.y) + m[0][2] * T(p.z) + m[0][3]),
            double(m[1][0] * T(p.x) + m[1][1] * T(p.y) + m[1][2] * T(p.z) + m[1][3]),
            double(m[2][0] * T(p.x) + m[2][1] * T(p.y) + m[2][2] * T(p.z) + m[2][3])};
  }
  // this * o: first o, then this.
  BasicTransform operator*(const BasicTransform& o) const {
    BasicTransform r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) {
        T s = j == 3 ? m[i][3] : T(0);
        for (int k = 0; k < 3; ++k) s += m[i][k] * o.m[k][j];
        r.m[i][j] = s;
      }
    return r;
  }
  T determinant() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }
  bool isIdentity() const {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j)
        if (m[i][j] != T(i == j ? 1 : 0)) return false;
    return true;
  }
  static BasicTransform translate(Vec3 t) { return translate(T(t.x), T(t.y), T(t.z)); }
  static BasicTransform translate(T x, T y, T z) {
    BasicTransform r; r.m[0][3] = x; r.m[1][3] = y; r.m[2][3] = z; return r;
  }
  static BasicTransform scale(Vec3 s) { return scale(T(s.x), T(s.y), T(s.z)); }
  static BasicTransform scale(T x, T y, T z) {
    BasicTransform r; r.m[0][0] = x; r.m[1][1] = y; r.m[2][2] = z; return r;
  }
  // Rotation by `degrees` about `axis` (right-handed; normalised here).
  static BasicTransform rotate(Vec3 axis, T degrees) { return rotate(T(axis.x), T(axis.y), T(axis.z), degrees); }
  static BasicTransform rotate(T ax, T ay, T az, T degrees) {
    const T l = std::sqrt(ax * ax + ay * ay + az * az);
    const T x = l > 0 ? ax / l : T(0), y = l > 0 ? ay / l : T(0), z = l > 0 ? az / l : T(0);
    const T th = degrees * std::numbers::pi_v<T> / T(180);
    const T c = std::cos(th), s = std::sin(th), t = 1 - c;
    BasicTransform r;
    r.m[0][0] = t * x * x + c;     r.m[0][1] = t * x * y - s * z; r.m[0][2] = t * x * z + s * y;
    r.m[1][0] = t * x * y + s * z; r.m[1][1] = t * y * y + c;     r.m[1][2] = t * y * z - s * x;
    r.m[2][0] = t * x * z - s * y; r.m[2][1] = t * y * z + s * x; r.m[2][2] = t * z * z + c;
    return r;
  }
};

using Transform = BasicTransform<float>;
using TransformD = BasicTransform<double>;

}  // namespace rayes
