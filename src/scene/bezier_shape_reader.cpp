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
  std::vector<std::array<Vec3, 16>> patches;
  if (shape.contains("file")) {
    patches = loadBezierPatchFile(ctx.file("file").string());
  } else {
    const json& ps = shape["patches"];
    if (!ps.is_array() || ps.empty()) r.fail(p + "/patches", "expected a non-empty array of patches");
    for (size_t k = 0; k < ps.size(); ++k) {
      const std::string pp = p + "/patches/" + std::to_string(k);
      if (!ps[k].is_array() || ps[k].size() != 16) r.fail(pp, "expected 16 control points (4x4, row by row)");
      std::array<Vec3, 16> cp;
      for (int c = 0; c < 16; ++c) cp[c] = r.vec3(ps[k][c], pp + "/" + std::to_string(c));
      patches.push_back(cp);
    }
  }
  return {{"file", "patches", "uvs"},
          [patches](const Transform& xf) {
            std::vector<PatchPtr> out;
            for (auto cp : patches) {
              for (auto& v : cp) v = xf.point(v);
              out.push_back(std::make_shared<BezierPatch>(cp));
            }
            return out;
          },
          readCornerUvs(ctx, patches.size())};
}

}  // namespace rayes
