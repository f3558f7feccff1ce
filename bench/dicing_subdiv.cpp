// Dicing throughput of subdivision leaves against a Bézier patch: Patch::dice at m = 4..8,
// reported as seconds per micropolygon (one thread). Leaves: a regular Catmull-Clark face in
// Bézier form (the default) and through Bfr (regularAsBezier = false), an irregular quad (a
// cube face: all four corners have valence 3), a sub-face of a pentagon, and a Loop
// sub-quad. Also the cost of one Bfr surface set-up (InitVertexSurface + PreparePatchPoints),
// which the per-thread surface cache saves when a face is diced again. See
// bench/history/RESULTS-subdiv.md for figures and the command line.
#include <benchmark/benchmark.h>
#include <cmath>
#include <vector>
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include "geometry/subdiv_mesh.h"
#include "support/subdiv_test_meshes.h"
#include "dicing_bench_setup.h"

namespace {

using namespace rayes;

// 6 x 6 wavy grid: face 14 (row 2, column 2) is regular.
SubdivMeshDesc grid() {
  SubdivMeshDesc d;
  for (int j = 0; j <= 6; ++j)
    for (int i = 0; i <= 6; ++i)
      d.positions.push_back({float(i), float(j), 0.3f * std::sin(1.3f * float(i)) * std::cos(0.9f * float(j))});
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) {
      const int a = j * 7 + i;
      d.faceSizes.push_back(4);
      for (int v : {a, a + 1, a + 8, a + 7}) d.faceVertices.push_back(v);
    }
  return d;
}

using test::cube;
const auto prism = test::pentagonalPrism;
using test::octahedron;

struct Leaf {
  SubdivMeshPtr mesh;
  PatchPtr patch;
};

Leaf leafOf(const SubdivMeshDesc& d, int face, bool bezier = true) {
  Leaf l;
  l.mesh = SubdivMesh::build(buildSubdivTopology(d, bezier), d.positions);
  auto patches = l.mesh->patches();
  for (int k = 0; k < l.mesh->leafCount(); ++k)
    if (l.mesh->leafFace(k).first == face) {
      l.patch = patches[size_t(k)];
      break;
    }
  return l;
}

void perMicropolygon(benchmark::State& state, int m) {
  state.counters["per_micropolygon"] = benchmark::Counter(
      double(state.iterations()) * double(1 << (2 * m)), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void diceLoop(benchmark::State& state, const Patch& patch) {
  const int m = int(state.range(0));
  const size_t n = size_t((1 << m) + 1) * ((1 << m) + 1);
  std::vector<Vec3> p(n), nrm(n);
  for (auto _ : state) {
    patch.dice(m, p.data(), nrm.data());
    benchmark::DoNotOptimize(p.data());
  }
  perMicropolygon(state, m);
}

void BM_DiceBezier(benchmark::State& state) { diceLoop(state, rayes::bench::benchPatch()); }
void BM_DiceSubdivRegularBezierForm(benchmark::State& state) {
  static const Leaf l = leafOf(grid(), 14, true);
  diceLoop(state, *l.patch);
}
void BM_DiceSubdivRegularBfr(benchmark::State& state) {
  static const Leaf l = leafOf(grid(), 14, false);
  diceLoop(state, *l.patch);
}
void BM_DiceSubdivIrregularQuad(benchmark::State& state) {
  static const Leaf l = leafOf(cube(), 0);
  diceLoop(state, *l.patch);
}
void BM_DiceSubdivPentagonSubface(benchmark::State& state) {
  static const Leaf l = leafOf(prism(), 0);
  diceLoop(state, *l.patch);
}
void BM_DiceSubdivLoopSubquad(benchmark::State& state) {
  static const Leaf l = leafOf(octahedron(), 0);
  diceLoop(state, *l.patch);
}

BENCHMARK(BM_DiceBezier)->DenseRange(4, 8, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DiceSubdivRegularBezierForm)->DenseRange(4, 8, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DiceSubdivRegularBfr)->DenseRange(4, 8, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DiceSubdivIrregularQuad)->DenseRange(4, 8, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DiceSubdivPentagonSubface)->DenseRange(4, 8, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DiceSubdivLoopSubquad)->DenseRange(4, 8, 2)->Unit(benchmark::kMicrosecond);

// Patch::boundsOver on a border segment (what the DiceBuffer's crack-closure boxes ask for,
// about 8 * 2^m times per dicing): an irregular leaf (Bfr) and a regular one (Bézier hull).
void boundsLoop(benchmark::State& state, const Patch& patch) {
  int j = 0;
  for (auto _ : state) {
    const float t0 = float(j & 63) / 64.0f;
    benchmark::DoNotOptimize(patch.boundsOver(t0, t0 + 1.0f / 64.0f, 0.0f, 0.0f));
    ++j;
  }
}
void BM_BorderBoundsIrregular(benchmark::State& state) {
  static const Leaf l = leafOf(cube(), 0);
  boundsLoop(state, *l.patch);
}
void BM_BorderBoundsRegular(benchmark::State& state) {
  static const Leaf l = leafOf(grid(), 14, true);
  boundsLoop(state, *l.patch);
}
BENCHMARK(BM_BorderBoundsIrregular);
BENCHMARK(BM_BorderBoundsRegular);

// One Bfr surface set-up for an irregular face (what a dicing would pay per call, and per
// neighbour owning one of its edges, without the per-thread cache).
void BM_BfrSurfaceSetup(benchmark::State& state) {
  namespace Far = OpenSubdiv::Far;
  namespace Sdc = OpenSubdiv::Sdc;
  const SubdivMeshDesc d = cube();
  Far::TopologyDescriptor desc;
  desc.numVertices = 8;
  desc.numFaces = 6;
  desc.numVertsPerFace = d.faceSizes.data();
  desc.vertIndicesPerFace = d.faceVertices.data();
  using RF = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(RF::Create(desc, RF::Options(Sdc::SCHEME_CATMARK)));
  OpenSubdiv::Bfr::RefinerSurfaceFactory<> factory(*refiner);
  std::vector<float> pts;
  for (const Vec3& p : d.positions) pts.insert(pts.end(), {p.x, p.y, p.z});
  std::vector<float> patch;
  for (auto _ : state) {
    OpenSubdiv::Bfr::Surface<float> s;
    factory.InitVertexSurface(0, &s);
    patch.resize(size_t(s.GetNumPatchPoints()) * 3);
    s.PreparePatchPoints(pts.data(), 3, patch.data(), 3);
    benchmark::DoNotOptimize(patch.data());
  }
}
BENCHMARK(BM_BfrSurfaceSetup)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
