// The shipped creature (scenes/creature.obj, written by scenes/make_creature.py): a
// Catmull-Clark cage of several hundred quads with creases and extraordinary vertices. Its
// leaves' bounds hold the limit surface, its seams are bit-identical, rays aimed at the seams
// never slip through, its uv set is continuous across every edge its uv topology shares and
// jumps by one turn across its seam, and the scene that shows it loads.
#include <gtest/gtest.h>
#include <cstring>
#include <map>
#include "dicing/dice_buffer.h"
#include "geometry/subdiv_mesh.h"
#include "geometry/subdiv_patch.h"
#include "geometry/subdiv_uv.h"
#include "scene/obj_reader.h"
#include "scene/scene_loader.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

using test::Random;

struct Creature {
  SubdivMeshPtr mesh;
  std::vector<PatchPtr> patches;
};

const Creature& creature() {
  static const Creature c = [] {
    const ObjMesh obj = loadObj(RAYES_SOURCE_DIR "/scenes/creature.obj");
    Creature c;
    c.mesh = SubdivMesh::build(buildSubdivTopology(obj.mesh), obj.mesh.positions);
    c.patches = c.mesh->patches();
    return c;
  }();
  return c;
}

TEST(Creature, IsACreasedCatmullClarkCageOfSeveralHundredFaces) {
  const ObjMesh obj = loadObj(RAYES_SOURCE_DIR "/scenes/creature.obj");
  EXPECT_GE(obj.mesh.faceSizes.size(), 300u);
  EXPECT_GE(obj.mesh.creases.size(), 20u);
  const SubdivStats s = creature().mesh->stats();
  EXPECT_EQ(s.faces, int(obj.mesh.faceSizes.size()));
  EXPECT_EQ(s.leaves, s.faces);
  EXPECT_GT(s.regularFaces, 0);
  EXPECT_GT(s.irregularFaces, 0);
  std::printf("[ creature ] %d faces: %d regular, %d irregular\n", s.faces, s.regularFaces, s.irregularFaces);
}

// Every diced vertex (level 7) and 20000 random limit points per leaf lie in the leaf's
// bounds; normals are finite and non-zero everywhere, extraordinary vertices included.
TEST(Creature, BoundsHoldTheLimitSurfaceAndNormalsAreFinite) {
  const int m = 7, n = 1 << m;
  std::vector<Vec3> P(size_t(n + 1) * size_t(n + 1)), N(P.size());
  Random rng(17);
  long points = 0;
  for (const auto& patch : creature().patches) {
    const Box3 box = patch->bounds();
    patch->dice(m, P.data(), N.data());
    for (size_t k = 0; k < P.size(); ++k) {
      ASSERT_TRUE(box.contains(P[k]));
      ASSERT_TRUE(isFinite(N[k]));
      ASSERT_GT(maxComponent(vabs(N[k])), 0.0f);
    }
    for (int k = 0; k < 20000; ++k) {
      const SurfacePoint sp = patch->evaluate(rng.uniform(), rng.uniform());
      ASSERT_TRUE(box.contains(sp.p));
      ASSERT_TRUE(isFinite(sp.n));
    }
    points += long(P.size()) + 20000;
  }
  std::printf("[ creature ] %ld limit points inside their leaf bounds\n", points);
}

using Bits = std::array<uint32_t, 3>;
Bits bitsOf(Vec3 p) {
  Bits b;
  std::memcpy(b.data(), &p, sizeof p);
  return b;
}

// Grid index of the k-th vertex (0..n) going round the border counter-clockwise, side s
// (0: v=0, 1: u=1, 2: v=1, 3: u=0); k = 0..n-1 over the four sides visits each border vertex once.
std::pair<int, int> sideVertex(int s, int k, int n) {
  switch (s) {
    case 0: return {k, 0};
    case 1: return {n, k};
    case 2: return {n - k, n};
    default: return {0, n - k};
  }
}

TEST(Creature, SeamsAreBitwiseAndRaysAtThemNeverMiss) {
  const auto& patches = creature().patches;
  const int m = 4, n = 1 << m;
  // Border vertices of every leaf at level m, by bits.
  std::map<Bits, std::vector<int>> owners;
  std::vector<std::vector<Vec3>> grids(patches.size());
  std::vector<Vec3> N(size_t(n + 1) * size_t(n + 1));
  for (size_t l = 0; l < patches.size(); ++l) {
    grids[l].resize(N.size());
    patches[l]->dice(m, grids[l].data(), N.data());
    for (int s = 0; s < 4; ++s)
      for (int k = 0; k < n; ++k) {
        const auto [i, j] = sideVertex(s, k, n);
        auto& o = owners[bitsOf(grids[l][size_t(j * (n + 1) + i)])];
        if (o.empty() || o.back() != int(l)) o.push_back(int(l));
      }
  }
  int lonely = 0;
  for (const auto& [bits, leaves] : owners) lonely += leaves.size() < 2;
  EXPECT_EQ(lonely, 0) << "border vertices without a bitwise twin";

  // Rays at shared micro-edges: for border micro-edges (both ends shared with one other leaf),
  // aim at a point on the edge from directions transversal to all four micro-triangles next
  // to it (|cos| >= 0.2 to each, same side of each: a ray touching a sharp ridge only
  // grazes it), and check that one of the two dicings is hit no farther than the aimed point.
  auto quadAt = [&](const std::vector<Vec3>& g, int i0, int j0, int i1, int j1) {
    // The micro-quad of the border edge (i0,j0)-(i1,j1), as its two triangles' normals.
    int qx = std::min(i0, i1), qy = std::min(j0, j1);
    if (i0 == i1) qx = i0 == n ? n - 1 : 0;
    if (j0 == j1) qy = j0 == n ? n - 1 : 0;
    auto at = [&](int i, int j) { return g[size_t(j * (n + 1) + i)]; };
    const Vec3 p00 = at(qx, qy), p10 = at(qx + 1, qy), p01 = at(qx, qy + 1), p11 = at(qx + 1, qy + 1);
    return std::array<Vec3, 2>{normalize(cross(p10 - p00, p11 - p00)), normalize(cross(p11 - p00, p01 - p00))};
  };
  auto find = [&](const std::vector<Vec3>& g, Vec3 p) {
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        if (bitsOf(g[size_t(j * (n + 1) + i)]) == bitsOf(p)) return std::make_pair(i, j);
    return std::make_pair(-1, -1);
  };
  DiceBuffer a(m), b(m);
  Random rng(23);
  long rays = 0, misses = 0, skipped = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const int la = rng.below(int(patches.size())), s = rng.below(4), k = rng.below(n);
    const auto [i0, j0] = sideVertex(s, k, n);
    const auto [i1, j1] = sideVertex(s, k + 1, n);
    const Vec3 va = grids[size_t(la)][size_t(j0 * (n + 1) + i0)], vb = grids[size_t(la)][size_t(j1 * (n + 1) + i1)];
    const auto& oa = owners[bitsOf(va)];
    const auto& ob = owners[bitsOf(vb)];
    int lb = -1;
    for (int x : oa)
      if (x != la && std::find(ob.begin(), ob.end(), x) != ob.end()) lb = x;
    ASSERT_GE(lb, 0) << "a border micro-edge without a neighbour sharing both ends";
    const auto [bi0, bj0] = find(grids[size_t(lb)], va);
    const auto [bi1, bj1] = find(grids[size_t(lb)], vb);
    const auto na = quadAt(grids[size_t(la)], i0, j0, i1, j1), nb = quadAt(grids[size_t(lb)], bi0, bj0, bi1, bj1);
    a.dice(*patches[size_t(la)], m);
    b.dice(*patches[size_t(lb)], m);
    for (int r = 0; r < 8; ++r) {
      const float lambda = rng.uniform();
      const Vec3 p = va * (1.0f - lambda) + vb * lambda;
      const Vec3 w = rng.unitVector();
      bool pos = true, neg = true;
      for (const Vec3& nn : {na[0], na[1], nb[0], nb[1]}) {
        if (!(length(nn) > 0.5f)) continue;  // a zero-area triangle
        pos = pos && dot(w, nn) >= 0.2f;
        neg = neg && dot(w, nn) <= -0.2f;
      }
      if (!pos && !neg) {
        ++skipped;
        continue;
      }
      const Vec3 org = p + w * rng.uniform(0.05f, 2.0f);
      const Vec3 dir = p - org;
      GridHit h;
      const bool hit = a.intersect(org, dir, 0.0f, 1.0f + 1e-3f, m, h) || b.intersect(org, dir, 0.0f, 1.0f + 1e-3f, m, h);
      ++rays;
      if (!hit) {
        ++misses;
        ADD_FAILURE() << "miss at leaves " << la << "/" << lb << " point " << p.x << " " << p.y << " " << p.z;
      }
    }
  }
  EXPECT_EQ(misses, 0);
  EXPECT_GT(rays, 8000);
  std::printf("[ creature ] %ld rays at shared edges, %ld misses (%ld directions not transversal, skipped)\n", rays,
              misses, skipped);
}

// Every edge shared by two faces (all quads, so leaf = face), evaluated from both at 9 points:
// where both faces give the edge's ends the same uv values the two evaluations agree within the
// rounding of a Bfr blend (BfrFace::evaluationError's estimate: at most 64 patch points, weights'
// absolute sum 4, values within 1). Across the seam the two sides' s differ by one turn at the
// ends the seam splits (both ends of an edge along it, one end of an edge leaving its end
// points), and with linear interpolation (the default, "all") by the linear blend of the ends'
// differences in between; t agrees everywhere.
TEST(Creature, UvSetIsContinuousExceptAcrossItsSeam) {
  const ObjMesh obj = loadObj(RAYES_SOURCE_DIR "/scenes/creature.obj");
  ASSERT_EQ(obj.mesh.uvIndices.size(), obj.mesh.faceVertices.size());
  const SubdivUvSet uvs(buildSubdivTopology(obj.mesh));
  const float bound = 2 * gammaBound(128) * 4.0f;
  struct Side { int face, k; };
  std::map<std::pair<int, int>, std::vector<Side>> edges;
  for (int f = 0; f < int(obj.mesh.faceSizes.size()); ++f)
    for (int k = 0; k < 4; ++k) {
      const int a = obj.mesh.faceVertices[size_t(4 * f + k)], b = obj.mesh.faceVertices[size_t(4 * f + (k + 1) % 4)];
      edges[{std::min(a, b), std::max(a, b)}].push_back({f, k});
    }
  static const float corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  auto at = [&](Side sd, float x) {  // face sd.face's edge sd.k at x from its corner k
    const float* p = corner[sd.k];
    const float* q = corner[(sd.k + 1) % 4];
    float st[2], du[2], dv[2];
    uvs.evaluate(sd.face, p[0] + (q[0] - p[0]) * x, p[1] + (q[1] - p[1]) * x, st, du, dv);
    return std::array<float, 2>{st[0], st[1]};
  };
  auto uvIndex = [&](Side sd, int which) { return obj.mesh.uvIndices[size_t(4 * sd.face + (sd.k + which) % 4)]; };
  int seamEdges = 0, sharedEdges = 0;
  for (const auto& [e, sides] : edges) {
    ASSERT_EQ(sides.size(), 2u);
    const Side a = sides[0], b = sides[1];
    // b runs the edge the other way: its corner k is a's corner k + 1.
    const bool shared = uvIndex(a, 0) == uvIndex(b, 1) && uvIndex(a, 1) == uvIndex(b, 0);
    (shared ? sharedEdges : seamEdges)++;
    // The jump of s at a's corners k and k + 1 (0 where shared, a turn where split).
    const float jump0 = obj.mesh.uvs[size_t(uvIndex(b, 1))][0] - obj.mesh.uvs[size_t(uvIndex(a, 0))][0];
    const float jump1 = obj.mesh.uvs[size_t(uvIndex(b, 0))][0] - obj.mesh.uvs[size_t(uvIndex(a, 1))][0];
    if (!shared) EXPECT_GT(std::fabs(jump0) + std::fabs(jump1), 0.5f) << "seam edge " << e.first << "-" << e.second;
    for (int i = 0; i <= 8; ++i) {
      const float x = float(i) / 8;
      const auto pa = at(a, x), pb = at(b, 1 - x);
      EXPECT_NEAR(pb[0] - pa[0], (1 - x) * jump0 + x * jump1, bound) << "edge " << e.first << "-" << e.second;
      EXPECT_NEAR(pb[1], pa[1], bound) << "edge " << e.first << "-" << e.second;
    }
  }
  EXPECT_GT(seamEdges, 0);
  EXPECT_GT(sharedEdges, 10 * seamEdges);
}

TEST(Creature, SceneLoads) {
  const Scene s = loadScene(RAYES_SOURCE_DIR "/scenes/subdiv-creature.json");
  size_t subdiv = 0;
  for (size_t i = 0; i < s.leaves.size(); ++i) subdiv += std::strcmp(s.leaves.facts(i).kind, "subdiv") == 0;
  EXPECT_EQ(subdiv, creature().patches.size());
}

}  // namespace
}  // namespace rayes
