#include "shading/footprint.h"
#include <algorithm>
#include <cmath>

namespace rayes {
namespace {

// Double precision inside: a footprint may be asked of micro-scale and kilometre-scale scenes
// alike, and the normal equations square the Jacobian's lengths.
struct D3 {
  double x = 0, y = 0, z = 0;
};
D3 d3(Vec3 a) { return {a.x, a.y, a.z}; }
Vec3 f3(D3 a) { return {float(a.x), float(a.y), float(a.z)}; }
double dotD(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 crossD(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
D3 scaleD(D3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
bool finiteD(D3 a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

// Ridge of the normalised normal equations: det >= 2e-9, so a parallel Jacobian amplifies by
// at most 1 / (2e-9) (then kMaxFootprintAxis clamps); otherwise the solution is off by at most
// 1e-9 / (1 - |cos|) relative, |cos| the angle between the columns: below float rounding
// unless they are within a few 1e-3 rad of parallel.
constexpr double kRegularisation = 1e-9;

float clampAxis(double x) {
  if (!std::isfinite(x)) return std::isnan(x) ? 0.0f : (x > 0 ? kMaxFootprintAxis : -kMaxFootprintAxis);
  return float(std::clamp(x, -double(kMaxFootprintAxis), double(kMaxFootprintAxis)));
}

}  // namespace

void footprintAxes(Vec3 d, Vec3 n, float w, Vec3& A, Vec3& B) {
  A = B = Vec3{};
  if (!(w > 0) || !std::isfinite(w) || !isFinite(d) || !isFinite(n)) return;
  const D3 dd = d3(d), nd = d3(n);
  const double dl = std::sqrt(dotD(dd, dd)), nl = std::sqrt(dotD(nd, nd));
  if (!(dl > 0) || !(nl > 0) || !std::isfinite(dl) || !std::isfinite(nl)) return;
  const D3 du = scaleD(dd, 1 / dl), nu = scaleD(nd, 1 / nl);
  const double cosTheta = std::fabs(dotD(nu, du));
  const D3 side = crossD(nu, du);
  const double sinTheta = std::sqrt(dotD(side, side));
  if (!(sinTheta > 1e-7)) {
    // Normal incidence: the cross-section is a circle; any orthonormal pair of the plane.
    Vec3 t, b;
    orthonormalBasis(f3(nu), t, b);
    A = t * w;
    B = b * w;
    return;
  }
  const D3 minor = scaleD(side, 1 / sinTheta);  // unit, along n x d
  const D3 major = crossD(minor, nu);           // unit, in the plane, along d's projection
  // 1 / cos θ capped (kMaxFootprintStretch); cos θ = 0 (a ray in the plane) gives the cap.
  const double stretch = cosTheta * kMaxFootprintStretch > 1 ? 1 / cosTheta : double(kMaxFootprintStretch);
  A = f3(scaleD(major, double(w) * stretch));
  B = f3(scaleD(minor, double(w)));
}

void toParameters(Vec3 a, Vec3 dpdu, Vec3 dpdv, float& du, float& dv) {
  du = dv = 0;
  const D3 ad = d3(a), pu = d3(dpdu), pv = d3(dpdv);
  if (!finiteD(ad) || !finiteD(pu) || !finiteD(pv)) return;
  const double lu = std::sqrt(dotD(pu, pu)), lv = std::sqrt(dotD(pv, pv));
  if (!(lu > 0) && !(lv > 0)) return;
  if (!(lu > 0)) {  // u collapsed (a pole, a degenerate edge): only v can move
    dv = clampAxis(dotD(pv, ad) / (lv * lv));
    return;
  }
  if (!(lv > 0)) {
    du = clampAxis(dotD(pu, ad) / (lu * lu));
    return;
  }
  // Normal equations of the columns scaled to unit length, so the regularisation is relative
  // to neither column's length (a long thin patch keeps its short direction).
  const D3 eu = scaleD(pu, 1 / lu), ev = scaleD(pv, 1 / lv);
  const double c = dotD(eu, ev), r1 = dotD(eu, ad), r2 = dotD(ev, ad);
  const double diag = 1 + kRegularisation;
  const double det = diag * diag - c * c;
  du = clampAxis((diag * r1 - c * r2) / det / lu);
  dv = clampAxis((diag * r2 - c * r1) / det / lv);
}

float cameraFootprintScale(int samplesPerPixel) {
  return std::max(0.125f, 1.0f / std::sqrt(float(std::max(1, samplesPerPixel))));
}

TextureQuery footprintQuery(float u, float v, Vec3 d, Vec3 n, float width, const HitDerivatives* dpd,
                            const TexCoordSample* uv) {
  TextureQuery q = TextureQuery::at(u, v);
  if (uv) {
    q.hasUv = true;
    q.uv.x = uv->s;
    q.uv.y = uv->t;
  }
  if (!dpd) return q;
  Vec3 A, B;
  footprintAxes(d, n, width, A, B);
  toParameters(A, dpd->dpdu, dpd->dpdv, q.patch.dxA, q.patch.dyA);
  toParameters(B, dpd->dpdu, dpd->dpdv, q.patch.dxB, q.patch.dyB);
  if (uv) {
    auto map = [&](float du, float dv, float& ds, float& dt) {
      ds = clampAxis(double(uv->dsdu) * du + double(uv->dsdv) * dv);
      dt = clampAxis(double(uv->dtdu) * du + double(uv->dtdv) * dv);
    };
    map(q.patch.dxA, q.patch.dyA, q.uv.dxA, q.uv.dyA);
    map(q.patch.dxB, q.patch.dyB, q.uv.dxB, q.uv.dyB);
  }
  return q;
}

}  // namespace rayes
