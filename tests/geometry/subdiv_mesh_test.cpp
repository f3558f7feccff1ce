// Subdivision surfaces (geometry/subdiv_mesh.h): limit points against OpenSubdiv's own
// evaluation and an analytic limit, dice() against evaluate() bit for bit, conservative
// bounds, normals at extraordinary vertices, Loop, creases, holes, n-gons, bad topology.
#include <gtest/gtest.h>
#include <cmath>
#include <cstring>
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include "geometry/subdiv_mesh.h"
#include "geometry/subdiv_patch.h"
#include "support/patch_test_util.h"
#include "support/subdiv_test_meshes.h"

namespace rayes {
namespace {

using test::Random;
using test::sameBits;
using test::cube;
using test::pentagonalPrism;
using test::octahedron;

// An n x n open grid of quads with a wavy height: interior faces are regular.
SubdivMeshDesc wavyGrid(int n) {
  SubdivMeshDesc d;
  Random rng(7);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) d.positions.push_back({float(i), float(j), rng.uniform(-0.5f, 0.5f)});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      d.faceSizes.push_back(4);
      for (int v : {a, a + 1, a + n + 2, a + n + 1}) d.faceVertices.push_back(v);
    }
  return d;
}

struct Built {
  SubdivMeshPtr mesh;
  std::vector<PatchPtr> patches;
};

Built build(const SubdivMeshDesc& d) {
  Built b;
  b.mesh = SubdivMesh::build(buildSubdivTopology(d), d.positions);
  b.patches = b.mesh->patches();
  return b;
}

// OpenSubdiv's own evaluation, independent of ours: a fresh refiner and factory, in double.
class Reference {
 public:
  explicit Reference(const SubdivMeshDesc& d) : d_(d) {
    namespace Far = OpenSubdiv::Far;
    namespace Sdc = OpenSubdiv::Sdc;
    Far::TopologyDescriptor desc;
    desc.numVertices = int(d.positions.size());
    desc.numFaces = int(d.faceSizes.size());
    desc.numVertsPerFace = d.faceSizes.data();
    desc.vertIndicesPerFace = d.faceVertices.data();
    for (const auto& c : d.creases) {
      creaseVerts_.push_back(c.v0);
      creaseVerts_.push_back(c.v1);
      creaseW_.push_back(c.sharpness);
    }
    desc.numCreases = int(d.creases.size());
    desc.creaseVertexIndexPairs = creaseVerts_.data();
    desc.creaseWeights = creaseW_.data();
    desc.numHoles = int(d.holes.size());
    desc.holeIndices = d.holes.data();
    Sdc::Options o;
    o.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
    scheme_ = d.scheme == SubdivScheme::Loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK;
    using RF = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    refiner_.reset(RF::Create(desc, RF::Options(scheme_, o)));
    factory_ = std::make_unique<OpenSubdiv::Bfr::RefinerSurfaceFactory<>>(*refiner_);
    for (const Vec3& p : d.positions)
      for (int k = 0; k < 3; ++k) points_.push_back(p[k]);
  }

  // Limit position of face f at face coordinates uv.
  Vec3 at(int f, const double uv[2]) const {
    OpenSubdiv::Bfr::Surface<double> s;
    EXPECT_TRUE(factory_->InitVertexSurface(f, &s));
    std::vector<double> pts(size_t(s.GetNumPatchPoints()) * 3);
    s.PreparePatchPoints(points_.data(), 3, pts.data(), 3);
    double P[3];
    s.Evaluate(uv, pts.data(), 3, P);
    return {float(P[0]), float(P[1]), float(P[2])};
  }

  // Leaf (s, t) of (face, sub) -> face coordinates, written independently of the library.
  Vec3 atLeaf(int f, int sub, double s, double t) const {
    double uv[2] = {s, t};
    const int n = d_.faceSizes[size_t(f)];
    if (d_.scheme == SubdivScheme::Loop) {
      const double V[3][2] = {{0, 0}, {1, 0}, {0, 1}};
      const int a = sub, b = (sub + 1) % 3, c = (sub + 2) % 3;
      for (int x = 0; x < 2; ++x) {
        const double c0 = V[a][x], c1 = 0.5 * (V[a][x] + V[b][x]), c2 = 1.0 / 3.0, c3 = 0.5 * (V[a][x] + V[c][x]);
        uv[x] = (1 - s) * (1 - t) * c0 + s * (1 - t) * c1 + s * t * c2 + (1 - s) * t * c3;
      }
    } else if (sub >= 0) {
      OpenSubdiv::Bfr::Parameterization p(scheme_, n);
      const double st[2] = {s, t};
      p.ConvertNormalizedSubFaceToCoord(sub, st, uv);
    }
    return at(f, uv);
  }

 private:
  SubdivMeshDesc d_;
  OpenSubdiv::Sdc::SchemeType scheme_;
  std::vector<int> creaseVerts_;
  std::vector<float> creaseW_;
  std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> refiner_;
  std::unique_ptr<OpenSubdiv::Bfr::RefinerSurfaceFactory<>> factory_;
  std::vector<double> points_;
};

float maxDist(Vec3 a, Vec3 b) { return maxComponent(vabs(a - b)); }

// Our evaluation against OpenSubdiv's at every leaf's corners and at random points.
void expectMatchesReference(const SubdivMeshDesc& d, float tol, int randomPerLeaf = 50) {
  const Built b = build(d);
  const Reference ref(d);
  Random rng(11);
  for (int leaf = 0; leaf < b.mesh->leafCount(); ++leaf) {
    const auto [f, sub] = b.mesh->leafFace(leaf);
    for (int k = 0; k < 4 + randomPerLeaf; ++k) {
      const float s = k < 4 ? float(k & 1) : rng.uniform(), t = k < 4 ? float(k >> 1) : rng.uniform();
      const Vec3 ours = b.patches[size_t(leaf)]->evaluate(s, t).p;
      const Vec3 theirs = ref.atLeaf(f, sub, s, t);
      ASSERT_LE(maxDist(ours, theirs), tol) << "leaf " << leaf << " (face " << f << ", sub " << sub << ") at " << s
                                            << ", " << t;
    }
  }
}

TEST(SubdivMesh, CubeCornersHaveTheAnalyticLimit) {
  // Catmull-Clark limit of a valence-n vertex: (n^2 V + 4 sum E + sum F) / (n (n + 5)); for a
  // cube corner (n = 3) this is V / 2.
  const Built b = build(cube());
  EXPECT_EQ(b.patches.size(), 6u);
  for (int v = 0; v < 8; ++v) {
    const Vec3 p = cube().positions[size_t(v)];
    EXPECT_LE(maxDist(b.mesh->vertexLimit(v), p * 0.5f), 1e-6f) << v;
  }
  for (const auto& patch : b.patches)
    for (int c = 0; c < 4; ++c) {
      const Vec3 p = patch->evaluate(float(c & 1), float(c >> 1)).p;
      EXPECT_NEAR(std::fabs(p.x), 0.5f, 1e-6f);
      EXPECT_NEAR(std::fabs(p.y), 0.5f, 1e-6f);
      EXPECT_NEAR(std::fabs(p.z), 0.5f, 1e-6f);
    }
}

TEST(SubdivMesh, MatchesOpenSubdivEvaluation) {
  expectMatchesReference(cube(), 2e-6f);
  expectMatchesReference(pentagonalPrism(), 2e-6f);
  expectMatchesReference(octahedron(), 2e-6f);
  SubdivMeshDesc creased = cube();
  creased.creases = {{0, 2, 10.0f}, {2, 3, 2.5f}, {3, 1, 0.5f}};
  expectMatchesReference(creased, 2e-6f);
}

TEST(SubdivMesh, RegularFacesUseTheBezierFormAndMatchOpenSubdiv) {
  const SubdivMeshDesc grid = wavyGrid(6);
  const Built b = build(grid);
  const SubdivStats st = b.mesh->stats();
  EXPECT_EQ(st.regularFaces, 16);  // the 4 x 4 interior faces
  EXPECT_EQ(st.irregularFaces, 20);
  expectMatchesReference(grid, 1e-5f, 200);
}

TEST(SubdivMesh, DiceEqualsEvaluateBitForBit) {
  for (const SubdivMeshDesc& d : {cube(), pentagonalPrism(), octahedron(), wavyGrid(4)}) {
    const Built b = build(d);
    for (int level = 0; level <= 4; ++level) {
      const int n = 1 << level;
      std::vector<Vec3> P(size_t(n + 1) * size_t(n + 1)), N(P.size());
      for (const auto& patch : b.patches) {
        patch->dice(level, P.data(), N.data());
        for (int j = 0; j <= n; ++j)
          for (int i = 0; i <= n; ++i) {
            const SurfacePoint sp = patch->evaluate(float(i) / float(n), float(j) / float(n));
            ASSERT_TRUE(sameBits(sp.p, P[size_t(j * (n + 1) + i)])) << level << " " << i << " " << j;
            ASSERT_TRUE(sameBits(sp.n, N[size_t(j * (n + 1) + i)])) << level << " " << i << " " << j;
          }
      }
    }
  }
}

// Every border vertex of every leaf of a closed mesh must reappear, bit for bit, on the border
// of another leaf: the canonical evaluation (owner faces, vertex table) makes seams exact.
// A sub-face of a non-quad covers half of each of its mesh edges, so along an edge between a
// quad and a non-quad the sub-face's level-m vertices are the quad's level-(m+1) vertices:
// the twin may be at level m or m+1. (Slits between such T-junctions, like those between
// neighbours diced at different levels, are closed by the dicing's border boxes.)
void expectBitwiseSeams(const SubdivMeshDesc& d, int level) {
  const Built b = build(d);
  std::vector<std::pair<std::array<uint32_t, 3>, int>> border[2];  // (bits, leaf) at m, m+1
  for (int l = 0; l < 2; ++l) {
    const int n = 1 << (level + l);
    std::vector<Vec3> P(size_t(n + 1) * size_t(n + 1)), N(P.size());
    for (int leaf = 0; leaf < int(b.patches.size()); ++leaf) {
      b.patches[size_t(leaf)]->dice(level + l, P.data(), N.data());
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
          if (i != 0 && j != 0 && i != n && j != n) continue;
          const Vec3 p = P[size_t(j * (n + 1) + i)];
          std::array<uint32_t, 3> bits;
          std::memcpy(bits.data(), &p, sizeof p);
          border[l].push_back({bits, leaf});
        }
    }
    std::sort(border[l].begin(), border[l].end());
  }
  auto twinIn = [&](const auto& list, const std::array<uint32_t, 3>& bits, int leaf) {
    auto it = std::lower_bound(list.begin(), list.end(), std::make_pair(bits, -1));
    for (; it != list.end() && it->first == bits; ++it)
      if (it->second != leaf) return true;
    return false;
  };
  int lonely = 0, viaFiner = 0;
  for (const auto& [bits, leaf] : border[0]) {
    if (twinIn(border[0], bits, leaf)) continue;
    if (twinIn(border[1], bits, leaf)) ++viaFiner;
    else ++lonely;
  }
  EXPECT_EQ(lonely, 0) << "border vertices without a bitwise twin on another leaf, level " << level;
  if (d.scheme == SubdivScheme::Loop || std::all_of(d.faceSizes.begin(), d.faceSizes.end(), [](int s) { return s == 4; })) {
    EXPECT_EQ(viaFiner, 0) << "uniform meshes have their twins at the same level";
  }
}

TEST(SubdivMesh, SeamsAreBitwiseIdentical) {
  for (int level : {1, 3, 5}) {
    expectBitwiseSeams(cube(), level);
    expectBitwiseSeams(pentagonalPrism(), level);
    expectBitwiseSeams(octahedron(), level);
    SubdivMeshDesc creased = pentagonalPrism();
    creased.creases = {{0, 1, 10.0f}, {5, 6, 1.5f}};
    expectBitwiseSeams(creased, level);
  }
}

// Bounds contain the limit surface: random points and every diced vertex.
void expectBoundsContain(const SubdivMeshDesc& d, int randomPerLeaf) {
  const Built b = build(d);
  Random rng(3);
  const int level = 6, n = 1 << level;
  std::vector<Vec3> P(size_t(n + 1) * size_t(n + 1)), N(P.size());
  for (const auto& patch : b.patches) {
    const Box3 box = patch->bounds();
    for (int k = 0; k < randomPerLeaf; ++k) {
      const Vec3 p = patch->evaluate(rng.uniform(), rng.uniform()).p;
      ASSERT_TRUE(box.contains(p));
    }
    patch->dice(level, P.data(), N.data());
    for (const Vec3& p : P) ASSERT_TRUE(box.contains(p));
    // boundsOver a random rectangle contains the points inside it.
    for (int r = 0; r < 20; ++r) {
      float u0 = rng.uniform(), u1 = rng.uniform(), v0 = rng.uniform(), v1 = rng.uniform();
      if (u0 > u1) std::swap(u0, u1);
      if (v0 > v1) std::swap(v0, v1);
      const Box3 sub = patch->boundsOver(u0, u1, v0, v1);
      EXPECT_TRUE(box.contains(sub) || !sub.empty());
      for (int k = 0; k < 50; ++k) {
        const Vec3 p = patch->evaluate(u0 + (u1 - u0) * rng.uniform(), v0 + (v1 - v0) * rng.uniform()).p;
        ASSERT_TRUE(sub.contains(p));
      }
    }
    // Degenerate rectangles on the borders (the dicing's crack-closure boxes): they hold the
    // border points, which are the canonical (owner-evaluated) ones, at every dyadic level.
    for (int level = 0; level <= 6; ++level) {
      const int segs = 1 << level;
      for (int side = 0; side < 4; ++side)
        for (int j = 0; j < segs; ++j) {
          const float t0 = float(j) / float(segs), t1 = float(j + 1) / float(segs), c = float(side & 1);
          const Box3 sub = side < 2 ? patch->boundsOver(t0, t1, c, c) : patch->boundsOver(c, c, t0, t1);
          for (int k = 0; k <= 16; ++k) {
            const float t = t0 + (t1 - t0) * float(k) / 16.0f;
            const Vec3 p = (side < 2 ? patch->evaluate(t, c) : patch->evaluate(c, t)).p;
            ASSERT_TRUE(sub.contains(p)) << "level " << level << " side " << side << " segment " << j;
          }
        }
    }
  }
}

TEST(SubdivMesh, BoundsContainTheLimitSurface) {
  expectBoundsContain(cube(), 100000);
  expectBoundsContain(pentagonalPrism(), 20000);
  expectBoundsContain(octahedron(), 20000);
  expectBoundsContain(wavyGrid(5), 20000);
}

TEST(SubdivMesh, CubeLimitSurfaceIsInsideTheCube) {
  const Built b = build(cube());
  Random rng(5);
  for (const auto& patch : b.patches)
    for (int k = 0; k < 20000; ++k) {
      const Vec3 p = patch->evaluate(rng.uniform(), rng.uniform()).p;
      ASSERT_LE(maxComponent(vabs(p)), 1.0f);
      ASSERT_GE(maxComponent(vabs(p)), 0.5f);  // and outside the cube of the corner limits' box
    }
}

TEST(SubdivMesh, NormalsAreFiniteAndOutwardAtExtraordinaryVertices) {
  for (const SubdivMeshDesc& d : {cube(), pentagonalPrism(), octahedron()}) {
    const Built b = build(d);
    for (const auto& patch : b.patches)
      for (int level : {0, 3}) {
        const int n = 1 << level;
        std::vector<Vec3> P(size_t(n + 1) * size_t(n + 1)), N(P.size());
        patch->dice(level, P.data(), N.data());
        for (size_t k = 0; k < P.size(); ++k) {
          ASSERT_TRUE(isFinite(N[k]));
          ASSERT_GT(length(N[k]), 0.0f);
          // Convex, centred at the origin: the normal points away from it.
          EXPECT_GT(dot(normalize(N[k]), normalize(P[k])), 0.0f) << patch->kind();
        }
      }
  }
}

TEST(SubdivMesh, LoopOnTrianglesGivesThreeLeavesPerTriangle) {
  const Built b = build(octahedron());
  EXPECT_EQ(b.patches.size(), 24u);
  // Symmetric: every vertex's limit is at the same distance from the centre.
  const float r = length(b.mesh->vertexLimit(0));
  for (int v = 1; v < 6; ++v) EXPECT_NEAR(length(b.mesh->vertexLimit(v)), r, 1e-6f);
  EXPECT_LT(r, 1.0f);
  EXPECT_STREQ(b.patches[0]->kind(), "subdiv");
}

TEST(SubdivMesh, HolesHaveNoLeaves) {
  SubdivMeshDesc d = cube();
  d.holes = {2};
  const Built b = build(d);
  EXPECT_EQ(b.patches.size(), 5u);
  EXPECT_EQ(b.mesh->stats().facesWithoutLimit, 1);
}

TEST(SubdivMesh, InfinitelySharpCreaseIsAnEdgeOfTheCage) {
  // Infinitely sharp creases around the rim of the z = -1 face: the rim's limit curve is the
  // uniform B-spline of its four corners, which lies in the plane z = -1.
  SubdivMeshDesc d = cube();
  d.creases = {{0, 1, 10.0f}, {1, 3, 10.0f}, {3, 2, 10.0f}, {2, 0, 10.0f}};
  const Built b = build(d);
  // Vertices 0..3 are now crease vertices (two sharp edges): their limit lies in z = -1.
  for (int v = 0; v < 4; ++v) EXPECT_NEAR(b.mesh->vertexLimit(v).z, -1.0f, 1e-6f);
  for (const auto& patch : b.patches) {
    for (int k = 0; k <= 8; ++k) {
      for (int side = 0; side < 4; ++side) {
        const float t = float(k) / 8.0f;
        const Vec3 p = patch->evaluate(side < 2 ? t : float(side & 1), side < 2 ? float(side) : t).p;
        if (std::fabs(p.z + 1.0f) < 1e-3f) {
          EXPECT_NEAR(p.z, -1.0f, 1e-6f);  // a point of the rim
        }
      }
    }
  }
}

TEST(SubdivMesh, BadTopologyNamesTheItem) {
  auto itemOf = [](const SubdivMeshDesc& d) {
    try {
      buildSubdivTopology(d);
    } catch (const SubdivInputError& e) {
      return std::make_pair(int(e.item), e.index);
    }
    return std::make_pair(-1, -1);
  };
  using Item = SubdivInputError::Item;
  SubdivMeshDesc d = cube();
  d.faceVertices[5] = 8;
  EXPECT_EQ(itemOf(d), std::make_pair(int(Item::Face), 1));
  d = cube();
  d.faceVertices[5] = d.faceVertices[4];
  EXPECT_EQ(itemOf(d), std::make_pair(int(Item::Face), 1));
  d = cube();
  d.creases = {{0, 1, 1.0f}, {0, 7, 1.0f}};  // 0-7 is a diagonal, not an edge
  EXPECT_EQ(itemOf(d), std::make_pair(int(Item::Crease), 1));
  d = cube();
  d.scheme = SubdivScheme::Loop;
  EXPECT_EQ(itemOf(d), std::make_pair(int(Item::Face), 0));
  d = cube();
  d.holes = {6};
  EXPECT_EQ(itemOf(d), std::make_pair(int(Item::Hole), 0));
  d = cube();
  d.corners = {{3, -1.0f}};
  EXPECT_EQ(itemOf(d), std::make_pair(int(Item::Corner), 0));
}

// OpenSubdiv 3.5's Bfr reads out of bounds on a creased mesh with a non-manifold edge (the
// fuzzer's case, reduced: a quad, the same quad reversed, and a third face on two of its
// edges). Such a mesh is refused by name; either half of the pair alone still builds.
TEST(SubdivMesh, CreasesOnANonManifoldMeshAreRefusedAndEitherAloneBuilds) {
  SubdivMeshDesc d;
  d.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}};
  d.faceSizes = {4, 4, 4};
  d.faceVertices = {0, 1, 2, 3, 0, 1, 2, 4, 3, 2, 1, 0};
  d.creases = {{2, 3, 3.0f}};
  try {
    buildSubdivTopology(d);
    ADD_FAILURE() << "a creased non-manifold mesh was accepted";
  } catch (const SubdivInputError& e) {
    EXPECT_EQ(int(e.item), int(SubdivInputError::Item::Face));
    EXPECT_EQ(e.index, 1);  // its edge 0-1 is the first to be run twice in one direction
    EXPECT_NE(std::string(e.what()).find("manifold"), std::string::npos) << e.what();
  }
  d.creases.clear();
  EXPECT_GT(SubdivMesh::build(buildSubdivTopology(d), d.positions)->patches().size(), 0u);

  // Closed and manifold, with a valence-2 vertex (1: its two faces share both its edges) and
  // every edge creased: Bfr's other overlapping-faces case, which it handles.
  SubdivMeshDesc m;
  m.positions = d.positions;
  m.faceSizes = {4, 4, 3, 3};
  m.faceVertices = {0, 1, 2, 3, 2, 1, 0, 4, 3, 2, 4, 0, 3, 4};
  for (auto [a, b] : {std::pair{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 4}, {2, 4}, {3, 4}}) m.creases.push_back({a, b, 3.0f});
  EXPECT_GT(SubdivMesh::build(buildSubdivTopology(m), m.positions)->patches().size(), 0u);
}

}  // namespace
}  // namespace rayes
