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

}  // namespace rayes
