// Interval arithmetic on value noise and on the fractal displacement (geometry/displacement.h):
// every sampled point value lies in the interval of its box, and the interval is not absurdly
// loose (the mean ratio of interval width to the sampled spread is printed and bounded).
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <cstring>
#include <thread>
#include <vector>
#include "core/interval.h"
#include "core/vector_isa.h"
#include "geometry/displacement.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

using test::Random;

TEST(Interval, OperationsContainEveryResult) {
  Random rng(11);
  for (int k = 0; k < 20000; ++k) {
    const float a0 = rng.uniform(-10, 10), a1 = a0 + rng.uniform(0, 5);
    const float b0 = rng.uniform(-10, 10), b1 = b0 + rng.uniform(0, 5);
    const Interval a{a0, a1}, b{b0, b1};
    const float x = rng.uniform(a0, a1), y = rng.uniform(b0, b1);
    EXPECT_TRUE((a + b).contains(x + y));
    EXPECT_TRUE((a - b).contains(x - y));
    EXPECT_TRUE((a * b).contains(x * y));
    EXPECT_TRUE(abs(a).contains(std::fabs(x)));
  }
  // 0 x inf is everything, not NaN.
  const Interval inf{0.0f, std::numeric_limits<float>::infinity()};
  const Interval z{-1.0f, 0.0f};
  EXPECT_TRUE((inf * z).contains(-1e30f));
  EXPECT_FALSE((inf * z).empty());
}

// A random box in lattice units: sizes from 1e-4 to 20 cells, anywhere from -1e4 to 1e4.
void randomBox(Random& rng, Vec3& lo, Vec3& hi) {
  const float scale = std::pow(10.0f, rng.uniform(-4.0f, 1.3f));
  const float reach = std::pow(10.0f, rng.uniform(0.0f, 4.0f));
  for (int a = 0; a < 3; ++a) {
    lo[a] = rng.uniform(-reach, reach);
    hi[a] = lo[a] + scale * rng.uniform(0.0f, 1.0f);
  }
}

Vec3 pointIn(Random& rng, Vec3 lo, Vec3 hi) {
  Vec3 p;
  for (int a = 0; a < 3; ++a) {
    // A quarter of the coordinates exactly on the box's faces (where the floor changes).
    const int pick = rng.below(8);
    p[a] = pick == 0 ? lo[a] : pick == 1 ? hi[a] : std::min(hi[a], lo[a] + (hi[a] - lo[a]) * rng.uniform());
  }
  return p;
}

TEST(ValueNoise, IntervalContainsEverySampledValue) {
  const ValueNoise noise(42);
  Random rng(7);
  int outside = 0;
  double ratioSum = 0;
  int ratioCount = 0;
  constexpr int kBoxes = 400, kPoints = 5000;  // 2e6 points
  for (int b = 0; b < kBoxes; ++b) {
    Vec3 lo, hi;
    randomBox(rng, lo, hi);
    const Interval r = noise.range(lo, hi);
    float mn = 2, mx = -2;
    for (int k = 0; k < kPoints; ++k) {
      const Vec3 p = pointIn(rng, lo, hi);
      const float n = noise.eval(p.x, p.y, p.z, nullptr);
      mn = std::min(mn, n);
      mx = std::max(mx, n);
      if (!r.contains(n)) {
        if (++outside < 5) ADD_FAILURE() << "noise " << n << " outside [" << r.lo << ", " << r.hi << "]";
      }
    }
    if (mx - mn > 1e-3f) {
      ratioSum += double(r.width()) / double(mx - mn);
      ++ratioCount;
    }
  }
  EXPECT_EQ(outside, 0);
  const double meanRatio = ratioSum / ratioCount;
  std::printf("value noise: mean interval width / sampled spread = %.3f over %d boxes\n", meanRatio, ratioCount);
  EXPECT_LT(meanRatio, 2.0);  // the interval is a close bound, not [-1, 1]
}

TEST(ValueNoise, TinyBoxesGiveTinyIntervals) {
  const ValueNoise noise(3);
  Random rng(5);
  for (int k = 0; k < 1000; ++k) {
    const Vec3 lo{rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-50, 50)};
    const Vec3 hi = lo + Vec3{1e-4f, 1e-4f, 1e-4f};
    const Interval r = noise.range(lo, hi);
    EXPECT_LT(r.width(), 3e-3f);  // gradient <= 3.75 per axis: 3 x 3.75e-4 + rounding margins
    EXPECT_TRUE(r.contains(noise.eval(lo.x, lo.y, lo.z, nullptr)));
  }
}

// Over more than kMaxCells lattice cells range() gives [-1, 1] (widened) instead of visiting
// every cell: a coarse border segment or a whole patch spans hundreds of cells of a high octave,
// and visiting them was most of the cost of the border bounds. The cap costs little because the
// noise over a box that large already comes near both ends: with integer corners it holds the
// lattice values at its P = (nx + 1)(ny + 1)(nz + 1) > kMaxCells lattice points, i.i.d. uniform
// in [-1, 1), and misses 1 by more than 0.1 at one end with probability at most 2 x 0.95^P
// (< 37 % at the cap). The boxes below may be that loose no more often than the sum of those
// bounds plus four of its standard deviations. A cap of a few cells would fail (2 x 0.95^8 > 1).
TEST(ValueNoise, BoxesOverTheCellCapAreCloseToEverything) {
  const ValueNoise noise(17);
  Random rng(23);
  const int boxes = 1000;
  int loose = 0;
  double expected = 0;
  for (int k = 0; k < boxes; ++k) {
    const int ny = 1 + int(rng.below(3)), nz = 1 + int(rng.below(3));
    const int nx = ValueNoise::kMaxCells / ((ny + 1) * (nz + 1)) + int(rng.below(8));  // cells: (nx+1)(ny+1)(nz+1)
    const int64_t x0 = int64_t(std::floor(rng.uniform(-1000, 1000))), y0 = int64_t(std::floor(rng.uniform(-1000, 1000))),
                  z0 = int64_t(std::floor(rng.uniform(-1000, 1000)));
    const Vec3 lo{float(x0), float(y0), float(z0)}, hi = lo + Vec3{float(nx), float(ny), float(nz)};
    const int points = (nx + 1) * (ny + 1) * (nz + 1);
    if (points <= ValueNoise::kMaxCells) continue;
    expected += std::min(1.0, 2.0 * std::pow(0.95, points));
    const Interval capped = noise.range(lo, hi);
    EXPECT_LE(capped.lo, -1.0f);
    EXPECT_GE(capped.hi, 1.0f);
    float vmin = 1, vmax = -1;  // noise values the box holds: eval() at a lattice point is its value
    for (int64_t x = 0; x <= nx; ++x)
      for (int64_t y = 0; y <= ny; ++y)
        for (int64_t z = 0; z <= nz; ++z) {
          const float v = noise.lattice(x0 + x, y0 + y, z0 + z);
          vmin = std::min(vmin, v);
          vmax = std::max(vmax, v);
        }
    EXPECT_EQ(noise.eval(lo.x, lo.y, lo.z, nullptr), noise.lattice(x0, y0, z0));
    if (vmin > -0.9f || vmax < 0.9f) ++loose;
  }
  std::printf("boxes over the cell cap whose noise misses +-1 by more than 0.1: %d of %d (bound %.1f)\n", loose,
              boxes, expected);
  EXPECT_LE(loose, expected + 4.0 * std::sqrt(expected));
}

// eval() and range() keep each thread's last lattice cell per seed; what they return must not
// depend on what the thread evaluated before. Seeds that are multiples of 2^5 share one cache
// slot, points are clustered in a few cells so that hits, misses and evictions all happen, and
// the same queries in a shuffled order on another thread give the same bits.
TEST(ValueNoise, ValuesDoNotDependOnWhatWasEvaluatedBefore) {
  std::vector<ValueNoise> noises;
  for (uint64_t k = 0; k < 40; ++k) noises.emplace_back(k < 20 ? k * 32 : k * 7919 + 1);
  struct Query {
    size_t noise;
    Vec3 p;
  };
  Random rng(11);
  std::vector<Query> queries;
  for (int k = 0; k < 20000; ++k)
    queries.push_back({size_t(rng.uniform() * 39.99f), {rng.uniform(0, 2.5f), rng.uniform(0, 2.5f), rng.uniform(-1, 1)}});
  auto run = [&](const std::vector<size_t>& order) {
    std::vector<float> out(queries.size() * 4);
    std::thread([&] {
      for (const size_t q : order) {
        const Query& e = queries[q];
        Vec3 g;
        out[4 * q] = noises[e.noise].eval(e.p.x, e.p.y, e.p.z, &g);
        out[4 * q + 1] = g.x + 2 * g.y + 3 * g.z;
        const Vec3 hi = e.p + Vec3{0.01f, 0.01f, 0.01f};  // mostly one cell
        const Interval r = noises[e.noise].range(e.p, hi);
        out[4 * q + 2] = r.lo;
        out[4 * q + 3] = r.hi;
      }
    }).join();
    return out;
  };
  std::vector<size_t> order(queries.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  const std::vector<float> inOrder = run(order);
  for (size_t k = order.size() - 1; k > 0; --k) std::swap(order[k], order[size_t(rng.uniform() * float(k + 1)) % (k + 1)]);
  const std::vector<float> shuffled = run(order);
  ASSERT_EQ(0, std::memcmp(inOrder.data(), shuffled.data(), inOrder.size() * sizeof(float)));
}

// Value noise is defined as the trilinear blend, with quintic fade weights, of the lattice
// values at the corners of the cell floor(x): written here with std::floor and std::clamp, as
// the definition reads, the same float operations give the same bits as eval(), whose cell
// search is a truncation (for the vectorised row) -- at integers, at -0.0 and just below 0,
// beyond 2^24 (where every float is an integer) and past the 2^30 clamp.
TEST(ValueNoise, EvalIsTheTrilinearBlendOfTheCellsLatticeValues) {
  const ValueNoise noise(77);
  auto reference = [&](float x, float y, float z) {
    float in[3] = {x, y, z}, t[3], s[3];
    int64_t cell[3];
    for (int a = 0; a < 3; ++a) {
      const float c = std::clamp(in[a], -1073741824.0f, 1073741824.0f);
      const float f = std::floor(c);
      cell[a] = int64_t(f);
      t[a] = std::clamp(c - f, 0.0f, 1.0f);
      s[a] = std::clamp(t[a] * t[a] * t[a] * (t[a] * (t[a] * 6.0f - 15.0f) + 10.0f), 0.0f, 1.0f);
    }
    auto l = [&](int dx, int dy, int dz) { return noise.lattice(cell[0] + dx, cell[1] + dy, cell[2] + dz); };
    auto lerp = [](float a, float b, float w) { return a + (b - a) * w; };
    const float b0 = lerp(lerp(l(0, 0, 0), l(1, 0, 0), s[0]), lerp(l(0, 1, 0), l(1, 1, 0), s[0]), s[1]);
    const float b1 = lerp(lerp(l(0, 0, 1), l(1, 0, 1), s[0]), lerp(l(0, 1, 1), l(1, 1, 1), s[0]), s[1]);
    return lerp(b0, b1, s[2]);
  };
  const float special[] = {0.0f, -0.0f, 1.0f, -1.0f, 3.0f, -7.0f, 0.5f, -0.5f, -1e-9f, 1e-9f, 0.99999994f,
                           -0.99999994f, 16777216.0f, -16777218.0f, 3e8f, -3e8f, 1073741824.0f, 2e9f, -2e9f};
  Random rng(5);
  int checked = 0;
  for (const float x : special)
    for (const float y : special) {
      const float z = special[size_t(rng.below(int(std::size(special))))];
      for (const Vec3 p : {Vec3{x, y, z}, Vec3{z, x, y}, Vec3{y, z, x}}) {
        const float got = noise.eval(p.x, p.y, p.z, nullptr), want = reference(p.x, p.y, p.z);
        ASSERT_EQ(0, std::memcmp(&got, &want, sizeof got)) << p.x << " " << p.y << " " << p.z << ": " << got << " " << want;
        ++checked;
      }
    }
  for (int k = 0; k < 20000; ++k) {
    const float reach = std::pow(10.0f, rng.uniform(-3.0f, 9.0f));
    const Vec3 p{rng.uniform(-reach, reach), rng.uniform(-reach, reach), rng.uniform(-reach, reach)};
    const float got = noise.eval(p.x, p.y, p.z, nullptr), want = reference(p.x, p.y, p.z);
    ASSERT_EQ(0, std::memcmp(&got, &want, sizeof got)) << p.x << " " << p.y << " " << p.z;
    ++checked;
  }
  EXPECT_GT(checked, 20000);
}

// evalRow() is eval() at every point of a row, bit for bit: rows longer than its chunk, whose
// points step to a neighbouring cell across a face (where it keeps four corners), along a
// diagonal, across several cells at once, back and forth, and stay in one cell.
TEST(ValueNoise, RowEqualsOnePointAtATime) {
  const ValueNoise noise(123);
  Random rng(9);
  const Vec3 steps[] = {{0.3f, 0, 0}, {0, -0.25f, 0}, {0, 0, 0.4f}, {0.3f, 0.2f, -0.1f},
                        {2.5f, 0, 0}, {0.001f, 0, 0}, {-0.7f, 1.3f, 0.05f}};
  // And a row jumping between the two ends of the clamped lattice (cells 2^31 apart).
  {
    const int n = 10;
    std::vector<float> x(n), y(n, 0.5f), z(n, -0.25f), value(n), gx(n), gy(n), gz(n);
    for (int i = 0; i < n; ++i) x[size_t(i)] = i % 2 ? 3e9f : -3e9f;
    noise.evalRow(n, x.data(), y.data(), z.data(), value.data(), gx.data(), gy.data(), gz.data());
    for (int i = 0; i < n; ++i) {
      const float v = noise.eval(x[size_t(i)], y[size_t(i)], z[size_t(i)], nullptr);
      ASSERT_EQ(0, std::memcmp(&v, &value[size_t(i)], sizeof v)) << "point " << i << " of the jumping row";
    }
  }
  for (const Vec3 step : steps)
    for (const bool jitter : {false, true}) {
      const int n = 200;
      std::vector<float> x(n), y(n), z(n), value(n), gx(n), gy(n), gz(n);
      Vec3 p{rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-50, 50)};
      for (int i = 0; i < n; ++i) {
        x[size_t(i)] = p.x;
        y[size_t(i)] = p.y;
        z[size_t(i)] = p.z;
        p = p + step * (jitter && rng.below(4) == 0 ? -1.0f : 1.0f);
      }
      noise.evalRow(n, x.data(), y.data(), z.data(), value.data(), gx.data(), gy.data(), gz.data());
      for (int i = 0; i < n; ++i) {
        Vec3 g;
        const float v = noise.eval(x[size_t(i)], y[size_t(i)], z[size_t(i)], &g);
        const float row[4] = {value[size_t(i)], gx[size_t(i)], gy[size_t(i)], gz[size_t(i)]}, one[4] = {v, g.x, g.y, g.z};
        ASSERT_EQ(0, std::memcmp(row, one, sizeof row)) << "point " << i << " of a row stepping " << step.x << " "
                                                        << step.y << " " << step.z;
      }
    }
}

TEST(ValueNoise, GradientMatchesDifferences) {
  const ValueNoise noise(9);
  Random rng(1);
  for (int k = 0; k < 200; ++k) {
    const Vec3 p{rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-20, 20)};
    Vec3 g;
    noise.eval(p.x, p.y, p.z, &g);
    const float h = 1e-3f;
    for (int a = 0; a < 3; ++a) {
      Vec3 pa = p, pb = p;
      pa[a] += h;
      pb[a] -= h;
      const float d = (noise.eval(pa.x, pa.y, pa.z, nullptr) - noise.eval(pb.x, pb.y, pb.z, nullptr)) / (2 * h);
      EXPECT_NEAR(g[a], d, 0.02f + 0.01f * std::fabs(d));
    }
  }
}

void checkFractal(const NoiseParams& np, uint64_t seed, const char* label) {
  const NoiseDisplacement disp(np);
  Random rng(seed);
  int outside = 0;
  double ratioSum = 0;
  int ratioCount = 0;
  for (int b = 0; b < 200; ++b) {
    Vec3 lo, hi;
    randomBox(rng, lo, hi);
    // World units: divide by the first octave's frequency.
    lo = lo / np.frequency;
    hi = hi / np.frequency;
    Box3 box;
    box.extend(lo);
    box.extend(hi);
    const Interval r = disp.range(box, 0, 1, 0, 1);
    float mn = 1e30f, mx = -1e30f;
    for (int k = 0; k < 5000; ++k) {
      const Vec3 p = pointIn(rng, box.lo, box.hi);
      const float h = disp.sample(p, {1, 0, 0}, {0, 1, 0}, 0, 0).h;
      mn = std::min(mn, h);
      mx = std::max(mx, h);
      if (!r.contains(h) && ++outside < 5)
        ADD_FAILURE() << label << ": h " << h << " outside [" << r.lo << ", " << r.hi << "]";
    }
    if (mx - mn > 1e-3f * std::fabs(np.amplitude)) {
      ratioSum += double(r.width()) / double(mx - mn);
      ++ratioCount;
    }
  }
  EXPECT_EQ(outside, 0) << label;
  std::printf("%s: mean interval width / sampled spread = %.3f over %d boxes\n", label, ratioSum / ratioCount, ratioCount);
  EXPECT_LT(ratioSum / ratioCount, 3.0) << label;
}

TEST(NoiseDisplacement, FractalIntervalContainsEverySample) {
  NoiseParams np;
  np.amplitude = 2.5f;
  np.frequency = 3.0f;
  np.octaves = 6;
  np.offset = 0.25f;
  checkFractal(np, 21, "fbm 6 octaves");
  np.ridged = true;
  np.amplitude = -4.0f;  // negative amplitudes push inward
  checkFractal(np, 22, "ridged 6 octaves");
  np.ridged = false;
  np.octaves = 16;  // up to 2^15 x the first frequency
  np.gain = 0.8f;
  checkFractal(np, 23, "fbm 16 octaves");
}

// sampleRow() is sample() at every point, bit for bit, plain and ridged (whose gradient flips
// with the sign of each octave's value).
TEST(NoiseDisplacement, SampleRowEqualsOnePointAtATime) {
  for (const bool ridged : {false, true}) {
    NoiseParams np;
    np.amplitude = 0.7f;
    np.frequency = 2.5f;
    np.octaves = 5;
    np.ridged = ridged;
    np.offset = -0.1f;
    const NoiseDisplacement disp(np);
    Random rng(ridged ? 3 : 4);
    const int n = 150;
    std::vector<Vec3> p(n), pu(n), pv(n);
    std::vector<float> u(n);
    for (int i = 0; i < n; ++i) {
      p[size_t(i)] = Vec3{0.013f * float(i), 0.4f * std::sin(0.05f * float(i)), 1.0f} + Vec3{rng.uniform(), 0, 0} * 0.01f;
      pu[size_t(i)] = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
      pv[size_t(i)] = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
      u[size_t(i)] = float(i) / float(n - 1);
    }
    std::vector<HeightSample> row(n);
    disp.sampleRow(n, p.data(), pu.data(), pv.data(), u.data(), 0.5f, row.data());
    for (int i = 0; i < n; ++i) {
      const HeightSample one = disp.sample(p[size_t(i)], pu[size_t(i)], pv[size_t(i)], u[size_t(i)], 0.5f);
      const float a[3] = {row[size_t(i)].h, row[size_t(i)].hu, row[size_t(i)].hv}, b[3] = {one.h, one.hu, one.hv};
      ASSERT_EQ(0, std::memcmp(a, b, sizeof a)) << (ridged ? "ridged" : "plain") << " point " << i;
    }
  }
}

// The row kernels run on AVX2 or on the baseline (core/vector_isa.h); both must give the same
// bits, so that an image does not depend on the CPU. Rows that step along and across cells,
// and the edge values of the cell and clamp arithmetic: -0.0, integers and the float just
// below them, denormals, values past 2^24 and past the 2^30 clamp, infinities and NaN.
TEST(ValueNoise, RowIsTheSameOnEveryInstructionSet) {
  if (!cpuHasAvx2()) GTEST_SKIP() << "this CPU runs the baseline kernels only";
  const ValueNoise noise(77);
  Random rng(21);
  const float inf = std::numeric_limits<float>::infinity();
  const float edges[] = {0.0f, -0.0f, 1.0f, -1.0f, std::nextafter(1.0f, 0.0f), std::nextafter(-1.0f, -2.0f),
                         1e-40f, -1e-40f, 16777217.0f, -16777219.0f, 1073741824.0f, 3e9f, -3e9f,
                         inf, -inf, std::numeric_limits<float>::quiet_NaN(), 0.5f, 12345.678f};
  const int n = 300;
  std::vector<float> x(n), y(n), z(n);
  for (int i = 0; i < n; ++i) {
    if (i < 100) {  // every edge value on every axis
      x[size_t(i)] = edges[size_t(i) % std::size(edges)];
      y[size_t(i)] = edges[size_t(i / 3) % std::size(edges)];
      z[size_t(i)] = edges[size_t(i / 7) % std::size(edges)];
    } else {  // a walk with steps of a few hundredths to a few cells
      const float s = i < 200 ? 0.03f : 1.7f;
      x[size_t(i)] = x[size_t(i - 1)] * (i == 100 ? 0.0f : 1.0f) + s * rng.uniform(-1, 1);
      y[size_t(i)] = y[size_t(i - 1)] * (i == 100 ? 0.0f : 1.0f) + 0.5f * s * rng.uniform(-1, 1);
      z[size_t(i)] = z[size_t(i - 1)] * (i == 100 ? 0.0f : 1.0f) + 0.2f * s;
    }
  }
  auto run = [&](VectorIsa isa) {
    ScopedVectorIsa scoped(isa);
    std::vector<float> out(4 * size_t(n));
    noise.evalRow(n, x.data(), y.data(), z.data(), out.data(), out.data() + n, out.data() + 2 * n,
                  out.data() + 3 * n);
    return out;
  };
  const std::vector<float> base = run(VectorIsa::Baseline), avx2 = run(VectorIsa::Avx2);
  for (int k = 0; k < 4 * n; ++k)
    ASSERT_EQ(0, std::memcmp(&base[size_t(k)], &avx2[size_t(k)], sizeof(float)))
        << "output " << k / n << " (value, gx, gy, gz) of point " << k % n;
}

TEST(NoiseDisplacement, SampleRowIsTheSameOnEveryInstructionSet) {
  if (!cpuHasAvx2()) GTEST_SKIP() << "this CPU runs the baseline kernels only";
  for (const bool ridged : {false, true}) {
    NoiseParams np;
    np.amplitude = 0.7f;
    np.frequency = 40.0f;
    np.octaves = 8;
    np.ridged = ridged;
    const NoiseDisplacement disp(np);
    Random rng(ridged ? 5 : 6);
    const int n = 257;
    std::vector<Vec3> p(n), pu(n), pv(n);
    for (int i = 0; i < n; ++i) {
      p[size_t(i)] = {0.004f * float(i), rng.uniform(-1, 1), 3.0f};
      pu[size_t(i)] = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
      pv[size_t(i)] = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
    }
    std::vector<float> u(n, 0.0f);
    auto run = [&](VectorIsa isa) {
      ScopedVectorIsa scoped(isa);
      std::vector<HeightSample> out(n);
      disp.sampleRow(n, p.data(), pu.data(), pv.data(), u.data(), 0.5f, out.data());
      return out;
    };
    const std::vector<HeightSample> base = run(VectorIsa::Baseline), avx2 = run(VectorIsa::Avx2);
    for (int i = 0; i < n; ++i) {
      const float a[3] = {base[size_t(i)].h, base[size_t(i)].hu, base[size_t(i)].hv};
      const float b[3] = {avx2[size_t(i)].h, avx2[size_t(i)].hu, avx2[size_t(i)].hv};
      ASSERT_EQ(0, std::memcmp(a, b, sizeof a)) << (ridged ? "ridged" : "plain") << " point " << i;
    }
  }
}

TEST(NoiseDisplacement, AmplitudeBoundsTheHeight) {
  NoiseParams np;
  np.amplitude = 3.0f;
  np.octaves = 5;
  const NoiseDisplacement disp(np);
  Box3 everywhere;
  everywhere.extend({-1e6f, -1e6f, -1e6f});
  everywhere.extend({1e6f, 1e6f, 1e6f});
  const Interval r = disp.range(everywhere, 0, 1, 0, 1);
  EXPECT_GE(r.lo, -3.001f);
  EXPECT_LE(r.hi, 3.001f);
}

TEST(NoiseDisplacement, RejectsBadParameters) {
  NoiseParams np;
  np.frequency = 0;
  EXPECT_THROW(NoiseDisplacement{np}, std::invalid_argument);
  np = {};
  np.octaves = 17;
  EXPECT_THROW(NoiseDisplacement{np}, std::invalid_argument);
  np = {};
  np.gain = 0;
  EXPECT_THROW(NoiseDisplacement{np}, std::invalid_argument);
}

}  // namespace
}  // namespace rayes

namespace rayes {
namespace {

// magnitudeBound() bounds every range(): over boxes from a point to a thousand lattice cells
// (the cell cap's [-1, 1]), an empty box and one that is not finite, for plain and ridged noise
// with offsets on either side and a negative amplitude.
TEST(NoiseDisplacement, MagnitudeBoundHoldsEveryRange) {
  Random rnd(23);
  for (const bool ridged : {false, true})
    for (const float offset : {0.0f, 0.7f, -3.0f})
      for (const float amplitude : {1.0f, -0.05f, 1e-6f}) {
        NoiseParams p;
        p.amplitude = amplitude;
        p.offset = offset;
        p.ridged = ridged;
        p.frequency = 2.5f;
        p.octaves = 6;
        const NoiseDisplacement d(p);
        const float m = d.magnitudeBound();
        ASSERT_TRUE(std::isfinite(m));
        auto check = [&](const Box3& b) {
          const Interval r = d.range(b, 0.0f, 1.0f, 0.0f, 1.0f);
          ASSERT_GE(r.lo, -m);
          ASSERT_LE(r.hi, m);
        };
        for (int k = 0; k < 300; ++k) {
          const Vec3 c{rnd.uniform(-50.0f, 50.0f), rnd.uniform(-50.0f, 50.0f), rnd.uniform(-50.0f, 50.0f)};
          const float half = std::ldexp(1.0f, rnd.below(20) - 12);
          Box3 b;
          b.extend(c - Vec3{half, half, half});
          b.extend(c + Vec3{half, half, half});
          check(b);
        }
        check(Box3{});
        Box3 inf;
        inf.lo = {-std::numeric_limits<float>::infinity(), 0, 0};
        inf.hi = {1, 1, 1};
        check(inf);
      }
}

}  // namespace
}  // namespace rayes
