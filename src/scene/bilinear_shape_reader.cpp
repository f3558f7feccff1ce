#include <array>
#include "geometry/bilinear_patch.h"
#include "scene/shape_kinds.h"

namespace rayes {

// {"type": "bilinear", "quads": [[p00, p10, p01, p11], ...]}, optional "uvs": four (s, t)
// corners per quad, in the same order (readCornerUvs).
ShapeSource readBilinearShape(const ShapeContext& ctx) {
  const JsonReader& r = ctx.reader;
  const json& qs = r.member(ctx.shape, ctx.ptr, "quads");
  if (!qs.is_array() || qs.empty()) r.fail(ctx.ptr + "/quads", "expected a non-empty array of quads");
  std::vector<std::array<Vec3d, 4>> quads;  // in double until placed (see the Bézier reader)
  for (size_t k = 0; k < qs.size(); ++k) {
    const std::string p = ctx.ptr + "/quads/" + std::to_string(k);
    const json& q = qs[k];
    if (!q.is_array() || q.size() != 4) r.fail(p, "expected 4 corners [p00, p10, p01, p11]");
    quads.push_back({r.vec3d(q[0], p + "/0"), r.vec3d(q[1], p + "/1"), r.vec3d(q[2], p + "/2"), r.vec3d(q[3], p + "/3")});
  }
  return {{"quads", "uvs"},
          [quads](const TransformD& xf) {
            std::vector<PatchPtr> out;
            for (const auto& q : quads)
              out.push_back(std::make_shared<BilinearPatch>(xf.roundedPoint(q[0]), xf.roundedPoint(q[1]), xf.roundedPoint(q[2]), xf.roundedPoint(q[3])));
            return out;
          },
          readCornerUvs(ctx, quads.size())};
}

}  // namespace rayes
