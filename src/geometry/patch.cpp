#include "geometry/patch.h"

namespace rayes {

// Parameters are float(i) / float(2^level): exact dyadic numbers, so vertex (i*2^(m-k), j*2^(m-k))
// of a level-m dicing has the same (u, v) bits -- and hence the same position -- as vertex (i, j)
// of a level-k dicing. The implicit tree's level of detail rests on this.
void Patch::dice(int level, Vec3* positions, Vec3* normals) const {
  const int n = 1 << level;
  const float fn = float(n);
  for (int j = 0; j <= n; ++j) {
    const float v = float(j) / fn;
    for (int i = 0; i <= n; ++i) {
      const SurfacePoint sp = evaluate(float(i) / fn, v);
      positions[size_t(j) * (n + 1) + i] = sp.p;
      normals[size_t(j) * (n + 1) + i] = sp.n;
    }
  }
}

void Patch::borderPieceBoundsAt(int sample, int e, int k, uint32_t j, int split, Box3* out) const {
  const uint32_t pieces = 1u << split;
  const float inv = 1.0f / float(1u << (k + split));  // a power of two: the ends are exact
  for (uint32_t i = 0; i < pieces; ++i) {
    const float t0 = float(j * pieces + i) * inv, t1 = float(j * pieces + i + 1) * inv;
    switch (e) {
      case 0: out[i] = boundsOverAt(sample, t0, t1, 0.0f, 0.0f); break;
      case 1: out[i] = boundsOverAt(sample, 1.0f, 1.0f, t0, t1); break;
      case 2: out[i] = boundsOverAt(sample, t0, t1, 1.0f, 1.0f); break;
      default: out[i] = boundsOverAt(sample, 0.0f, 0.0f, t0, t1); break;
    }
  }
}

}  // namespace rayes
