#include "geometry/displaced_patch.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>
#include "core/interval.h"
#include "core/vector_isa.h"
#include "geometry/bezier_patch.h"
#include "geometry/bilinear_patch.h"
#include "geometry/bezier_restriction.h"
#include "geometry/patch_math.h"

namespace rayes {

namespace {

using detail::unitOrZero;

struct IVec3 {
  Interval x, y, z;
};

IVec3 toIntervals(const Box3& b) { return {{b.lo.x, b.hi.x}, {b.lo.y, b.hi.y}, {b.lo.z, b.hi.z}}; }

IVec3 cross(const IVec3& a, const IVec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

Box3 widenedBox(Box3 b, float m) {
  b.lo = b.lo - Vec3{m, m, m};
  b.hi = b.hi + Vec3{m, m, m};
  return b;
}

// Every unit normal, widened for the rounding of unitOrZero().
Box3 allDirections() { return {{-1.000001f, -1.000001f, -1.000001f}, {1.000001f, 1.000001f, 1.000001f}}; }

// Per component, the range of n / |n| over n in the box `nb` (in double; then widened).
// `degenerate`: below this magnitude (max component) the base substitutes a nudged normal,
// whose direction we know nothing of, so a box reaching it gives every direction.
Box3 unitRange(const IVec3& nb, double degenerate) {
  const Interval c[3] = {nb.x, nb.y, nb.z};
  double dmin2 = 0, dmax2 = 0, minMaxAbs = 0;
  for (const Interval& i : c) {
    if (!std::isfinite(i.lo) || !std::isfinite(i.hi)) return allDirections();
    const double lo = i.lo, hi = i.hi;
    const double near = (lo <= 0 && hi >= 0) ? 0.0 : std::min(std::fabs(lo), std::fabs(hi));
    const double far = std::max(std::fabs(lo), std::fabs(hi));
    dmin2 += near * near;
    dmax2 += far * far;
    minMaxAbs = std::max(minMaxAbs, near);
  }
  if (!(minMaxAbs > degenerate) || !(dmin2 > 0)) return allDirections();
  const double dmin = std::sqrt(dmin2) * (1 - 1e-12), dmax = std::sqrt(dmax2) * (1 + 1e-12);
  Box3 r;
  for (int a = 0; a < 3; ++a) {
    const double lo = c[a].lo, hi = c[a].hi;
    double rl, rh;
    if (lo >= 0) { rl = lo / dmax; rh = hi / dmin; }
    else if (hi <= 0) { rl = lo / dmin; rh = hi / dmax; }
    else { rl = lo / dmin; rh = hi / dmin; }
    // unitOrZero() rounds: a few ulps of 1.
    r.lo[a] = float(std::max(-1.0, rl) - 1e-6);
    r.hi[a] = float(std::min(1.0, rh) + 1e-6);
  }
  return r;
}

}  // namespace

DisplacedPatch::DisplacedPatch(PatchPtr base, DisplacementPtr displacement, PatchPtr reference)
    : base_(std::move(base)), displacement_(std::move(displacement)), reference_(std::move(reference)) {
  if (!base_ || !displacement_) throw std::invalid_argument("DisplacedPatch needs a base patch and a displacement");
  if (!reference_) reference_ = base_;
  kind_ = std::string("displaced-") + base_->kind();
  bezierReference_ = dynamic_cast<const BezierPatch*>(reference_.get());
  bilinearReference_ = dynamic_cast<const BilinearPatch*>(reference_.get());
  if (const auto* bz = dynamic_cast<const BezierPatch*>(base_.get())) {
    bezierBase_ = bz;
    const auto& cp = bz->controlPoints();
    Box3 box;
    for (const Vec3& p : cp) box.extend(p);
    // The base's own threshold: rowFrames() takes a frame as analytic exactly where the base
    // did not nudge its normal.
    tinyNormal_ = bz->degenerateNormalThreshold();
    // P_u and P_v are Bézier patches themselves (hodographs): 3 x the control point
    // differences along u (3 x 4 points) and along v (4 x 3). Made once here: the border
    // bounds restrict them to hundreds of pieces per dicing.
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 3; ++i) hodographU_[j * 3 + i] = (cp[size_t(j) * 4 + i + 1] - cp[size_t(j) * 4 + i]) * 3.0f;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i) hodographV_[j * 4 + i] = (cp[size_t(j + 1) * 4 + i] - cp[size_t(j) * 4 + i]) * 3.0f;
    // evaluate()'s derivatives are differences of float blends of the control points taken
    // relative to the patch's anchor (bezier_patch.cpp): off by a few ulps of the anchored
    // control points' magnitude, at most the control box's extent (not of the derivative's,
    // and not of the distance from the origin).
    hodographCancellation_ = 2e-5f * maxComponent(box.extent()) + 1e-30f;
  } else if (const auto* bl = dynamic_cast<const BilinearPatch*>(base_.get())) {
    bilinearBase_ = bl;
    // A bilinear patch's corners come out of evaluate() exactly (lerp weights 1 and 0).
    corners_[0] = base_->evaluate(0, 0).p;
    corners_[1] = base_->evaluate(1, 0).p;
    corners_[2] = base_->evaluate(0, 1).p;
    corners_[3] = base_->evaluate(1, 1).p;
    Box3 box;
    for (const Vec3& p : corners_) box.extend(p);
    // BilinearPatch's own threshold: the same formula on the same (exact) corners.
    tinyNormal_ = detail::degenerateNormalThreshold(box.longestSide());
  } else {
    tinyNormal_ = detail::degenerateNormalThreshold(base_->bounds().longestSide());
  }
  bounds_ = boundsOver(0, 1, 0, 1);
  const Interval h = displacement_->range(reference_->bounds(), 0, 1, 0, 1);
  const float spread = std::min(2.0f, length(normalRangeOver(0, 1, 0, 1).extent()));
  // h changes along an iso curve by about meanSlopePerLength x its length on the reference.
  sizeBound_ = base_->sizeBound() + reference_->sizeBound() * displacement_->meanSlopePerLength() +
               displacement_->meanSlopePerParameter() + h.magnitude() * spread;
}

Box3 DisplacedPatch::normalRangeOver(float u0, float u1, float v0, float v1) const {
  if (u0 > u1) std::swap(u0, u1);
  if (v0 > v1) std::swap(v0, v1);
  u0 = std::clamp(u0, 0.0f, 1.0f); u1 = std::clamp(u1, 0.0f, 1.0f);
  v0 = std::clamp(v0, 0.0f, 1.0f); v1 = std::clamp(v1, 0.0f, 1.0f);
  if (bezierBase_) {
    // The hodographs restricted to the rectangle: their control boxes bound the derivatives
    // there -- also over a degenerate rectangle (a border piece, u0 == u1 or v0 == v1).
    return normalRangeFromHodographs(detail::restrictedHull<3, 4>(hodographU_, u0, u1, v0, v1),
                                     detail::restrictedHull<4, 3>(hodographV_, u0, u1, v0, v1), 0.0f);
  }
  if (bilinearBase_) {
    const Vec3 &p00 = corners_[0], &p10 = corners_[1], &p01 = corners_[2], &p11 = corners_[3];
    // P_u = lerp(p10 - p00, p11 - p01, v) and P_v = lerp(p01 - p00, p11 - p10, u): linear.
    Box3 du, dv, cb;
    for (float v : {v0, v1}) du.extend(detail::lerp(p10 - p00, p11 - p01, v));
    for (float u : {u0, u1}) dv.extend(detail::lerp(p01 - p00, p11 - p10, u));
    for (const Vec3& p : corners_) cb.extend(p);
    // Corner differences round by half an ulp of themselves (at most the extent), not of the
    // corners' distance from the origin.
    const float roundError = 1e-5f * maxComponent(cb.extent()) + 1e-30f;
    du = widenedBox(du, roundError);
    dv = widenedBox(dv, roundError);
    IVec3 n = cross(toIntervals(du), toIntervals(dv));
    const float evalError = 1e-5f * (length(vmax(vabs(du.lo), vabs(du.hi))) * length(vmax(vabs(dv.lo), vabs(dv.hi))));
    n = {widened(n.x, evalError), widened(n.y, evalError), widened(n.z, evalError)};
    return unitRange(n, 2.0 * tinyNormal_);
  }
  return allDirections();
}

Box3 DisplacedPatch::normalRangeFromHodographs(Box3 du, Box3 dv, float restrictionError) const {
  // Widened for the cancellation in evaluate()'s derivatives (see the constructor) and for
  // the float restriction, a few ulps of the derivative's magnitude (and what the caller's
  // restriction adds beyond that).
  const float cancellation = hodographCancellation_ + restrictionError;
  du = widenedBox(du, 1e-5f * du.magnitude() + cancellation);
  dv = widenedBox(dv, 1e-5f * dv.magnitude() + cancellation);
  IVec3 n = cross(toIntervals(du), toIntervals(dv));
  // evaluate() computes dP/du x dP/dv in float: off by a few ulps of |P_u| |P_v|.
  const float evalError = 1e-5f * (length(vmax(vabs(du.lo), vabs(du.hi))) * length(vmax(vabs(dv.lo), vabs(dv.hi))));
  n = {widened(n.x, evalError), widened(n.y, evalError), widened(n.z, evalError)};
  return unitRange(n, 2.0 * tinyNormal_);
}

Box3 DisplacedPatch::boundsOver(float u0, float u1, float v0, float v1) const {
  const Box3 b = base_->boundsOver(u0, u1, v0, v1);
  const Box3 rb = reference_ == base_ ? b : reference_->boundsOver(u0, u1, v0, v1);
  const Interval h = displacement_->range(rb, std::min(u0, u1), std::max(u0, u1), std::min(v0, v1), std::max(v0, v1));
  return displacedBox(b, normalRangeOver(u0, u1, v0, v1), h);
}

// P + N h over a piece whose base lies in b, unit normal in nr and height in h.
Box3 DisplacedPatch::displacedBox(const Box3& b, const Box3& nr, Interval h) {
  Box3 r;
  for (int a = 0; a < 3; ++a) {
    const Interval c = Interval(b.lo[a], b.hi[a]) + Interval(nr.lo[a], nr.hi[a]) * h;
    r.lo[a] = c.lo;
    r.hi[a] = c.hi;
  }
  // The base box already holds the base's diced vertices. P + N h rounds the product and the
  // sum (the sum's half ulp of the point is grownBy's own term); N's normalisation errs by a
  // few roundings of |h|, outside the normal range: gamma(8) |h| covers all three.
  return r.grownBy(gammaBound(8) * std::max(std::fabs(h.lo), std::fabs(h.hi)));
}

// boundsOver is displacedBox(b, nr, h), b the base's box: per axis [b] + [nr] [h], then grown
// by gamma(8) |h| and half an ulp of its magnitude. Every component of nr lies in
// [-1 - 10^-6, 1 + 10^-6] (unitRange) and |h| <= M = magnitudeBound(), so each coordinate
// moves from b's by at most M (1 + 2 10^-6) + gamma(8) M and a few roundings of
// (|b| + M) 2^-23; b grown by 1.001 M + (|b| + M) 2^-18 reaches beyond that. Float rounding
// of each step is monotone, so the computed box lies inside it bit for bit.
bool DisplacedPatch::coarseBoundsOverAt(int, float u0, float u1, float v0, float v1, Box3& out) const {
  const float m = displacement_->magnitudeBound();
  if (!std::isfinite(m)) return false;
  const Box3 b = base_->boundsOver(u0, u1, v0, v1);
  if (b.empty() || !isFinite(b.lo) || !isFinite(b.hi)) return false;
  const float grow = 1.001f * m + (b.magnitude() + m) * 0x1p-18f;
  if (!std::isfinite(grow)) return false;
  out = b.grownBy(grow);
  return isFinite(out.lo) && isFinite(out.hi);
}

// boundsOver's composition per piece, from the pieces of the base's (and reference's) border
// curve and of the hodographs' border curves, each restricted once and halved (Bézier bases;
// the others take the default, boundsOver per piece).
void DisplacedPatch::borderPieceBoundsAt(int, int e, int k, uint32_t j, int split, Box3* out) const {
  if (!bezierBase_) {
    Patch::borderPieceBoundsAt(0, e, k, j, split, out);
    return;
  }
  if (split <= 3) {  // Box3 arrays are initialised: a coarse radius's 8 pieces should not pay for 128
    Box3 reference[8], du[8], dv[8];
    displacedPieces(e, k, j, split, out, reference, du, dv);
  } else {
    Box3 reference[1u << kMaxPieceSplit], du[1u << kMaxPieceSplit], dv[1u << kMaxPieceSplit];
    displacedPieces(e, k, j, split, out, reference, du, dv);
  }
}

void DisplacedPatch::displacedPieces(int e, int k, uint32_t j, int split, Box3* out, Box3* reference, Box3* du,
                                     Box3* dv) const {
  const uint32_t pieces = 1u << split;
  base_->borderPieceBoundsAt(0, e, k, j, split, out);
  if (reference_ != base_) reference_->borderPieceBoundsAt(0, e, k, j, split, reference);
  const Box3* rb = reference_ == base_ ? out : reference;
  const float inv = 1.0f / float(1u << k);  // powers of two: every piece's ends are exact
  Vec3 curve[4];
  int n = detail::borderCurve<3, 4>(hodographU_, e, curve);
  detail::borderPieceHulls(curve, n, float(j) * inv, float(j + 1) * inv, split, du);
  n = detail::borderCurve<4, 3>(hodographV_, e, curve);
  detail::borderPieceHulls(curve, n, float(j) * inv, float(j + 1) * inv, split, dv);
  // The restriction's rounding is of the whole hodograph's magnitude, not the piece's.
  float magnitude = 0;
  for (int i = 0; i < 12; ++i)
    magnitude = std::max({magnitude, maxComponent(vabs(hodographU_[i])), maxComponent(vabs(hodographV_[i]))});
  const float restrictionError = gammaBound(detail::borderPieceRoundings(split)) * magnitude;
  const float pieceInv = 1.0f / float(1u << (k + split));
  for (uint32_t i = 0; i < pieces; ++i) {
    const float t0 = float(j * pieces + i) * pieceInv, t1 = float(j * pieces + i + 1) * pieceInv;
    const bool alongU = e == 0 || e == 2;
    const float fixed = e == 1 || e == 2 ? 1.0f : 0.0f;
    const Interval h = alongU ? displacement_->range(rb[i], t0, t1, fixed, fixed)
                              : displacement_->range(rb[i], fixed, fixed, t0, t1);
    out[i] = displacedBox(out[i], normalRangeFromHodographs(du[i], dv[i], restrictionError), h);
  }
}

// The step of the one-sided differences at u: forward, backward where it would leave the patch.
static float differencePoint(float u) {
  const float h = DisplacedPatch::kDifferenceStep;
  return u + h <= 1.0f ? u + h : u - h;
}

// The three points a vertex's difference frame is built from: at (u, v), (ua, v) and (u, va).
static void threePoints(const Patch& patch, float u, float v, float ua, float va, SurfacePoint out[3]) {
  out[0] = patch.evaluate(u, v);
  out[1] = patch.evaluate(ua, v);
  out[2] = patch.evaluate(u, va);
}

struct DisplacedPatch::RowContext {
  float v = 0, va = 0;
  BezierPatch::RowAtV row, refRow;  // valid for a Bézier base / reference
  // The Bézier base's row at va, for a vertex that falls back to differences; made on first use.
  BezierPatch::RowAtV rowA;
  bool haveRowA = false;
};

DisplacedPatch::RowContext DisplacedPatch::rowContext(float v) const {
  RowContext r;
  r.v = v;
  r.va = differencePoint(v);
  if (bezierBase_) r.row = bezierBase_->rowAt(v);
  if (bezierReference_ && reference_ != base_) r.refRow = bezierReference_->rowAt(v);
  return r;
}

// One-sided differences of the base at a fixed step (two extra base evaluations; central
// differences took four, for no visible gain in a shading normal).
DisplacedPatch::Frame DisplacedPatch::differenceFrame(RowContext& r, const SurfacePoint& c, float u) const {
  const float v = r.v, ua = differencePoint(u), va = r.va;
  SurfacePoint atUa, atVa;
  if (bezierBase_) {
    if (!r.haveRowA) {
      r.rowA = bezierBase_->rowAt(va);
      r.haveRowA = true;
    }
    atUa = bezierBase_->pointOnRow(r.row, ua, v);
    atVa = bezierBase_->pointOnRow(r.rowA, u, va);
  } else {
    atUa = base_->evaluate(ua, v);
    atVa = base_->evaluate(u, va);
  }
  Frame f;
  f.p = c.p;
  f.baseNormal = c.n;
  f.n = unitOrZero(c.n);
  const float iu = 1.0f / (ua - u), iv = 1.0f / (va - v);
  f.pu = (atUa.p - c.p) * iu;
  f.pv = (atVa.p - c.p) * iv;
  f.nu = (unitOrZero(atUa.n) - f.n) * iu;
  f.nv = (unitOrZero(atVa.n) - f.n) * iv;
  return f;
}

namespace {

// Finite (not NaN, not infinite), as a compare the vectoriser turns into one vector compare.
inline bool finite(float x) { return std::fabs(x) <= std::numeric_limits<float>::max(); }
// (`&` on ints, not `&&`: no branch in a loop the vectoriser should keep.)
inline bool finite(Vec3 a) { return bool(int(finite(a.x)) & int(finite(a.y)) & int(finite(a.z))); }

// One vertex's analytic frame from the base's derivatives: the raw normal N = P_u x P_v, the
// unit normal n (unitOrZero's operations: 1 / max component, then 1 / |N / m|, so no under-
// or overflow of |N|^2 at tiny or huge scales) and n's derivatives
//   n_u = (I - n n^T) (P_uu x P_v + P_u x P_uv) / |N|,  n_v likewise with P_uv, P_vv.
// valid: |N| above the base's degenerate-normal threshold (below it the base nudges its normal
// -- a pole -- and n_u is not this formula) and everything finite. Written without branches
// so that a loop over a grid row of it vectorises.
struct AnalyticFrame {
  Vec3 raw, n, nu, nv;
  bool valid;
};
inline AnalyticFrame analyticFrame(const SurfaceDerivatives& d, float tinyNormal) {
  AnalyticFrame f;
  f.raw = cross(d.pu, d.pv);
  const float m = maxComponent(vabs(f.raw));
  const float r = 1.0f / m;
  const Vec3 s = f.raw * r;
  const float k = 1.0f / std::sqrt(dot(s, s));
  f.n = s * k;
  const float inv = r * k;
  const Vec3 dnu = cross(d.puu, d.pv) + cross(d.pu, d.puv);
  const Vec3 dnv = cross(d.puv, d.pv) + cross(d.pu, d.pvv);
  f.nu = (dnu - f.n * dot(f.n, dnu)) * inv;
  f.nv = (dnv - f.n * dot(f.n, dnv)) * inv;
  f.valid = bool(int(m > tinyNormal) & int(finite(m)) & int(finite(f.nu)) & int(finite(f.nv)));
  return f;
}

// A chunk of a grid row's analytic frames as structure of arrays, so the loop that fills it
// vectorises (SSE: four vertices per instruction, the divisions and square roots included).
// Per lane the same IEEE operations as one vertex alone, so any count gives the same bits.
constexpr int kChunk = 64;
struct FrameChunk {
  enum { P = 0, Pu = 3, Pv = 6, Raw = 9, N = 12, Nu = 15, Nv = 18, Arrays = 21 };
  float a[Arrays][kChunk];
  bool valid[kChunk];
  void put(int k, int i, Vec3 v) { a[k][i] = v.x; a[k + 1][i] = v.y; a[k + 2][i] = v.z; }
  void putFrame(int i, const SurfaceDerivatives& d, const AnalyticFrame& f) {
    put(Pu, i, d.pu);
    put(Pv, i, d.pv);
    put(Raw, i, f.raw);
    put(N, i, f.n);
    put(Nu, i, f.nu);
    put(Nv, i, f.nv);
    valid[i] = f.valid;
  }
  Vec3 get(int k, int i) const { return {a[k][i], a[k + 1][i], a[k + 2][i]}; }
};

}  // namespace

RAYES_KERNEL_BODY void DisplacedPatch::rowFramesBody(RowContext& r, int count, const float* us, Frame* frames,
                                                     Vec3* at, Vec3* atU, Vec3* atV) const {
  const float v = r.v;
  const bool analytic = bezierBase_ || bilinearBase_;
  FrameChunk chunk;
  for (int c0 = 0; c0 < count; c0 += kChunk) {
    const int n = std::min(kChunk, count - c0);
    const float* u = us + c0;
    if (bezierBase_) {
      const BezierPatch& bz = *bezierBase_;
      const BezierPatch::RowAtV row = r.row;  // a local copy: the loop's stores cannot alias it
      for (int i = 0; i < n; ++i) {
        float b[4];
        detail::cubicBasis(u[i], b);
        const SurfaceDerivatives d = BezierPatch::derivativesOnRow(row, u[i]);
        chunk.put(FrameChunk::P, i, bz.interiorPointOnRow(row, b));
        chunk.putFrame(i, d, analyticFrame(d, tinyNormal_));
      }
    } else if (bilinearBase_) {
      for (int i = 0; i < n; ++i) {
        const SurfaceDerivatives d = bilinearBase_->derivatives(u[i], v);
        chunk.putFrame(i, d, analyticFrame(d, tinyNormal_));
      }
    }
    for (int i = 0; i < n; ++i) {
      const size_t k = size_t(c0 + i);
      Frame& f = frames[k];
      if (analytic && chunk.valid[i]) {
        // The base point: a Bézier interior point from the chunk, borders (canonical curves)
        // and bilinear points from the base itself.
        if (!bezierBase_) f.p = base_->evaluate(u[i], v).p;
        else if (BezierPatch::onBorder(u[i], v)) f.p = bezierBase_->positionOnRow(r.row, u[i], v);
        else f.p = chunk.get(FrameChunk::P, i);
        f.baseNormal = chunk.get(FrameChunk::Raw, i);  // the base's own normal there, bit for bit
        f.n = chunk.get(FrameChunk::N, i);
        f.pu = chunk.get(FrameChunk::Pu, i);
        f.pv = chunk.get(FrameChunk::Pv, i);
        f.nu = chunk.get(FrameChunk::Nu, i);
        f.nv = chunk.get(FrameChunk::Nv, i);
      } else {
        const SurfacePoint c = bezierBase_ ? bezierBase_->pointOnRow(r.row, u[i], v) : base_->evaluate(u[i], v);
        f = differenceFrame(r, c, u[i]);
      }
      referenceAt(r, u[i], f, at[k], atU[k], atV[k]);
    }
  }
}

void DisplacedPatch::rowFrames(RowContext& r, int count, const float* us, Frame* frames, Vec3* at, Vec3* atU,
                               Vec3* atV) const {
  if (vectorIsa() == VectorIsa::Avx2) rowFramesAvx2(r, count, us, frames, at, atU, atV);
  else rowFramesBaseline(r, count, us, frames, at, atU, atV);
}

void DisplacedPatch::rowFramesAvx2(RowContext& r, int count, const float* us, Frame* frames, Vec3* at, Vec3* atU,
                                   Vec3* atV) const {
  rowFramesBody(r, count, us, frames, at, atU, atV);
}

void DisplacedPatch::rowFramesBaseline(RowContext& r, int count, const float* us, Frame* frames, Vec3* at,
                                       Vec3* atU, Vec3* atV) const {
  rowFramesBody(r, count, us, frames, at, atU, atV);
}

void DisplacedPatch::referenceAt(const RowContext& r, float u, const Frame& f, Vec3& at, Vec3& atU, Vec3& atV) const {
  const float v = r.v;
  if (reference_ == base_) {
    at = f.p;
    atU = f.pu;
    atV = f.pv;
  } else if (bezierReference_) {
    at = bezierReference_->positionOnRow(r.refRow, u, v);
    const SurfaceDerivatives d = BezierPatch::derivativesOnRow(r.refRow, u);
    atU = d.pu;
    atV = d.pv;
  } else if (bilinearReference_) {
    at = reference_->evaluate(u, v).p;
    const SurfaceDerivatives d = bilinearReference_->derivatives(u, v);
    atU = d.pu;
    atV = d.pv;
  } else {
    SurfacePoint ref[3];
    const float ua = differencePoint(u);
    threePoints(*reference_, u, v, ua, r.va, ref);
    at = ref[0].p;
    atU = (ref[1].p - ref[0].p) * (1.0f / (ua - u));
    atV = (ref[2].p - ref[0].p) * (1.0f / (r.va - v));
  }
}

SurfacePoint DisplacedPatch::displaced(const Frame& f, const HeightSample& s) const {
  SurfacePoint out;
  out.p = f.p + f.n * s.h;
  const Vec3 du = f.pu + f.nu * s.h + f.n * s.hu, dv = f.pv + f.nv * s.h + f.n * s.hv;
  const Vec3 dn = rayes::cross(du, dv);
  out.n = (isFinite(dn) && maxComponent(vabs(dn)) > tinyNormal_) ? dn : f.baseNormal;
  return out;
}

SurfacePoint DisplacedPatch::evaluate(float u, float v) const {
  RowContext r = rowContext(v);
  Frame f;
  Vec3 at, atU, atV;
  rowFrames(r, 1, &u, &f, &at, &atU, &atV);
  return displaced(f, displacement_->sample(at, atU, atV, u, v));
}

// One evaluate() per vertex, bit for bit, a grid row at a time: the row's base frames first,
// then the displacement over the whole row (Displacement::sampleRow: the noise vectorises
// across it), then the displaced points. A Bézier base's (and reference's) rows are computed
// once per grid row rather than once per point.
void DisplacedPatch::dice(int level, Vec3* positions, Vec3* normals) const {
  const int n = 1 << level;
  const float fn = float(n);
  std::vector<Frame> frames(size_t(n) + 1);
  std::vector<Vec3> at(size_t(n) + 1), atU(size_t(n) + 1), atV(size_t(n) + 1);
  std::vector<float> us(size_t(n) + 1);
  std::vector<HeightSample> heights(size_t(n) + 1);
  for (int i = 0; i <= n; ++i) us[size_t(i)] = float(i) / fn;
  for (int j = 0; j <= n; ++j) {
    const float v = float(j) / fn;
    RowContext r = rowContext(v);
    rowFrames(r, n + 1, us.data(), frames.data(), at.data(), atU.data(), atV.data());
    displacement_->sampleRow(n + 1, at.data(), atU.data(), atV.data(), us.data(), v, heights.data());
    for (int i = 0; i <= n; ++i) {
      const SurfacePoint sp = displaced(frames[size_t(i)], heights[size_t(i)]);
      positions[size_t(j) * (n + 1) + i] = sp.p;
      normals[size_t(j) * (n + 1) + i] = sp.n;
    }
  }
}

}  // namespace rayes
