#include <array>
#include "geometry/bezier_patch.h"
#include "scene/shape_kinds.h"

namespace rayes {

// {"type": "bezier", "file": "x.bpt"} or {"type": "bezier", "patches": [[16 points], ...]},
// optional "uvs": four (s, t) corners per patch (readCornerUvs).
ShapeSource readBezierShape(const ShapeContext& ctx) {
  const JsonReader& r = ctx.reader;
  const json& shape = ctx.shape;
  const std::string& p = ctx.ptr;
  if (shape.contains("file") == shape.contains("patches"))
    r.fail(p, "a bezier shape needs exactly one of 'file' and 'patches'");
  // Control points in double until the transform (with the move into the render frame) is
  // applied: a patch written at 10^6 in the file keeps its shape near the camera.
  std::vector<std::array<Vec3d, 16>> patches;
  if (shape.contains("file")) {
    for (const auto& cp : loadBezierPatchFile(ctx.file("file").string())) {
      std::array<Vec3d, 16> d;
      for (int c = 0; c < 16; ++c) d[c] = Vec3d(cp[c]);
      patches.push_back(d);
    }
  } else {
    const json& ps = shape["patches"];
    if (!ps.is_array() || ps.empty()) r.fail(p + "/patches", "expected a non-empty array of patches");
    for (size_t k = 0; k < ps.size(); ++k) {
      const std::string pp = p + "/patches/" + std::to_string(k);
      if (!ps[k].is_array() || ps[k].size() != 16) r.fail(pp, "expected 16 control points (4x4, row by row)");
      std::array<Vec3d, 16> cp;
      for (int c = 0; c < 16; ++c) cp[c] = r.vec3d(ps[k][c], pp + "/" + std::to_string(c));
      patches.push_back(cp);
    }
  }
  return {{"file", "patches", "uvs"},
          [patches](const TransformD& xf) {
            std::vector<PatchPtr> out;
            for (const auto& cpd : patches) {
              std::array<Vec3, 16> cp;
              for (int c = 0; c < 16; ++c) cp[c] = xf.roundedPoint(cpd[c]);
              out.push_back(std::make_shared<BezierPatch>(cp));
            }
            return out;
          },
          readCornerUvs(ctx, patches.size())};
}

}  // namespace rayes
