// Fractal value noise and its interval extension (see geometry/displacement.h).
//
// Why value noise rather than gradient noise: its value at a point is a convex combination of
// lattice values with monotone weights, which gives an interval extension that is both
// provably conservative and tight (it shrinks to the point value as the box shrinks, and is
// exact per cell at the box's corners); gradient noise's range within a cell has no such
// closed form and needs Lipschitz bounds that stay loose.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include "core/rng.h"
#include "core/vector_isa.h"
#include "geometry/displacement.h"

namespace rayes {

namespace {

// Lattice coordinates are clamped to +-2^30 so that the cell index always fits an int64 and
// the clamp, a monotone function, keeps the box image conservative.
constexpr float kCoordinateLimit = 1073741824.0f;

// Selects rather than std::clamp's branches, so that the loops over a row vectorise (with
// -fno-trapping-math, CMakeLists.txt).
inline float clampCoordinate(float x) {
  x = x == x ? x : 0.0f;  // NaN (never from a finite base surface)
  x = x > -kCoordinateLimit ? x : -kCoordinateLimit;
  return x < kCoordinateLimit ? x : kCoordinateLimit;
}

// A coordinate p of an octave of frequency f whose lattice is shifted by `shift`.
inline float octaveAxis(float p, float f, float shift) { return clampCoordinate(p * f + shift); }

inline float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
inline float fadeDerivative(float t) { return 30.0f * t * t * (t * (t - 2.0f) + 1.0f); }
inline double fadeExact(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }
inline float lerp1(float a, float b, float s) { return a + (b - a) * s; }

// The float fade differs from the exact one by a few ulps of 1 (about 2e-6 at worst for the
// Horner form above on [0, 1]); the interval weights are widened by this much.
constexpr double kFadeError = 1e-5;
// A chain of three float lerps of values in [-1, 1] with weights in [0, 1] errs by less than
// 1e-6 from the exact trilinear blend of the same weights.
constexpr float kLerpError = 2e-6f;

struct D {
  double lo, hi;
};

// Range of (1 - s) a + s b over a in A, b in B, s in S (S within [0, 1]): both weights are
// non-negative, so the extremes take A's and B's matching ends, and are linear in s.
inline D lerpRange(D a, D b, D s) {
  const double l0 = a.lo + (b.lo - a.lo) * s.lo, l1 = a.lo + (b.lo - a.lo) * s.hi;
  const double h0 = a.hi + (b.hi - a.hi) * s.lo, h1 = a.hi + (b.hi - a.hi) * s.hi;
  return {std::min(l0, l1), std::max(h0, h1)};
}

// The last lattice cell a thread asked for, per noise seed.
struct CellCorners {
  uint64_t seed = 0;
  int64_t ix = 0, iy = 0, iz = std::numeric_limits<int64_t>::min();  // no cell yet
  float c[2][2][2] = {};  // c[dz][dy][dx]
};

// The lattice value at corner k = dz * 4 + dy * 2 + dx of cell (ix, iy, iz).
inline float cornerValue(const ValueNoise& noise, int64_t ix, int64_t iy, int64_t iz, int k) {
  return noise.lattice(ix + (k & 1), iy + ((k >> 1) & 1), iz + (k >> 2));
}

// The lattice values at the corners of cell (ix, iy, iz). Neighbouring vertices of a dicing,
// and neighbouring border pieces, mostly fall in the cell of the one before (a lattice cell of
// the low octaves spans many micropolygons), so each thread keeps the last cell per seed:
// hashing the eight corners was the larger half of eval(). The values are a pure function of
// (seed, cell), so the cache never changes a result. Direct-mapped by seed: the octaves of one
// displacement (and the displacements diced one after another on a thread) have independent
// random seeds, so they rarely share a slot, and a shared slot only costs hashing again.
const float (&cellCorners(const ValueNoise& noise, int64_t ix, int64_t iy, int64_t iz))[2][2][2] {
  constexpr size_t kSlots = 32;
  thread_local CellCorners cells[kSlots];
  const uint64_t seed = noise.seed();
  CellCorners& cell = cells[(seed ^ (seed >> 32)) % kSlots];
  if (!(cell.seed == seed && cell.ix == ix && cell.iy == iy && cell.iz == iz)) {
    for (int dz = 0; dz < 2; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) cell.c[dz][dy][dx] = cornerValue(noise, ix, iy, iz, dz * 4 + dy * 2 + dx);
    cell.seed = seed;
    cell.ix = ix;
    cell.iy = iy;
    cell.iz = iz;
  }
  return cell.c;
}

// Where x lies on the lattice: its cell floor(x) and its position t = x - floor(x) in [0, 1].
// Two spellings of one function, for the two kernels (core/vector_isa.h), because GCC vectorises
// each only on its own target: SSE2 has no vector floor, so the baseline truncates and steps
// down below negative non-integers; AVX2 has one (vroundps), but there GCC turns the truncation
// back into a scalar trunc with a branch, while std::floor vectorises. For every x within the
// coordinate limit both give std::floor's float (the truncation is exact for |x| <= 2^30), -0.0
// included (the + 0.0f turns t's -0.0 there into the +0.0 of -0.0 - -0.0), so the same bits:
// ValueNoise.RowIsTheSameOnEveryInstructionSet.
template <bool kVectorFloor>
inline void cellOf(float x, int32_t& cell, float& t) {
  x = clampCoordinate(x);
  float f;
  if constexpr (kVectorFloor) {
    f = std::floor(x);
    cell = int32_t(f);                        // exact: |f| <= 2^30
  } else {
    const int32_t i = int32_t(x);
    const float fi = float(i);                // exact: |x| <= 2^30
    const bool below = fi > x;                // only when x is not an integer
    f = below ? fi - 1.0f : fi;               // exact
    cell = below ? i - 1 : i;
  }
  const float d = (x - f) + 0.0f;
  t = d < 1.0f ? (d > 0.0f ? d : 0.0f) : 1.0f;  // std::clamp(d, 0, 1) for the d here (never NaN)
}

}  // namespace

float ValueNoise::lattice(int64_t ix, int64_t iy, int64_t iz) const {
  const uint64_t h = mix64(seed_ ^ (uint64_t(ix) * 0x9E3779B97F4A7C15ull) ^
                           (uint64_t(iy) * 0xC2B2AE3D27D4EB4Full) ^ (uint64_t(iz) * 0x165667B19E3779F9ull));
  return float(h >> 40) * (1.0f / 8388608.0f) - 1.0f;  // exact, in [-1, 1)
}

float ValueNoise::eval(float x, float y, float z, Vec3* gradient) const {
  float value, gx, gy, gz;
  evalRow(1, &x, &y, &z, &value, &gx, &gy, &gz);
  if (gradient) *gradient = {gx, gy, gz};
  return value;
}

namespace {

// ValueNoise::evalRow's body, compiled once per instruction set (core/vector_isa.h).
// Three passes over chunks of a row: the cells and fade weights (vectorised), the corners'
// lattice values copied per point from the cell they share with their neighbours (scalar: a
// cell spans many points of a row at all but the finest octaves), and the trilinear blend
// and its gradient (vectorised). Per point the same float operations as a point at a time,
// in the same order, so the row's values are eval()'s bit for bit -- eval() is this for n = 1.
template <bool kVectorFloor>
RAYES_KERNEL_BODY void evalRowBody(const ValueNoise& noise, int count, const float* xs, const float* ys,
                                   const float* zs, float* value, float* gx, float* gy, float* gz) {
  constexpr int kChunk = 64;
  alignas(16) float tx[kChunk], ty[kChunk], tz[kChunk];
  alignas(16) int32_t cx[kChunk], cy[kChunk], cz[kChunk];
  alignas(16) float c[8][kChunk];  // c[dz * 4 + dy * 2 + dx][point]
  for (int start = 0; start < count; start += kChunk) {
    const int m = std::min(kChunk, count - start);
    for (int i = 0; i < m; ++i) {
      cellOf<kVectorFloor>(xs[start + i], cx[i], tx[i]);
      cellOf<kVectorFloor>(ys[start + i], cy[i], ty[i]);
      cellOf<kVectorFloor>(zs[start + i], cz[i], tz[i]);
    }
    // The corners of the current cell, c[dz * 4 + dy * 2 + dx]. A step to a cell that shares
    // a face with it (the common step along a row) keeps that face's four values and hashes
    // the other four; the thread's cell cache is asked only at a chunk's start, where the row
    // before began in the same cell.
    float cur[8];
    int32_t lastX = cx[0], lastY = cy[0], lastZ = cz[0];
    {
      const float* first = &cellCorners(noise, lastX, lastY, lastZ)[0][0][0];
      std::copy(first, first + 8, cur);
    }
    for (int i = 0; i < m; ++i) {
      // In int64: cells span +-2^30, so a step can exceed the int32 range.
      const int64_t dx = int64_t(cx[i]) - lastX, dy = int64_t(cy[i]) - lastY, dz = int64_t(cz[i]) - lastZ;
      if (dx | dy | dz) {
        const int axis = (dy == 0 && dz == 0) ? 0 : (dx == 0 && dz == 0) ? 1 : (dx == 0 && dy == 0) ? 2 : -1;
        const int64_t step = axis == 0 ? dx : axis == 1 ? dy : axis == 2 ? dz : 0;
        int fresh = 0xFF;  // the corners to hash, one bit per corner index
        if (step == 1 || step == -1) {
          // The new cell's corners on the shared face come from the old cell's other side.
          const int bit = 1 << axis;  // the corner index bit of that axis
          fresh = 0;
          for (int k = 0; k < 8; ++k) {
            if (((k & bit) != 0) == (step < 0)) cur[k] = cur[k ^ bit];
            else fresh |= 1 << k;
          }
        }
        for (int k = 0; k < 8; ++k)
          if (fresh & (1 << k)) cur[k] = cornerValue(noise, cx[i], cy[i], cz[i], k);
        lastX = cx[i];
        lastY = cy[i];
        lastZ = cz[i];
      }
      for (int k = 0; k < 8; ++k) c[k][i] = cur[k];
    }
    float *out = value + start, *dx = gx + start, *dy = gy + start, *dz = gz + start;
    for (int i = 0; i < m; ++i) {
      const float sx = std::clamp(fade(tx[i]), 0.0f, 1.0f), sy = std::clamp(fade(ty[i]), 0.0f, 1.0f),
                  sz = std::clamp(fade(tz[i]), 0.0f, 1.0f);
      const float a00 = lerp1(c[0][i], c[1][i], sx), a10 = lerp1(c[2][i], c[3][i], sx);
      const float a01 = lerp1(c[4][i], c[5][i], sx), a11 = lerp1(c[6][i], c[7][i], sx);
      const float b0 = lerp1(a00, a10, sy), b1 = lerp1(a01, a11, sy);
      out[i] = lerp1(b0, b1, sz);
      const float e00 = c[1][i] - c[0][i], e10 = c[3][i] - c[2][i];
      const float e01 = c[5][i] - c[4][i], e11 = c[7][i] - c[6][i];
      dx[i] = fadeDerivative(tx[i]) * lerp1(lerp1(e00, e10, sy), lerp1(e01, e11, sy), sz);
      dy[i] = fadeDerivative(ty[i]) * lerp1(a10 - a00, a11 - a01, sz);
      dz[i] = fadeDerivative(tz[i]) * (b1 - b0);
    }
  }
}

RAYES_TARGET_AVX2 void evalRowAvx2(const ValueNoise& noise, int count, const float* xs, const float* ys,
                                   const float* zs, float* value, float* gx, float* gy, float* gz) {
  evalRowBody<true>(noise, count, xs, ys, zs, value, gx, gy, gz);
}

void evalRowBaseline(const ValueNoise& noise, int count, const float* xs, const float* ys, const float* zs,
                     float* value, float* gx, float* gy, float* gz) {
  evalRowBody<false>(noise, count, xs, ys, zs, value, gx, gy, gz);
}

}  // namespace

void ValueNoise::evalRow(int count, const float* xs, const float* ys, const float* zs, float* value, float* gx,
                         float* gy, float* gz) const {
  if (vectorIsa() == VectorIsa::Avx2) evalRowAvx2(*this, count, xs, ys, zs, value, gx, gy, gz);
  else evalRowBaseline(*this, count, xs, ys, zs, value, gx, gy, gz);
}

Interval ValueNoise::range(Vec3 lo, Vec3 hi) const {
  const Interval everything = widened({-1.0f, 1.0f}, kLerpError);
  float cl[3], ch[3];
  double cells = 1;
  for (int a = 0; a < 3; ++a) {
    const float l = clampCoordinate(lo[a]), h = clampCoordinate(hi[a]);
    if (!(l <= h)) return everything;
    cl[a] = std::floor(l);
    ch[a] = std::floor(h);
    cells *= double(ch[a]) - double(cl[a]) + 1.0;
  }
  if (cells > kMaxCells) return everything;
  // Per axis and cell: the interval of the fade weight over the box's slice of the cell.
  // t = x - floor(x) is computed exactly as eval() does, at the slice's ends; for fixed
  // floor(x) it is a monotone function of x, so every t of the slice lies between them.
  auto weights = [&](int a, int64_t cell) -> D {
    const float l = clampCoordinate(lo[a]), h = clampCoordinate(hi[a]);
    const float t0 = cell == int64_t(cl[a]) ? std::clamp(l - cl[a], 0.0f, 1.0f) : 0.0f;
    const float t1 = cell == int64_t(ch[a]) ? std::clamp(h - ch[a], 0.0f, 1.0f) : 1.0f;
    return {std::max(0.0, fadeExact(t0) - kFadeError), std::min(1.0, fadeExact(t1) + kFadeError)};
  };
  // The weights of each axis's cells and the lattice values at the cells' corners, computed
  // once (a corner is shared by up to 8 cells; a weight by every cell of its slab).
  int count[3];
  D w[3][kMaxCells];
  for (int a = 0; a < 3; ++a) {
    count[a] = int(int64_t(ch[a]) - int64_t(cl[a]) + 1);
    for (int c = 0; c < count[a]; ++c) w[a][c] = weights(a, int64_t(cl[a]) + c);
  }
  const int sx = count[0] + 1, sy = count[1] + 1;
  float corner[8 * kMaxCells];  // (count+1) per axis: at most 2 * 2 * (kMaxCells + 1) <= 8 kMaxCells
  if (count[0] == 1 && count[1] == 1 && count[2] == 1) {
    // Most boxes (a border piece, a small dicing's subtree) lie in one cell: eval()'s cache.
    const float (&c)[2][2][2] = cellCorners(*this, int64_t(cl[0]), int64_t(cl[1]), int64_t(cl[2]));
    for (int k = 0; k < 8; ++k) corner[k] = c[k >> 2][(k >> 1) & 1][k & 1];
  } else {
    for (int z = 0; z <= count[2]; ++z)
      for (int y = 0; y < sy; ++y)
        for (int x = 0; x < sx; ++x)
          corner[(z * sy + y) * sx + x] = lattice(int64_t(cl[0]) + x, int64_t(cl[1]) + y, int64_t(cl[2]) + z);
  }
  // The per-cell blend of the trilinear interpolation, done axis by axis: a lerp along x of two
  // corners is shared by the (up to) four cells around that lattice edge, a lerp along y by
  // the two cells on either side in z, so each is computed once (about 3 lerps per cell instead
  // of 7 for large boxes). The same operations on the same values as per cell: the same bits.
  const int nx = count[0], ny = count[1], nz = count[2];
  D alongX[4 * kMaxCells];  // [z in 0..nz][y in 0..ny][x < nx]: nx (ny + 1) (nz + 1) <= 4 kMaxCells
  for (int z = 0; z <= nz; ++z)
    for (int y = 0; y <= ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const double a = corner[(z * sy + y) * sx + x], b = corner[(z * sy + y) * sx + x + 1];
        alongX[(z * (ny + 1) + y) * nx + x] = lerpRange({a, a}, {b, b}, w[0][x]);
      }
  D alongY[2 * kMaxCells];  // [z in 0..nz][y < ny][x < nx]: nx ny (nz + 1) <= 2 kMaxCells
  for (int z = 0; z <= nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        alongY[(z * ny + y) * nx + x] = lerpRange(alongX[(z * (ny + 1) + y) * nx + x],
                                                  alongX[(z * (ny + 1) + y + 1) * nx + x], w[1][y]);
  double rlo = 2, rhi = -2;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const D r = lerpRange(alongY[(z * ny + y) * nx + x], alongY[((z + 1) * ny + y) * nx + x], w[2][z]);
        rlo = std::min(rlo, r.lo);
        rhi = std::max(rhi, r.hi);
      }
  return intersect(widened({float(rlo), float(rhi)}, kLerpError), everything);
}

NoiseDisplacement::NoiseDisplacement(const NoiseParams& p) : params_(p) {
  if (!(p.frequency > 0) || !std::isfinite(p.frequency)) throw std::invalid_argument("noise frequency must be > 0");
  if (p.octaves < 1 || p.octaves > 16) throw std::invalid_argument("noise octaves must be in 1..16");
  if (!(p.gain > 0 && p.gain <= 1)) throw std::invalid_argument("noise gain must be in (0, 1]");
  if (!(p.lacunarity >= 1 && p.lacunarity <= 4)) throw std::invalid_argument("noise lacunarity must be in [1, 4]");
  if (!std::isfinite(p.amplitude) || !std::isfinite(p.offset)) throw std::invalid_argument("noise amplitude and offset must be finite");
  float f = p.frequency, w = 1, sum = 0;
  double slope = 0;
  for (int k = 0; k < p.octaves; ++k) {
    octaves_.emplace_back(mix64(uint64_t(p.seed) * 0x100000001B3ull + uint64_t(k) + 1));
    freq_.push_back(f);
    weight_.push_back(w);
    const uint64_t h = mix64(mix64(p.seed) ^ (uint64_t(k) << 32 | 0xA5A5u));
    // A per-octave offset of the lattice (in [0, 64) cells) so that octaves do not all have a
    // lattice point at the origin.
    shift_.push_back({float(h & 0xFFFF) / 1024.0f, float((h >> 16) & 0xFFFF) / 1024.0f,
                      float((h >> 32) & 0xFFFF) / 1024.0f});
    sum += w;
    // Mean |d n / d x| of value noise per lattice unit: E|fade'| (= 1) x E|b - a| (= 2/3 for
    // uniform lattice values).
    slope += double(w) * f * (2.0 / 3.0);
    f *= p.lacunarity;
    w *= p.gain;
  }
  invWeightSum_ = 1.0f / sum;
  meanSlope_ = float(std::fabs(double(p.amplitude)) * slope / sum);
}

Vec3 NoiseDisplacement::octaveCoordinate(int k, Vec3 p) const {
  const float f = freq_[size_t(k)];
  const Vec3 s = shift_[size_t(k)];
  return {octaveAxis(p.x, f, s.x), octaveAxis(p.y, f, s.y), octaveAxis(p.z, f, s.z)};
}

HeightSample NoiseDisplacement::sample(Vec3 p, Vec3 pu, Vec3 pv, float u, float v) const {
  HeightSample s;
  sampleRow(1, &p, &pu, &pv, &u, v, &s);
  return s;
}

// Octave by octave over chunks of the row (per point the octaves' sum in the same order as a
// point at a time, so the same bits), so that ValueNoise::evalRow sees a row.
RAYES_KERNEL_BODY void NoiseDisplacement::sampleRowBody(int count, const Vec3* p, const Vec3* pu, const Vec3* pv,
                                                        HeightSample* out) const {
  constexpr int kChunk = 64;
  alignas(16) float x[kChunk], y[kChunk], z[kChunk], n[kChunk], gx[kChunk], gy[kChunk], gz[kChunk];
  alignas(16) float acc[kChunk], ax[kChunk], ay[kChunk], az[kChunk], px[kChunk], py[kChunk], pz[kChunk];
  for (int start = 0; start < count; start += kChunk) {
    const int m = std::min(kChunk, count - start);
    std::fill(acc, acc + m, 0.0f);
    std::fill(ax, ax + m, 0.0f);
    std::fill(ay, ay + m, 0.0f);
    std::fill(az, az + m, 0.0f);
    // The points as structure of arrays once, so that each octave's coordinates (octaveCoordinate
    // per axis) vectorise.
    for (int i = 0; i < m; ++i) {
      px[i] = p[start + i].x;
      py[i] = p[start + i].y;
      pz[i] = p[start + i].z;
    }
    for (int k = 0; k < params_.octaves; ++k) {
      const float f = freq_[size_t(k)];
      const Vec3 sh = shift_[size_t(k)];
      for (int i = 0; i < m; ++i) {
        x[i] = octaveAxis(px[i], f, sh.x);
        y[i] = octaveAxis(py[i], f, sh.y);
        z[i] = octaveAxis(pz[i], f, sh.z);
      }
      octaves_[size_t(k)].evalRow(m, x, y, z, n, gx, gy, gz);
      const float w = weight_[size_t(k)], wf = w * freq_[size_t(k)];
      for (int i = 0; i < m; ++i) {
        float ni = n[i], sign = 1.0f;
        if (params_.ridged) {
          sign = ni < 0.0f ? 1.0f : -1.0f;  // exact: the gradient of 1 - |n|
          ni = 1.0f - std::fabs(ni);
        }
        acc[i] += w * ni;
        ax[i] += (sign * gx[i]) * wf;
        ay[i] += (sign * gy[i]) * wf;
        az[i] += (sign * gz[i]) * wf;
      }
    }
    const float scale = params_.amplitude * invWeightSum_;
    for (int i = 0; i < m; ++i) {
      HeightSample& s = out[start + i];
      s.h = params_.offset + params_.amplitude * (acc[i] * invWeightSum_);
      const Vec3 gp = Vec3{ax[i], ay[i], az[i]} * scale;
      s.hu = dot(gp, pu[start + i]);
      s.hv = dot(gp, pv[start + i]);
    }
  }
}

void NoiseDisplacement::sampleRowAvx2(int count, const Vec3* p, const Vec3* pu, const Vec3* pv,
                                      HeightSample* out) const {
  sampleRowBody(count, p, pu, pv, out);
}

void NoiseDisplacement::sampleRowBaseline(int count, const Vec3* p, const Vec3* pu, const Vec3* pv,
                                          HeightSample* out) const {
  sampleRowBody(count, p, pu, pv, out);
}

void NoiseDisplacement::sampleRow(int count, const Vec3* p, const Vec3* pu, const Vec3* pv, const float*, float,
                                  HeightSample* out) const {
  if (vectorIsa() == VectorIsa::Avx2) sampleRowAvx2(count, p, pu, pv, out);
  else sampleRowBaseline(count, p, pu, pv, out);
}

Interval NoiseDisplacement::fractalRange(const Box3& b) const {
  double lo = 0, hi = 0;
  for (int k = 0; k < params_.octaves; ++k) {
    // p * f + s is monotone in p (f > 0), so the box's corners map to the image box's corners.
    Interval r = octaves_[size_t(k)].range(octaveCoordinate(k, b.lo), octaveCoordinate(k, b.hi));
    if (params_.ridged) r = widened(Interval(1.0f) - abs(r), 1e-7f);
    lo += double(weight_[size_t(k)]) * r.lo;
    hi += double(weight_[size_t(k)]) * r.hi;
  }
  // The float sum of sample() rounds once per octave and once for the normalisation: a few
  // ulps of 1 in all; 1e-6 covers 16 octaves with a wide margin.
  return widened({float(lo * invWeightSum_), float(hi * invWeightSum_)}, 1e-6f);
}

float NoiseDisplacement::magnitudeBound() const {
  // The widenings listed in the header add at most 3 10^-5 of |offset| + |amplitude| (and a few
  // roundings of it): 10^-3 holds them with room.
  return (std::fabs(params_.offset) + std::fabs(params_.amplitude)) * 1.001f;
}

Interval NoiseDisplacement::range(const Box3& pBox, float, float, float, float) const {
  const float amp = params_.amplitude, off = params_.offset;
  if (pBox.empty() || !isFinite(pBox.lo) || !isFinite(pBox.hi)) {
    const Interval f = params_.ridged ? Interval(0.0f, 1.0f) : Interval(-1.0f, 1.0f);
    return widened(Interval(off) + Interval(amp) * widened(f, 1e-5f), 1e-5f * (std::fabs(amp) + std::fabs(off)));
  }
  const Interval h = Interval(off) + Interval(amp) * fractalRange(pBox);
  // offset + amplitude * x rounds twice in sample().
  return widened(h, 1e-6f * (std::fabs(amp) + std::fabs(off)));
}

}  // namespace rayes
