#include "scene/shape_kinds.h"

namespace rayes {

Transform readTransform(const JsonReader& r, const json& j, const std::string& ptr) {
  if (!j.is_array()) r.fail(ptr, "expected an array of transform steps");
  Transform t;
  for (size_t i = 0; i < j.size(); ++i) {
    const std::string p = ptr + "/" + std::to_string(i);
    const json& step = j[i];
    r.object(step, p, {"translate", "rotate", "scale", "matrix"});
    if (step.size() != 1) r.fail(p, "each transform step has exactly one of translate, rotate, scale, matrix");
    Transform s;
    if (step.contains("translate")) {
      s = Transform::translate(r.vec3(step["translate"], p + "/translate"));
    } else if (step.contains("scale")) {
      const json& sc = step["scale"];
      const Vec3 v = sc.is_number() ? Vec3{1, 1, 1} * float(r.number(sc, p + "/scale")) : r.vec3(sc, p + "/scale");
      if (v.x == 0 || v.y == 0 || v.z == 0) r.fail(p + "/scale", "a zero scale collapses the shape");
      s = Transform::scale(v);
    } else if (step.contains("rotate")) {
      const json& ro = step["rotate"];
      r.object(ro, p + "/rotate", {"axis", "degrees"});
      const Vec3 axis = r.vec3(r.member(ro, p + "/rotate", "axis"), p + "/rotate/axis");
      if (!(length(axis) > 0)) r.fail(p + "/rotate/axis", "the rotation axis must not be zero");
      s = Transform::rotate(axis, float(r.number(r.member(ro, p + "/rotate", "degrees"), p + "/rotate/degrees")));
    } else {
      const json& m = step["matrix"];
      if (!m.is_array() || (m.size() != 12 && m.size() != 16))
        r.fail(p + "/matrix", "expected 12 or 16 numbers (row-major)");
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col)
          s.m[row][col] = float(r.number(m[row * 4 + col], p + "/matrix/" + std::to_string(row * 4 + col)));
      if (m.size() == 16) {
        const double w[4] = {r.number(m[12], p + "/matrix/12"), r.number(m[13], p + "/matrix/13"),
                             r.number(m[14], p + "/matrix/14"), r.number(m[15], p + "/matrix/15")};
        if (w[0] != 0 || w[1] != 0 || w[2] != 0 || w[3] != 1)
          r.fail(p + "/matrix", "the last row must be 0 0 0 1 (affine transforms only)");
      }
      if (!(std::fabs(s.determinant()) > 0)) r.fail(p + "/matrix", "the matrix is singular");
    }
    t = s * t;  // steps apply in the order listed
  }
  return t;
}

}  // namespace rayes
