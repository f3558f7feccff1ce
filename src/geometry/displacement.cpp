#include "geometry/displacement.h"

namespace rayes {

void Displacement::sampleRow(int n, const Vec3* p, const Vec3* pu, const Vec3* pv, const float* u, float v,
                             HeightSample* out) const {
  for (int i = 0; i < n; ++i) out[i] = sample(p[i], pu[i], pv[i], u[i], v);
}

}  // namespace rayes
