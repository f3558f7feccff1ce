#include "scene/shape_kinds.h"

namespace rayes {

TransformD readTransform(const JsonReader& r, const json& j, const std::string& ptr) {
  if (!j.is_array()) r.fail(ptr, "expected an array of transform steps");
  TransformD t;
  for (size_t i = 0; i < j.size(); ++i) {
    const std::string p = ptr + "/" + std::to_string(i);
    const json& step = j[i];
    r.object(step, p, {"translate", "rotate", "scale", "matrix"});
    if (step.size() != 1) r.fail(p, "each transform step has exactly one of translate, rotate, scale, matrix");
    TransformD s;
    if (step.contains("translate")) {
      const Vec3d t = r.vec3d(step["translate"], p + "/translate");
      s = TransformD::translate(t.x, t.y, t.z);
    } else if (step.contains("scale")) {
      const json& sc = step["scale"];
      const double k = sc.is_number() ? r.number(sc, p + "/scale") : 0;
      const Vec3d v = sc.is_number() ? Vec3d{k, k, k} : r.vec3d(sc, p + "/scale");
      if (v.x == 0 || v.y == 0 || v.z == 0) r.fail(p + "/scale", "a zero scale collapses the shape");
      s = TransformD::scale(v.x, v.y, v.z);
    } else if (step.contains("rotate")) {
      const json& ro = step["rotate"];
      r.object(ro, p + "/rotate", {"axis", "degrees"});
      const Vec3d axis = r.vec3d(r.member(ro, p + "/rotate", "axis"), p + "/rotate/axis");
      if (!(length(axis) > 0)) r.fail(p + "/rotate/axis", "the rotation axis must not be zero");
      s = TransformD::rotate(axis.x, axis.y, axis.z, r.number(r.member(ro, p + "/rotate", "degrees"), p + "/rotate/degrees"));
    } else {
      const json& m = step["matrix"];
      if (!m.is_array() || (m.size() != 12 && m.size() != 16))
        r.fail(p + "/matrix", "expected 12 or 16 numbers (row-major)");
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col)
          s.m[row][col] = (r.number(m[row * 4 + col], p + "/matrix/" + std::to_string(row * 4 + col)));
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
