#include "dicing/micro_quad.h"
#include <limits>
#include <utility>

namespace rayes {

bool makeWatertightRay(Vec3 org, Vec3 dir, WatertightRay& ray) {
  if (!isFinite(org) || !isFinite(dir)) return false;
  const int kz = maxDimension(vabs(dir));
  if (!(std::fabs(dir[kz]) >= std::numeric_limits<float>::min())) return false;
  int kx = kz == 2 ? 0 : kz + 1;
  int ky = kx == 2 ? 0 : kx + 1;
  // Keep the triangle winding in the sheared frame independent of the direction's sign.
  if (dir[kz] < 0.0f) std::swap(kx, ky);
  ray.org = org;
  ray.kx = kx;
  ray.ky = ky;
  ray.kz = kz;
  ray.ox = org[kx];
  ray.oy = org[ky];
  ray.oz = org[kz];
  ray.axes = 2 * kz + (kx != (kz + 1) % 3 ? 1 : 0);
  ray.sx = dir[kx] / dir[kz];
  ray.sy = dir[ky] / dir[kz];
  ray.sz = 1.0f / dir[kz];
  return true;
}

namespace detail {

bool hitTriangleDouble(const Projected& a, const Projected& b, const Projected& c, float tmin,
                       float tmax, float& t, float& wb, float& wc) {
  // Products of floats are exact in double, so only the final subtraction rounds and the signs
  // are exact.
  auto edge = [](const Projected& p, const Projected& q) {
    return double(q.x) * double(p.y) - double(q.y) * double(p.x);
  };
  const double U = edge(b, c), V = edge(c, a), W = edge(a, b);
  if ((U < 0.0 || V < 0.0 || W < 0.0) && (U > 0.0 || V > 0.0 || W > 0.0)) return false;
  const double det = U + V + W;
  if (det == 0.0) return false;
  const double td = (U * a.z + V * b.z + W * c.z) / det;
  t = float(td);
  if (!(t > tmin && t < tmax)) return false;
  wb = float(V / det);
  wc = float(W / det);
  return true;
}

bool unitTriangleNormal(Vec3 a, Vec3 b, Vec3 c, Vec3& n) {
  // Double keeps tiny (1e-3-scaled, micro) and huge triangles from under/overflowing.
  const double e1[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
  const double e2[3] = {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
  const double x = e1[1] * e2[2] - e1[2] * e2[1];
  const double y = e1[2] * e2[0] - e1[0] * e2[2];
  const double z = e1[0] * e2[1] - e1[1] * e2[0];
  const double len = std::sqrt(x * x + y * y + z * z);
  if (!(len > 0.0) || !std::isfinite(len)) return false;
  n = {float(x / len), float(y / len), float(z / len)};
  return true;
}

}  // namespace detail
}  // namespace rayes
