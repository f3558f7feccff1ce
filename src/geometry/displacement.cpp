#include "geometry/displacement.h"
#include <limits>

namespace rayes {

void Displacement::sampleRow(int n, const Vec3* p, const Vec3* pu, const Vec3* pv, const float* u, float v,
                             HeightSample* out) const {
  for (int i = 0; i < n; ++i) out[i] = sample(p[i], pu[i], pv[i], u[i], v);
}

float Displacement::magnitudeBound() const { return std::numeric_limits<float>::infinity(); }

}  // namespace rayes
