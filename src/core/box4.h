// The 4-wide slab test both BVH levels run on their nodes (four child boxes in SoA form): core/box.h's
// conservative intersectBox in SSE, lane by lane. Contract: every lane's hit flag, entry and exit are
// bit-identical to intersectBox on that lane's box (the same IEEE operations in the same order, no
// FMA; `tn > t0 ? tn : t0` is exactly _mm_max_ps(tn, t0) and `tf < t1 ? tf : t1` _mm_min_ps(tf, t1),
// NaN operands included), so traversal order, culling and the exactness arguments made for the
// scalar test hold for the vector one. Written with intrinsics because the compilers kept the plain
// loop scalar, which made node visits compute bound.
#pragma once
#include <immintrin.h>
#include "core/box.h"

namespace rayes {

// A RayBoxQuery broadcast to four lanes, prepared once per ray.
struct RayBox4Query {
  __m128 org[3], invDir[3];
  int sign[3];  // per axis: 1 when the near plane is hi (negative direction)
  explicit RayBox4Query(const RayBoxQuery& q) {
    for (int a = 0; a < 3; ++a) {
      org[a] = _mm_set1_ps(q.org[a]);
      invDir[a] = _mm_set1_ps(q.invDir[a]);
      sign[a] = q.sign[a];
    }
  }
};

// Four boxes given per axis by their near planes (lo where sign is 0, hi where it is 1) and far
// planes. tmin/tmax bound the segment per lane. Returns the mask of lanes whose box the segment
// crosses, with their entry (clamped to tmin) and exit distances.
inline unsigned intersectBox4(const RayBox4Query& q, const __m128 nearPlane[3], const __m128 farPlane[3],
                              __m128 tmin, __m128 tmax, __m128& tEntry, __m128& tExit) {
  const __m128 farScale = _mm_set1_ps(1.0f + 2.0f * gammaBound(3));
  __m128 t0 = tmin, t1 = tmax;
  for (int a = 0; a < 3; ++a) {
    const __m128 tn = _mm_mul_ps(_mm_sub_ps(nearPlane[a], q.org[a]), q.invDir[a]);
    const __m128 tf = _mm_mul_ps(_mm_mul_ps(_mm_sub_ps(farPlane[a], q.org[a]), q.invDir[a]), farScale);
    t0 = _mm_max_ps(tn, t0);
    t1 = _mm_min_ps(tf, t1);
  }
  tEntry = t0;
  tExit = t1;
  return unsigned(_mm_movemask_ps(_mm_cmple_ps(t0, t1)));
}

}  // namespace rayes
