// The "motion" modifier of a shape (docs/scene-format.md, "Motion"):
//   "motion": {"times": [t0, t1, ...], "transforms": [[steps...], [steps...], ...]}
// one transform keyframe per time, applied after the shape's own "transform". The shape is
// built once per keyframe (displacement included) and each patch becomes a MovingPatch of its
// K versions; between keyframes positions are interpolated linearly (thesis §6.3).
#include <cstring>
#include "geometry/moving_patch.h"
#include "scene/shape_kinds.h"

namespace rayes {

Motion readMotion(const ShapeContext& ctx) {
  const JsonReader& r = ctx.reader;
  const std::string p = ctx.ptr + "/motion";
  const json& j = ctx.shape["motion"];
  r.object(j, p, {"times", "transforms"});
  const json& times = r.member(j, p, "times");
  if (!times.is_array() || times.size() < 2)
    r.fail(p + "/times", "expected an array of at least 2 times (one per time sample)");
  Motion m;
  for (size_t k = 0; k < times.size(); ++k) {
    const std::string tp = p + "/times/" + std::to_string(k);
    m.times.push_back(float(r.number(times[k], tp)));
    if (k > 0 && !(m.times[k] > m.times[k - 1])) r.fail(tp, "times must be strictly increasing");
  }
  const json& xfs = r.member(j, p, "transforms");
  if (!xfs.is_array()) r.fail(p + "/transforms", "expected an array of transforms, one per time sample");
  if (xfs.size() != times.size())
    r.fail(p + "/transforms", "time sample counts disagree: " + std::to_string(times.size()) + " times but " +
                                  std::to_string(xfs.size()) + " transforms (every motion attribute needs one entry "
                                  "per time)");
  for (size_t k = 0; k < xfs.size(); ++k)
    m.keyframes.push_back(readTransform(r, xfs[k], p + "/transforms/" + std::to_string(k)));
  return m;
}

std::vector<PatchPtr> movingPatches(const Motion& m, const TransformD& xf,
                                    const std::function<std::vector<PatchPtr>(const TransformD&)>& build) {
  // Keyframes that do not move the shape: one time sample, stored and diced once.
  bool still = true;
  for (const TransformD& k : m.keyframes) still = still && std::memcmp(k.m, m.keyframes[0].m, sizeof k.m) == 0;
  if (still) return build(m.keyframes[0] * xf);
  std::vector<std::vector<PatchPtr>> samples;
  for (const TransformD& k : m.keyframes) samples.push_back(build(k * xf));
  std::vector<PatchPtr> out;
  for (size_t i = 0; i < samples[0].size(); ++i) {
    std::vector<PatchPtr> versions;
    for (const auto& s : samples) versions.push_back(s[i]);
    out.push_back(std::make_shared<MovingPatch>(std::move(versions), m.times));
  }
  return out;
}

}  // namespace rayes
