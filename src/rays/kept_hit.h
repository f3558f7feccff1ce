// How both walks of the SortedEngine -- the sorted pipeline (rays/sorted_engine.cpp) and the
// one-ray-at-a-time walk (rays/single_ray_walk.cpp) -- bound a ray's search and record the hit
// they keep. One definition for both, because the two must find the same hit bit for bit (the
// walk alone is the reference the pipeline is tested against). Internal to the SortedEngine.
#pragma once
#include <algorithm>
#include <cstdint>
#include "core/next_float.h"
#include "core/ray_batch.h"
#include "dicing/dice_buffer.h"

namespace rayes {

// The farthest t a closest-hit ray still has to look at: its best hit `best` so far,
// inclusive, so that a leaf with an equal-distance hit and a smaller id is still found in a
// later iteration (the tie order must not depend on which iteration a leaf came in).
inline float searchLimit(const RayBatch& b, uint32_t i, float best) {
  if (b.ray[i].kind == RayKind::Shadow) return b.ray[i].tmax;
  return std::min(b.ray[i].tmax, nextFloatUp(best));
}

// The distance a hit on a leaf is ordered and kept by: its t, but never less than the ray's
// entry into the leaf's box as the top level computed it (`entry`, SortedEngine::leafEntry). A hit
// can be reported a few roundings before that entry (on the box's face, where the rounded slab
// distance and the watertight test's t err in opposite directions, or in a crack-closing
// region that bulges past the box), and a ray is finished when its hit is nearer than its next
// candidate's entry: without the clamp such a hit could beat the one found first or not,
// depending on whether its leaf came in the same iteration, so the image depended on the
// candidates per ray and the ray budget. Clamped, every hit on a leaf not yet visited is at
// least its entry, and the kept hit is the minimum of one total order in every mode. The
// shift is at most the intersection's own error (or a region's radius).
inline float keptDistance(float t, float entry) { return std::max(t, entry); }

// A hit as the RayHit keeps it: the distance clamped as above, normals octahedral-encoded (the
// same record in every mode, so the sorted and alone modes agree bit for bit).
inline RayHit hitRecord(const GridHit& h, uint32_t leaf, int level, float entry) {
  RayHit r;
  r.t = keptDistance(h.t, entry); r.u = h.u; r.v = h.v; r.leaf = leaf; r.quad = h.quad;
  r.level = static_cast<uint8_t>(level);
  r.border = h.border;
  r.setNormals(h.ng, h.ns);
  return r;
}

// The surface derivatives the batch keeps with that hit (RayBatch::dpd, when it keeps any): the
// grid hit's, unchanged, so both walks store the same bits.
inline HitDerivatives keptDerivatives(const GridHit& h) { return {h.dpdu, h.dpdv}; }

}  // namespace rayes
