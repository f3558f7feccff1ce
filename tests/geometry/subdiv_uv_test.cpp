// Uv sets on subdivision meshes (geometry/subdiv_uv.h): (s, t) at the corners and bilinear in
// every face under "all" interpolation, the Jacobian against finite differences on every kind of
// leaf (quads, quad sub-faces of n-gons, Loop's triangle sub-quads), continuity across edges the
// uv topology shares (also along a crease) and the seam where it does not, each interpolation
// option reaching OpenSubdiv, and the bilinear scheme rendering the control mesh itself.
#include <gtest/gtest.h>
#include <cmath>
#include "core/box.h"
#include "geometry/subdiv_mesh.h"
#include "geometry/subdiv_uv.h"
#include "support/patch_test_util.h"
#include "support/subdiv_test_meshes.h"

namespace rayes {
namespace {

using test::Random;

// Rounding of one face-varying evaluation: a blend of at most kMaxPatchPoints patch points whose
// weights' absolute sum we take as at most 4 (as BfrFace::evaluationError for positions); the
// meshes here have at most 25 patch points per face.
constexpr int kMaxPatchPoints = 64;
float evaluationError(float magnitude) { return gammaBound(2 * kMaxPatchPoints) * 4.0f * magnitude; }

struct Uv {
  float s, t, dsdu, dtdu, dsdv, dtdv;
};

Uv eval(const SubdivUvSet& set, int leaf, float u, float v) {
  float st[2], du[2], dv[2];
  set.evaluate(leaf, u, v, st, du, dv);
  return {st[0], st[1], du[0], du[1], dv[0], dv[1]};
}

// An n x n grid of quads over [0, n]^2 (face (i, j) = index j n + i, its corners (i, j),
// (i+1, j), (i+1, j+1), (i, j+1) are the leaf's (0,0), (1,0), (1,1), (0,1)). One uv per vertex,
// (x, y) / n jittered so no interpolation is accidentally exact. seamColumn > 0: faces with
// i >= seamColumn read a second copy of the uvs shifted by (0.5, 0): a uv seam along
// x = seamColumn. creaseRow > 0: the edges along y = creaseRow are infinitely sharp.
SubdivMeshDesc uvGrid(int n, SubdivUvInterpolation interp, int seamColumn = 0, int creaseRow = 0) {
  SubdivMeshDesc d;
  d.uvInterpolation = interp;
  Random rng(3);
  const int nv = (n + 1) * (n + 1);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      d.positions.push_back({float(i), float(j), rng.uniform(-0.3f, 0.3f)});
      d.uvs.push_back({float(i) / float(n) + rng.uniform(-0.05f, 0.05f), float(j) / float(n) + rng.uniform(-0.05f, 0.05f)});
    }
  if (seamColumn > 0)
    for (int v = 0; v < nv; ++v) d.uvs.push_back({d.uvs[size_t(v)][0] + 0.5f, d.uvs[size_t(v)][1]});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      d.faceSizes.push_back(4);
      for (int v : {a, a + 1, a + n + 2, a + n + 1}) {
        d.faceVertices.push_back(v);
        d.uvIndices.push_back(seamColumn > 0 && i >= seamColumn ? v + nv : v);
      }
    }
  if (creaseRow > 0)
    for (int i = 0; i < n; ++i) d.creases.push_back({creaseRow * (n + 1) + i, creaseRow * (n + 1) + i + 1, 10.0f});
  return d;
}

// One uv per vertex: the vertex's (x, y).
SubdivMeshDesc withVertexUvs(SubdivMeshDesc d, SubdivUvInterpolation interp) {
  d.uvInterpolation = interp;
  for (const Vec3& p : d.positions) d.uvs.push_back({p.x, p.y});
  d.uvIndices = d.faceVertices;
  return d;
}

SubdivUvSet uvSetOf(const SubdivMeshDesc& d) { return SubdivUvSet(buildSubdivTopology(d)); }

const SubdivUvInterpolation kAllOptions[] = {
    SubdivUvInterpolation::None,         SubdivUvInterpolation::CornersOnly, SubdivUvInterpolation::CornersPlus1,
    SubdivUvInterpolation::CornersPlus2, SubdivUvInterpolation::Boundaries,  SubdivUvInterpolation::All};

TEST(SubdivUv, LinearAllIsBilinearInTheCornerUvs) {
  const int n = 4;
  const SubdivMeshDesc d = uvGrid(n, SubdivUvInterpolation::All);
  const SubdivUvSet set = uvSetOf(d);
  ASSERT_EQ(set.leafCount(), n * n);
  const float tol = evaluationError(1.1f);
  Random rng(5);
  for (int f = 0; f < n * n; ++f) {
    std::array<float, 2> c[4];  // the leaf's (0,0), (1,0), (1,1), (0,1)
    for (int k = 0; k < 4; ++k) c[k] = d.uvs[size_t(d.uvIndices[size_t(4 * f + k)])];
    for (int k = 0; k < 24; ++k) {
      const float u = k < 4 ? float((k == 1) || (k == 2)) : rng.uniform(), v = k < 4 ? float(k >= 2) : rng.uniform();
      const Uv got = eval(set, f, u, v);
      for (int x = 0; x < 2; ++x) {
        const float want = (1 - u) * (1 - v) * c[0][x] + u * (1 - v) * c[1][x] + u * v * c[2][x] + (1 - u) * v * c[3][x];
        const float du = (1 - v) * (c[1][x] - c[0][x]) + v * (c[2][x] - c[3][x]);
        const float dv = (1 - u) * (c[3][x] - c[0][x]) + u * (c[2][x] - c[1][x]);
        EXPECT_NEAR(x ? got.t : got.s, want, tol) << "face " << f << " at " << u << ", " << v;
        // d/du of a blend of values within 1.1 of each other: rounding of the same order, times
        // the derivative weights' sum (2).
        EXPECT_NEAR(x ? got.dtdu : got.dsdu, du, 2 * tol) << "face " << f;
        EXPECT_NEAR(x ? got.dtdv : got.dsdv, dv, 2 * tol) << "face " << f;
      }
    }
  }
}

// Central differences with steps h and h/2 (exact in float): the smaller step's truncation error
// is about a third of their difference (Richardson; the next term is O(h^4)), so |D(h/2) - J|
// stays within that difference plus the rounding of the differences, 2 e / h.
void expectJacobianMatchesDifferences(const SubdivMeshDesc& d, const char* what) {
  const SubdivUvSet set = uvSetOf(d);
  float magnitude = 0;
  for (const auto& st : d.uvs) magnitude = std::max({magnitude, std::fabs(st[0]), std::fabs(st[1])});
  const float e = evaluationError(magnitude);
  Random rng(9);
  const float h = 1.0f / 64;
  for (int leaf = 0; leaf < set.leafCount(); ++leaf)
    for (int k = 0; k < 8; ++k) {
      const float u = rng.uniform(0.1f, 0.9f), v = rng.uniform(0.1f, 0.9f);
      const Uv j = eval(set, leaf, u, v);
      auto diff = [&](float step, bool alongU) {
        const Uv a = alongU ? eval(set, leaf, u + step, v) : eval(set, leaf, u, v + step);
        const Uv b = alongU ? eval(set, leaf, u - step, v) : eval(set, leaf, u, v - step);
        return std::array<float, 2>{(a.s - b.s) / (2 * step), (a.t - b.t) / (2 * step)};
      };
      for (bool alongU : {true, false}) {
        const auto coarse = diff(h, alongU), fine = diff(h / 2, alongU);
        const float jac[2] = {alongU ? j.dsdu : j.dsdv, alongU ? j.dtdu : j.dtdv};
        for (int x = 0; x < 2; ++x)
          EXPECT_NEAR(fine[x], jac[x], std::fabs(coarse[x] - fine[x]) + 2 * e / (h / 2))
              << what << ": leaf " << leaf << " at " << u << ", " << v << (alongU ? " d/du" : " d/dv") << " of "
              << (x ? "t" : "s");
      }
    }
}

TEST(SubdivUv, JacobianMatchesFiniteDifferences) {
  expectJacobianMatchesDifferences(uvGrid(4, SubdivUvInterpolation::None), "smooth uvs on quads");
  expectJacobianMatchesDifferences(uvGrid(4, SubdivUvInterpolation::All), "bilinear uvs on quads");
  expectJacobianMatchesDifferences(withVertexUvs(test::pentagonalPrism(), SubdivUvInterpolation::All),
                                   "quad sub-faces of pentagons");
  expectJacobianMatchesDifferences(withVertexUvs(test::octahedron(), SubdivUvInterpolation::All),
                                   "Loop's triangle sub-quads");
}

// Every interior edge of the grid, evaluated from both faces at the same points. `seamColumn`:
// the edges along x = seamColumn are a uv seam, all others shared by the uv topology. With any
// linear rule at boundaries (every option but none) the seam's two sides interpolate the same
// boundary values (one side's shifted by 0.5, and every rule is translation invariant), so they
// differ by exactly the shift. With none, OpenSubdiv smooths each side's boundary on its own
// (where the seam meets the mesh's boundary the two sides' neighbours differ), so the sides
// only differ.
void expectContinuousExceptAtTheSeam(const SubdivMeshDesc& d, int n, int seamColumn, const char* what) {
  const SubdivUvSet set = uvSetOf(d);
  const float e = evaluationError(1.6f);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      for (int k = 0; k <= 8; ++k) {
        const float p = float(k) / 8;
        if (i > 0) {  // the vertical edge x = i between faces (i-1, j) and (i, j)
          const Uv left = eval(set, j * n + i - 1, 1, p), right = eval(set, j * n + i, 0, p);
          const float shift = i == seamColumn ? 0.5f : 0.0f;
          if (shift != 0 && d.uvInterpolation == SubdivUvInterpolation::None)
            EXPECT_GT(std::fabs(right.s - left.s), 2 * e) << what << ": seam x = " << i << ", y = " << float(j) + p;
          else
            EXPECT_NEAR(right.s - left.s, shift, 2 * e) << what << ": edge x = " << i << ", y = " << float(j) + p;
          if (shift == 0 || d.uvInterpolation != SubdivUvInterpolation::None)
            EXPECT_NEAR(right.t - left.t, 0.0f, 2 * e) << what << ": edge x = " << i << ", y = " << float(j) + p;
        }
        if (j > 0) {  // the horizontal edge y = j between faces (i, j-1) and (i, j)
          const Uv below = eval(set, (j - 1) * n + i, p, 1), above = eval(set, j * n + i, p, 0);
          EXPECT_NEAR(above.s - below.s, 0.0f, 2 * e) << what << ": edge y = " << j << ", x = " << float(i) + p;
          EXPECT_NEAR(above.t - below.t, 0.0f, 2 * e) << what << ": edge y = " << j << ", x = " << float(i) + p;
        }
      }
}

TEST(SubdivUv, ContinuousWhereTheUvTopologyIsAndSeamedWhereItIsNot) {
  for (const SubdivUvInterpolation interp : kAllOptions) {
    const std::string what = "interpolation " + std::to_string(int(interp));
    expectContinuousExceptAtTheSeam(uvGrid(4, interp, 2), 4, 2, what.c_str());
    expectContinuousExceptAtTheSeam(uvGrid(4, interp, 2, 2), 4, 2, (what + ", crease along y = 2").c_str());
  }
}

TEST(SubdivUv, InterpolationOptionsReachOpenSubdiv) {
  // Smooth uvs (none) are not bilinear inside a face whose uvs are not affine; all is.
  const SubdivUvSet smooth = uvSetOf(uvGrid(4, SubdivUvInterpolation::None));
  const SubdivUvSet linear = uvSetOf(uvGrid(4, SubdivUvInterpolation::All));
  const Uv a = eval(smooth, 5, 0.5f, 0.5f), b = eval(linear, 5, 0.5f, 0.5f);
  EXPECT_GT(std::fabs(a.s - b.s) + std::fabs(a.t - b.t), 4 * evaluationError(1.1f));
  // On the grid's boundary, the corners-only rule keeps corner uvs where none smooths them.
  const SubdivMeshDesc cornersOnly = uvGrid(4, SubdivUvInterpolation::CornersOnly);
  const Uv corner = eval(uvSetOf(cornersOnly), 0, 0, 0);
  EXPECT_NEAR(corner.s, cornersOnly.uvs[0][0], evaluationError(1.1f));
  EXPECT_NEAR(corner.t, cornersOnly.uvs[0][1], evaluationError(1.1f));
}

TEST(SubdivUv, BadUvSetsNameTheItem) {
  using Item = SubdivInputError::Item;
  auto itemOf = [](const SubdivMeshDesc& d) {
    try {
      buildSubdivTopology(d);
    } catch (const SubdivInputError& e) {
      return std::make_pair(e.item, e.index);
    }
    return std::make_pair(Item::Mesh, -2);
  };
  SubdivMeshDesc d = withVertexUvs(test::cube(), SubdivUvInterpolation::All);
  d.uvs[3][1] = std::nanf("");
  EXPECT_EQ(itemOf(d), std::make_pair(Item::Uv, 3));
  d = withVertexUvs(test::cube(), SubdivUvInterpolation::All);
  d.uvs[5][0] = INFINITY;
  EXPECT_EQ(itemOf(d), std::make_pair(Item::Uv, 5));
  d = withVertexUvs(test::cube(), SubdivUvInterpolation::All);
  d.uvIndices[9] = 8;  // face 2's second corner; 8 values
  EXPECT_EQ(itemOf(d), std::make_pair(Item::UvFace, 2));
  d.uvIndices[9] = -1;
  EXPECT_EQ(itemOf(d), std::make_pair(Item::UvFace, 2));
  d = withVertexUvs(test::cube(), SubdivUvInterpolation::All);
  d.uvIndices.pop_back();
  EXPECT_EQ(itemOf(d), std::make_pair(Item::Mesh, -1));
  d = test::cube();
  d.uvIndices = d.faceVertices;  // indices without values
  EXPECT_EQ(itemOf(d), std::make_pair(Item::Mesh, -1));
  EXPECT_FALSE(hasUvSet(*buildSubdivTopology(test::cube())));
  EXPECT_THROW(SubdivUvSet(buildSubdivTopology(test::cube())), std::invalid_argument);
}

TEST(SubdivBilinearScheme, IsTheControlMeshItself) {
  // A plain polygon mesh: every point of a face lies on it, and a quad's point is the bilinear
  // blend of its corners (up to the rounding of Bfr's bilinear blend of 4 points).
  SubdivMeshDesc d = test::pentagonalPrism();
  d.scheme = SubdivScheme::Bilinear;
  const auto mesh = SubdivMesh::build(buildSubdivTopology(d), d.positions);
  const float tol = gammaBound(8) * 2.0f;  // |positions| <= 1.2
  Random rng(13);
  for (int leaf = 0; leaf < mesh->leafCount(); ++leaf) {
    const auto [f, sub] = mesh->leafFace(leaf);
    for (int k = 0; k < 16; ++k) {
      const float u = rng.uniform(), v = rng.uniform();
      const Vec3 p = mesh->evaluateLeaf(leaf, u, v).p;
      if (f < 2) {  // a pentagon's sub-face: on the cap's plane z = -1 or 1, inside the unit disc
        EXPECT_NEAR(p.z, f == 0 ? -1.0f : 1.0f, tol) << "leaf " << leaf;
        EXPECT_LE(std::hypot(p.x, p.y), 1.0f + tol) << "leaf " << leaf;
      } else {
        const int o = 10 + 4 * (f - 2);
        const Vec3 c0 = d.positions[size_t(d.faceVertices[size_t(o)])], c1 = d.positions[size_t(d.faceVertices[size_t(o + 1)])];
        const Vec3 c2 = d.positions[size_t(d.faceVertices[size_t(o + 2)])], c3 = d.positions[size_t(d.faceVertices[size_t(o + 3)])];
        const Vec3 want = c0 * ((1 - u) * (1 - v)) + c1 * (u * (1 - v)) + c2 * (u * v) + c3 * ((1 - u) * v);
        EXPECT_LE(maxComponent(vabs(p - want)), tol) << "leaf " << leaf << " at " << u << ", " << v;
      }
    }
  }
}

}  // namespace
}  // namespace rayes
