// DisplacedPatch (geometry/displaced_patch.h): docs/design.md, invariant 1 with displacement. For each
// test shape (a teapot body patch, a teapot pole patch, a twisted bilinear patch) and each
// displacement (moderate noise, extreme noise -- amplitude the patch's own size, frequency up to
// past the dicing resolution --, a height map), 10^6 displaced points all lie inside bounds(),
// and points of random sub-rectangles (and border pieces) inside boundsOver(). Also: dice()
// equals evaluate() bit for bit, normals are finite, and what the teapot's seams do.
#include <gtest/gtest.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>
#include "core/vector_isa.h"
#include "geometry/bilinear_patch.h"
#include "geometry/patch_math.h"
#include "geometry/displaced_patch.h"
#include "support/displaced_test_shapes.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

using test::Displaced;
using test::Random;
using test::sameBits;
using test::Shape;
using test::testDisplacements;
using test::testShapes;

// A parameter in [a, b]: an end, a dyadic grid point of level 8, or uniform.
float param(Random& rng, float a, float b) {
  switch (rng.below(8)) {
    case 0: return a;
    case 1: return b;
    case 2: return std::clamp(std::round(rng.uniform(a, b) * 256.0f) / 256.0f, a, b);
    default: return std::min(b, a + (b - a) * rng.uniform());
  }
}

// dice() at level m gives evaluate()'s grid, positions and normals, bit for bit.
::testing::AssertionResult diceEqualsEvaluate(const Patch& patch, int m) {
  const int n = 1 << m;
  std::vector<Vec3> p(size_t(n + 1) * (n + 1)), nn(p.size());
  patch.dice(m, p.data(), nn.data());
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const SurfacePoint sp = patch.evaluate(float(i) / n, float(j) / n);
      if (!sameBits(sp.p, p[size_t(j) * (n + 1) + i]) || !sameBits(sp.n, nn[size_t(j) * (n + 1) + i]))
        return ::testing::AssertionFailure() << "vertex (" << i << ", " << j << ") of level " << m;
    }
  return ::testing::AssertionSuccess();
}

TEST(DisplacedPatch, MillionPointsInsideBoundsAndBoundsOver) {
  for (const Shape& shape : testShapes()) {
    const float size = shape.patch->bounds().longestSide();
    for (const Displaced& disp : testDisplacements(size)) {
      const DisplacedPatch patch(shape.patch, disp.d);
      const Box3 box = patch.bounds();
      Random rng(uint64_t(size * 1000) + uint64_t(disp.name[0]));
      int outside = 0, nonFinite = 0;
      for (int k = 0; k < 1000000; ++k) {
        const float u = param(rng, 0, 1), v = param(rng, 0, 1);
        const SurfacePoint sp = patch.evaluate(u, v);
        if (!box.contains(sp.p) && ++outside < 4)
          ADD_FAILURE() << shape.name << " / " << disp.name << ": (" << u << ", " << v << ") outside bounds()";
        if (!isFinite(sp.n) || maxComponent(vabs(sp.n)) == 0.0f) ++nonFinite;
      }
      EXPECT_EQ(outside, 0) << shape.name << " / " << disp.name;
      EXPECT_EQ(nonFinite, 0) << shape.name << " / " << disp.name;

      // Sub-rectangles from a micro-quad at level 10 to half the patch, and border pieces.
      int outsideSub = 0;
      std::vector<double> ratios;
      for (int r = 0; r < 2000; ++r) {
        const float su = std::pow(2.0f, -rng.uniform(1, 10)), sv = std::pow(2.0f, -rng.uniform(1, 10));
        float u0 = rng.uniform(0, 1 - su), v0 = rng.uniform(0, 1 - sv), u1 = u0 + su, v1 = v0 + sv;
        if (r % 10 == 0) u0 = u1 = float(rng.below(2));   // a border piece along v
        if (r % 10 == 1) v0 = v1 = float(rng.below(2));   // a border piece along u
        const Box3 sub = patch.boundsOver(u0, u1, v0, v1);
        Box3 seen;
        for (int k = 0; k < 250; ++k) {
          const Vec3 p = patch.evaluate(param(rng, u0, u1), param(rng, v0, v1)).p;
          seen.extend(p);
          if (!sub.contains(p) && ++outsideSub < 4)
            ADD_FAILURE() << shape.name << " / " << disp.name << ": outside boundsOver(" << u0 << ", " << u1
                          << ", " << v0 << ", " << v1 << ")";
        }
        if (seen.longestSide() > 0) ratios.push_back(double(sub.longestSide()) / double(seen.longestSide()));
      }
      EXPECT_EQ(outsideSub, 0) << shape.name << " / " << disp.name;
      std::sort(ratios.begin(), ratios.end());
      std::printf("%-16s %-15s bounds %.3g (base %.3g); boundsOver longest side / sampled: median %.2f, 90%% %.2f\n",
                  shape.name, disp.name, box.longestSide(), size, ratios[ratios.size() / 2], ratios[ratios.size() * 9 / 10]);
    }
  }
}

TEST(DisplacedPatch, DiceEqualsEvaluateBitForBitAndLevelsNest) {
  for (const Shape& shape : testShapes()) {
    const float size = shape.patch->bounds().longestSide();
    for (const Displaced& disp : testDisplacements(size)) {
      const DisplacedPatch patch(shape.patch, disp.d);
      const int m = 5, n = 1 << m;
      std::vector<Vec3> p((n + 1) * (n + 1)), nn(p.size()), pc(17 * 17), nc(pc.size());
      patch.dice(m, p.data(), nn.data());
      patch.dice(4, pc.data(), nc.data());
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
          const SurfacePoint sp = patch.evaluate(float(i) / n, float(j) / n);
          ASSERT_TRUE(sameBits(sp.p, p[size_t(j) * (n + 1) + i])) << shape.name << " / " << disp.name;
          ASSERT_TRUE(sameBits(sp.n, nn[size_t(j) * (n + 1) + i])) << shape.name << " / " << disp.name;
          if (i % 2 == 0 && j % 2 == 0) {
            ASSERT_TRUE(sameBits(pc[size_t(j / 2) * 17 + i / 2], p[size_t(j) * (n + 1) + i]));
            ASSERT_TRUE(sameBits(nc[size_t(j / 2) * 17 + i / 2], nn[size_t(j) * (n + 1) + i]));
          }
        }
    }
  }
}

// The base frames and the noise run on AVX2 or on the baseline (core/vector_isa.h): a dicing
// is the same bits on both, for every base (a pole's difference fallback included), every
// displacement, a reference surface, and rows longer than a kernel's chunk.
TEST(DisplacedPatch, DiceIsTheSameOnEveryInstructionSet) {
  if (!cpuHasAvx2()) GTEST_SKIP() << "this CPU runs the baseline kernels only";
  auto diced = [](const Patch& patch, int m, VectorIsa isa) {
    ScopedVectorIsa scoped(isa);
    const size_t count = size_t((1 << m) + 1) * size_t((1 << m) + 1);
    std::vector<Vec3> out(2 * count);
    patch.dice(m, out.data(), out.data() + count);
    return out;
  };
  std::vector<std::pair<std::string, PatchPtr>> cases;
  for (const Shape& s : testShapes())
    for (const Displaced& d : testDisplacements(2.0f))
      cases.push_back({std::string(s.name) + ", " + d.name, std::make_shared<DisplacedPatch>(s.patch, d.d)});
  const auto teapot = test::loadTeapot();
  cases.push_back({"teapot body with a moved reference",
                   std::make_shared<DisplacedPatch>(
                       std::make_shared<BezierPatch>(test::transformed(teapot[0], 1.0f, {40, 0, 0})),
                       testDisplacements(2.0f)[0].d, std::make_shared<BezierPatch>(teapot[0]))});
  for (const auto& [name, patch] : cases) {
    const std::vector<Vec3> base = diced(*patch, 7, VectorIsa::Baseline), avx2 = diced(*patch, 7, VectorIsa::Avx2);
    for (size_t k = 0; k < base.size(); ++k)
      ASSERT_TRUE(sameBits(base[k], avx2[k])) << name << ": " << (k < base.size() / 2 ? "position " : "normal ")
                                              << k % (base.size() / 2);
  }
}

// dice() evaluates the displacement a grid row at a time (Displacement::sampleRow): at level 7
// a row of 129 vertices spans several of the noise's chunks; with a reference surface as the
// forest's terrain has (a bilinear base and reference) and its bark (Bézier), the grid is
// still evaluate()'s, bit for bit.
TEST(DisplacedPatch, RowsLongerThanTheNoiseChunkStillEqualEvaluate) {
  const auto teapot = test::loadTeapot();
  NoiseParams np;
  np.amplitude = 0.2f;
  np.frequency = 2.0f;
  np.octaves = 5;
  const auto d = std::make_shared<NoiseDisplacement>(np);
  const Vec3 c[4] = {{0, 0, 0}, {3, 0, 0.2f}, {0, 0.1f, -3}, {3, 0.3f, -3.1f}};
  auto bilinear = [&](Vec3 o) { return std::make_shared<BilinearPatch>(c[0] + o, c[1] + o, c[2] + o, c[3] + o); };
  const std::pair<const char*, DisplacedPatch> cases[] = {
      {"bilinear with reference", DisplacedPatch(bilinear({40, 0, 0}), d, bilinear({0, 0, 0}))},
      {"bezier with reference",
       DisplacedPatch(std::make_shared<BezierPatch>(test::transformed(teapot[0], 1.0f, {40, 0, 0})), d,
                      std::make_shared<BezierPatch>(teapot[0]))},
      {"bezier", DisplacedPatch(std::make_shared<BezierPatch>(teapot[0]), d)}};
  for (const auto& [name, patch] : cases) EXPECT_TRUE(diceEqualsEvaluate(patch, 7)) << name;
}

// A constant height h makes the offset surface P + h N, whose raw normal is exactly
// det(I - h S) (P_u x P_v), S the base's shape operator: trace and determinant from the first
// and second fundamental forms, (E N - 2 F M + G L) / W and (L N - M^2) / W, W = E G - F^2 --
// computed here in double from the base's float derivatives, independently of the code's
// projection formula for N_u. A wrong or missing term of N_u, or a finite difference in its
// place (error ~ h 2^-10 |N_u|^2, about 1e-4 of the normal here), fails it. The bound: the
// code's P'_u and P'_v are each at most ~24 roundings from exact (the unit normal's 10, N_u's
// projection 8, the sums) on terms of size |P_u| and |h| |dN_u| / |N| (dN_u = P_uu x P_v +
// P_u x P_uv, before the projection cancels its normal part), then one more cross product:
// gamma(32) of those magnitudes. Checked at scales from 1e-12 to 1e12 (the 1 / max component
// and the sqrt of analyticFrame at their edges) and on both sides of the base.
TEST(DisplacedPatch, ConstantHeightGivesTheOffsetSurfacesNormal) {
  using D3 = std::array<double, 3>;
  auto d3 = [](Vec3 a) { return D3{a.x, a.y, a.z}; };
  auto dot3 = [](D3 a, D3 b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  auto cross3 = [](D3 a, D3 b) { return D3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; };
  auto add3 = [](D3 a, D3 b, double k) { return D3{a[0] + k * b[0], a[1] + k * b[1], a[2] + k * b[2]}; };
  auto len3 = [&](D3 a) { return std::sqrt(dot3(a, a)); };
  const auto teapot = test::loadTeapot();
  for (const float scale : {1e-12f, 1e-6f, 1.0f, 1e6f, 1e12f}) {
    const auto body = std::make_shared<BezierPatch>(test::transformed(teapot[0], scale, {0, 0, 0}));
    const Vec3 c[4] = {{0, 0, 0}, {2 * scale, 0, 0.3f * scale}, {0, 2 * scale, -0.2f * scale}, {2 * scale, 2.2f * scale, 0.4f * scale}};
    const auto twisted = std::make_shared<BilinearPatch>(c[0], c[1], c[2], c[3]);
    struct Case { const char* name; PatchPtr base; float relativeHeight; };
    for (const Case& cs : {Case{"teapot body", body, 0.05f}, Case{"twisted bilinear", twisted, 0.2f}}) {
      for (const float sign : {1.0f, -1.0f}) {
        const float h = sign * cs.relativeHeight * cs.base->bounds().longestSide();
        NoiseParams np;
        np.amplitude = 0;
        np.offset = h;
        const DisplacedPatch patch(cs.base, std::make_shared<NoiseDisplacement>(np));
        Random rng(7);
        double worst = 0;
        for (int k = 0; k < 2000; ++k) {
          const float u = rng.uniform(0.02f, 0.98f), v = rng.uniform(0.02f, 0.98f);
          SurfaceDerivatives fd;
          if (const auto* bz = dynamic_cast<const BezierPatch*>(cs.base.get())) fd = BezierPatch::derivativesOnRow(bz->rowAt(v), u);
          else fd = dynamic_cast<const BilinearPatch&>(*cs.base).derivatives(u, v);
          const D3 pu = d3(fd.pu), pv = d3(fd.pv), puu = d3(fd.puu), puv = d3(fd.puv), pvv = d3(fd.pvv);
          const D3 raw = cross3(pu, pv);
          const double w = dot3(raw, raw), nl = std::sqrt(w);
          const D3 n{raw[0] / nl, raw[1] / nl, raw[2] / nl};
          const double E = dot3(pu, pu), F = dot3(pu, pv), G = dot3(pv, pv);
          const double L = dot3(puu, n), M = dot3(puv, n), N = dot3(pvv, n);
          const double trace = (E * N - 2 * F * M + G * L) / w, det = (L * N - M * M) / w;
          const double factor = 1 - double(h) * trace + double(h) * double(h) * det;
          const D3 expected{raw[0] * factor, raw[1] * factor, raw[2] * factor};
          // Magnitudes for the bound (from the exact N_u, the same formula in double).
          const D3 dnu = add3(cross3(puu, pv), cross3(pu, puv), 1), dnv = add3(cross3(puv, pv), cross3(pu, pvv), 1);
          const D3 nu = add3(dnu, n, -dot3(n, dnu)), nv = add3(dnv, n, -dot3(n, dnv));
          const D3 du = add3(pu, nu, double(h) / nl), dv = add3(pv, nv, double(h) / nl);
          const double bound = double(gammaBound(32)) * ((len3(pu) + std::fabs(h) * len3(dnu) / nl) * len3(dv) +
                                                         len3(du) * (len3(pv) + std::fabs(h) * len3(dnv) / nl));
          const D3 got = d3(patch.evaluate(u, v).n);
          const double err = len3(add3(got, expected, -1));
          worst = std::max(worst, err / bound);
          ASSERT_LE(err, bound) << cs.name << " at scale " << scale << ", h " << h << ", (" << u << ", " << v << ")";
        }
        std::printf("%-16s scale %-6g h %+.3g: worst error / bound %.3f\n", cs.name, double(scale), double(h), worst);
      }
    }
  }
}

// Near a pole the base normal P_u x P_v vanishes and the base nudges it; there the frame falls
// back to differences. Both paths give finite normals up to the pole (and bit-equal grids).
TEST(DisplacedPatch, NormalsStayFiniteUpToAPole) {
  const Shape pole = testShapes()[1];
  NoiseParams np;
  np.amplitude = 0.1f * pole.patch->bounds().longestSide();
  np.frequency = 4.0f / pole.patch->bounds().longestSide();
  const DisplacedPatch patch(pole.patch, std::make_shared<NoiseDisplacement>(np));
  for (int e = 0; e <= 40; ++e) {
    const float t = e == 40 ? 0.0f : std::ldexp(1.0f, -e);
    for (const float s : {0.0f, 0.3f, 0.5f, 1.0f})
      for (const float tt : {t, 1.0f - t}) {
        EXPECT_TRUE(isFinite(patch.evaluate(s, tt).n) && isFinite(patch.evaluate(tt, s).n)) << s << ", " << tt;
        EXPECT_GT(maxComponent(vabs(patch.evaluate(s, tt).n)), 0.0f);
      }
  }
  EXPECT_TRUE(diceEqualsEvaluate(patch, 6));
}

TEST(DisplacedPatch, FlatBaseKeepsItsBoxTightSideways) {
  // A horizontal plane: the normal is exactly +z, so displacement only widens z.
  auto plane = std::make_shared<BilinearPatch>(Vec3{0, 0, 0}, Vec3{10, 0, 0}, Vec3{0, 10, 0}, Vec3{10, 10, 0});
  NoiseParams np;
  np.amplitude = 5;
  np.frequency = 0.3f;
  const DisplacedPatch patch(plane, std::make_shared<NoiseDisplacement>(np));
  const Box3 b = patch.bounds();
  EXPECT_NEAR(b.lo.x, 0.0f, 1e-3f);
  EXPECT_NEAR(b.hi.y, 10.0f, 1e-3f);
  EXPECT_GT(b.hi.z, 0.5f);
  EXPECT_GE(b.lo.z, -5.01f);
  const Box3 q = patch.boundsOver(0.5f, 0.5f + 1.0f / 256, 0.25f, 0.25f + 1.0f / 256);
  EXPECT_LT(q.extent().x, 0.05f);
  EXPECT_LT(q.extent().z, 1.0f);  // far below the 10 of the whole range
  EXPECT_STREQ(patch.kind(), "displaced-bilinear");
  EXPECT_GT(patch.sizeBound(), plane->sizeBound());
  EXPECT_GT(patch.dicingErrorCoefficient(), 0.0f);
}

TEST(DisplacedPatch, NormalRangeContainsSampledUnitNormals) {
  for (const Shape& shape : testShapes()) {
    NoiseParams np;
    const DisplacedPatch patch(shape.patch, std::make_shared<NoiseDisplacement>(np));
    Random rng(77);
    for (int r = 0; r < 3000; ++r) {
      const float su = std::pow(2.0f, -rng.uniform(0, 12)), sv = std::pow(2.0f, -rng.uniform(0, 12));
      const float u0 = rng.uniform(0, 1 - su), v0 = rng.uniform(0, 1 - sv);
      const Box3 nr = patch.normalRangeOver(u0, u0 + su, v0, v0 + sv);
      for (int k = 0; k < 50; ++k) {
        const Vec3 n = detail::unitOrZero(shape.patch->evaluate(param(rng, u0, u0 + su), param(rng, v0, v0 + sv)).n);
        ASSERT_TRUE(nr.contains(n)) << shape.name;
      }
    }
  }
}

TEST(DisplacedPatch, ReferenceSurfaceFeedsTheNoise) {
  // The same patch moved by 100: with the unmoved patch as reference, the displacement moves
  // with it (same heights); without, the noise pattern differs.
  const auto teapot = test::loadTeapot();
  auto rest = std::make_shared<BezierPatch>(teapot[0]);
  auto moved = std::make_shared<BezierPatch>(test::transformed(teapot[0], 1.0f, {100, 0, 0}));
  NoiseParams np;
  np.amplitude = 0.3f;
  np.frequency = 3;
  auto d = std::make_shared<NoiseDisplacement>(np);
  const DisplacedPatch a(rest, d), b(moved, d, rest), c(moved, d);
  int differ = 0;
  for (float u : {0.1f, 0.4f, 0.7f})
    for (float v : {0.2f, 0.5f, 0.9f}) {
      const Vec3 pa = a.evaluate(u, v).p, pb = b.evaluate(u, v).p - Vec3{100, 0, 0};
      EXPECT_NEAR(pa.x, pb.x, 1e-4f);
      EXPECT_NEAR(pa.z, pb.z, 1e-4f);
      differ += length(c.evaluate(u, v).p - Vec3{100, 0, 0} - pa) > 1e-3f;
      EXPECT_TRUE(b.bounds().contains(b.evaluate(u, v).p));
    }
  EXPECT_GT(differ, 0);
  // dice() takes a Bézier base's and reference's rows once per grid row: still evaluate()'s
  // grid, bit for bit, with a reference surface (a transformed shape).
  EXPECT_TRUE(diceEqualsEvaluate(b, 5));
}

// What displacement does at the teapot's seams: heights are a function of position, so they
// agree; the base unit normals at a shared border come from different patches' derivatives.
TEST(DisplacedPatch, TeapotSeamsDifferOnlyByNormalRounding) {
  const auto teapot = test::loadTeapot();
  NoiseParams np;
  np.amplitude = 0.2f;
  np.frequency = 2;
  auto d = std::make_shared<NoiseDisplacement>(np);
  std::vector<std::shared_ptr<DisplacedPatch>> patches;
  for (const auto& cp : teapot) patches.push_back(std::make_shared<DisplacedPatch>(std::make_shared<BezierPatch>(cp), d));
  const int level = 5, n = 1 << level;
  std::vector<Vec3> pa((n + 1) * (n + 1)), na(pa.size()), pb(pa.size()), nb(pa.size());
  int identical = 0, total = 0;
  float maxGap = 0;
  for (const auto& s : test::findSharedBorders(teapot)) {
    patches[size_t(s.patchA)]->dice(level, pa.data(), na.data());
    patches[size_t(s.patchB)]->dice(level, pb.data(), nb.data());
    for (int k = 0; k <= n; ++k) {
      const auto ia = test::borderVertex(s.sideA, k, n);
      const auto ib = test::borderVertex(s.sideB, s.reversed ? n - k : k, n);
      const Vec3 a = pa[size_t(ia[1]) * (n + 1) + ia[0]], b = pb[size_t(ib[1]) * (n + 1) + ib[0]];
      identical += sameBits(a, b);
      maxGap = std::max(maxGap, length(a - b));
      ++total;
    }
  }
  std::printf("teapot seams, noise amplitude 0.2: %d of %d displaced border vertices bit-identical, max gap %.3g\n",
              identical, total, maxGap);
  // Rounding of the unit normal only (relative 1e-6 of the amplitude), no G1 breaks.
  EXPECT_LT(maxGap, 1e-5f);
}

}  // namespace
}  // namespace rayes

namespace rayes {
namespace {

// Patch::coarseBoundsOverAt: a static dicing tests rays against it before it computes a border
// segment's box, and skips the box when a ray misses it, so it must hold boundsOver's box as
// computed, every coordinate as far out or farther: for every segment a dicing asks about
// (each border, levels 0..10) and for interior rectangles, over each test shape with each
// noise (and an offset larger than the amplitude, a negative amplitude, a tiny one). A height
// map gives no bound (its range is a pyramid look-up, not the cost).
TEST(DisplacedPatch, CoarseBoundsHoldBoundsOverAsComputed) {
  Random rnd(17);
  int checked = 0;
  for (const Shape& s : test::testShapes()) {
    const float size = s.patch->bounds().longestSide();
    std::vector<Displaced> ds = testDisplacements(size);
    NoiseParams offset;
    offset.amplitude = -0.02f * size;
    offset.offset = 0.3f * size;
    offset.frequency = 3.0f / size;
    NoiseParams tiny;
    tiny.amplitude = 1e-7f * size;
    tiny.frequency = 5.0f / size;
    ds.push_back({"offset noise", std::make_shared<NoiseDisplacement>(offset)});
    ds.push_back({"tiny noise", std::make_shared<NoiseDisplacement>(tiny)});
    for (const Displaced& d : ds) {
      const DisplacedPatch patch(s.patch, d.d);
      const bool noise = std::string(d.d->kind()) == "noise";
      auto check = [&](float u0, float u1, float v0, float v1) {
        Box3 coarse;
        const bool has = patch.coarseBoundsOverAt(0, u0, u1, v0, v1, coarse);
        ASSERT_EQ(has, noise) << s.name << ", " << d.name;
        if (!has) return;
        const Box3 exact = patch.boundsOverAt(0, u0, u1, v0, v1);
        for (int a = 0; a < 3; ++a) {
          ASSERT_LE(coarse.lo[a], exact.lo[a]) << s.name << ", " << d.name << ": " << u0 << " " << u1 << " " << v0 << " " << v1;
          ASSERT_GE(coarse.hi[a], exact.hi[a]) << s.name << ", " << d.name << ": " << u0 << " " << u1 << " " << v0 << " " << v1;
        }
        ++checked;
      };
      for (int level = 0; level <= 10; ++level) {
        const uint32_t n = 1u << level;
        for (int k = 0; k < 24; ++k) {
          const uint32_t j = level <= 4 ? uint32_t(k) % n : uint32_t(rnd.below(int(n)));
          const float t0 = float(j) / float(n), t1 = float(j + 1) / float(n);
          check(t0, t1, 0.0f, 0.0f);
          check(1.0f, 1.0f, t0, t1);
          check(t0, t1, 1.0f, 1.0f);
          check(0.0f, 0.0f, t0, t1);
        }
      }
      for (int k = 0; k < 100; ++k) {
        float u0 = rnd.uniform(0.0f, 1.0f), u1 = rnd.uniform(0.0f, 1.0f), v0 = rnd.uniform(0.0f, 1.0f),
              v1 = rnd.uniform(0.0f, 1.0f);
        check(std::min(u0, u1), std::max(u0, u1), std::min(v0, v1), std::max(v0, v1));
      }
    }
  }
  EXPECT_EQ(checked, 3 * 4 * (11 * 24 * 4 + 100));  // 3 shapes, 4 noises
}

}  // namespace
}  // namespace rayes
