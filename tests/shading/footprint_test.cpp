// The ray's footprint at a hit (shading/footprint.h): the cone's ellipse on the tangent plane
// (minor axis w along n x d, major w / cos θ along d's projection, the stretch capped), its axes
// in the patch parameters by least squares against dP/du, dP/dv, and through a uv set's
// Jacobian; finite for grazing rays, degenerate Jacobians, zero and huge widths.
#include <cmath>
#include <numbers>
#include <gtest/gtest.h>
#include "shading/footprint.h"

namespace rayes {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

bool finiteQuery(const TexturePoint& p) {
  for (float x : {p.x, p.y, p.dxA, p.dyA, p.dxB, p.dyB})
    if (!std::isfinite(x)) return false;
  return true;
}

TEST(Footprint, AtNormalIncidenceTheAxesAreTwoOrthogonalWidths) {
  Vec3 A, B;
  footprintAxes(Vec3{0, 0, -3}, Vec3{0, 0, 1}, 0.5f, A, B);
  EXPECT_NEAR(length(A), 0.5f, 1e-6f);
  EXPECT_NEAR(length(B), 0.5f, 1e-6f);
  EXPECT_NEAR(dot(A, B), 0.0f, 1e-6f);
  EXPECT_NEAR(A.z, 0.0f, 1e-6f);
  EXPECT_NEAR(B.z, 0.0f, 1e-6f);
}

// At angle θ from the normal, in the x-z plane: B = w along y (n x d), A = w / cos θ along x,
// up to the cap, which θ = 89.9° exceeds (1 / cos = 573 > 64).
TEST(Footprint, AtGrazingTheMajorAxisIsTheClosedFormUpToTheCap) {
  for (const float deg : {0.5f, 30.0f, 60.0f, 85.0f, 89.0f, 89.5f, 89.9f}) {
    const float th = deg * kPi / 180;
    const Vec3 d{std::sin(th), 0, -std::cos(th)};
    Vec3 A, B;
    footprintAxes(d, Vec3{0, 0, 1}, 2.0f, A, B);
    const double stretch = std::min(1.0 / std::cos(double(th)), double(kMaxFootprintStretch));
    EXPECT_NEAR(length(B), 2.0, 2e-6) << deg;
    EXPECT_NEAR(std::fabs(B.y), 2.0, 2e-6) << deg;
    EXPECT_NEAR(std::fabs(A.x), 2.0 * stretch, 2.0 * stretch * 1e-5) << deg;
    EXPECT_NEAR(A.z, 0.0, 1e-6) << deg;
  }
}

TEST(Footprint, ARayInThePlaneAndBadInputsAreFinite) {
  Vec3 A, B;
  footprintAxes(Vec3{1, 0, 0}, Vec3{0, 0, 1}, 1.0f, A, B);  // cos θ = 0: the cap
  EXPECT_NEAR(length(A), kMaxFootprintStretch, 1e-4);
  for (const float w : {0.0f, -1.0f, std::nanf(""), INFINITY}) {
    footprintAxes(Vec3{0, 0, -1}, Vec3{0, 0, 1}, w, A, B);
    EXPECT_EQ(A, Vec3{});
    EXPECT_EQ(B, Vec3{});
  }
  footprintAxes(Vec3{}, Vec3{0, 0, 1}, 1.0f, A, B);
  EXPECT_EQ(A, Vec3{});
  footprintAxes(Vec3{0, 0, -1}, Vec3{}, 1.0f, A, B);
  EXPECT_EQ(A, Vec3{});
  // Huge and tiny scales.
  footprintAxes(Vec3{1e-30f, 0, -1e-30f}, Vec3{0, 0, 1}, 1e30f, A, B);
  EXPECT_TRUE(isFinite(A) && isFinite(B));
  EXPECT_NEAR(std::fabs(A.x) / 1e30f, std::sqrt(2.0f), 1e-5f);  // (length() would overflow)
}

TEST(Footprint, ParametersSolveTheJacobianExactlyWhenItIsInvertible) {
  // A sheared, scaled tangent basis: a = 0.3 dP/du - 2 dP/dv is found back.
  const Vec3 pu{4, 1, 0}, pv{1, 0.5f, 0};
  float du, dv;
  toParameters(pu * 0.3f - pv * 2.0f, pu, pv, du, dv);
  EXPECT_NEAR(du, 0.3f, 1e-5f);
  EXPECT_NEAR(dv, -2.0f, 1e-5f);
  // Long and thin (lengths 1e4 and 1e-3): the regularisation is relative to each column.
  toParameters(Vec3{0, 1e-3f, 0}, Vec3{1e4f, 0, 0}, Vec3{0, 1e-3f, 0}, du, dv);
  EXPECT_NEAR(du, 0.0f, 1e-6f);
  EXPECT_NEAR(dv, 1.0f, 1e-5f);
  // A vector off the plane: its projection (least squares).
  toParameters(Vec3{1, 0, 5}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, du, dv);
  EXPECT_NEAR(du, 1.0f, 1e-5f);
  EXPECT_NEAR(dv, 0.0f, 1e-6f);
}

TEST(Footprint, ADegenerateJacobianGivesFiniteAxes) {
  float du, dv;
  // A pole: dP/du = 0. The collapsed direction gets no extent; v is solved alone.
  toParameters(Vec3{1, 2, 0}, Vec3{}, Vec3{0, 4, 0}, du, dv);
  EXPECT_EQ(du, 0.0f);
  EXPECT_NEAR(dv, 0.5f, 1e-6f);
  // Both zero.
  toParameters(Vec3{1, 2, 0}, Vec3{}, Vec3{}, du, dv);
  EXPECT_EQ(du, 0.0f);
  EXPECT_EQ(dv, 0.0f);
  // Parallel columns (a collapsed quad): finite, and the combination still reproduces a.
  toParameters(Vec3{3, 0, 0}, Vec3{1, 0, 0}, Vec3{2, 0, 0}, du, dv);
  EXPECT_TRUE(std::isfinite(du) && std::isfinite(dv));
  EXPECT_NEAR(du * 1 + dv * 2, 3.0f, 1e-4f);
  // Nearly parallel: bounded by the cap.
  toParameters(Vec3{0, 1, 0}, Vec3{1, 0, 0}, Vec3{1, 1e-30f, 0}, du, dv);
  EXPECT_TRUE(std::isfinite(du) && std::isfinite(dv));
  EXPECT_LE(std::fabs(du), kMaxFootprintAxis);
  EXPECT_LE(std::fabs(dv), kMaxFootprintAxis);
  // Non-finite input.
  toParameters(Vec3{NAN, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, du, dv);
  EXPECT_EQ(du, 0.0f);
  EXPECT_EQ(dv, 0.0f);
}

TEST(Footprint, QueryAxesGoThroughTheUvJacobian) {
  // A plane z = 0 with P = (2u, 3v, 0); the ray straight down; a cone 0.6 wide.
  const HitDerivatives dpd{Vec3{2, 0, 0}, Vec3{0, 3, 0}};
  TexCoordSample st;
  st.s = 0.25f; st.t = 0.75f;
  st.dsdu = 2; st.dtdu = 1; st.dsdv = 0; st.dtdv = -1;
  const TextureQuery q = footprintQuery(0.1f, 0.2f, Vec3{0, 0, -1}, Vec3{0, 0, 1}, 0.6f, &dpd, &st);
  EXPECT_EQ(q.patch.x, 0.1f);
  EXPECT_TRUE(q.hasUv);
  EXPECT_EQ(q.uv.x, 0.25f);
  // Each axis, mapped back to world space, is 0.6 long and in the plane.
  for (const auto& [du, dv] : {std::pair{q.patch.dxA, q.patch.dyA}, std::pair{q.patch.dxB, q.patch.dyB}})
    EXPECT_NEAR(length(dpd.dpdu * du + dpd.dpdv * dv), 0.6f, 1e-5f);
  EXPECT_NEAR(q.uv.dxA, 2 * q.patch.dxA + 0 * q.patch.dyA, 1e-6f);
  EXPECT_NEAR(q.uv.dyA, 1 * q.patch.dxA - 1 * q.patch.dyA, 1e-6f);
  EXPECT_NEAR(q.uv.dxB, 2 * q.patch.dxB, 1e-6f);
  EXPECT_NEAR(q.uv.dyB, q.patch.dxB - q.patch.dyB, 1e-6f);
  // Without derivatives: a point sample (zero axes), the uv point still filled.
  const TextureQuery p = footprintQuery(0.1f, 0.2f, Vec3{0, 0, -1}, Vec3{0, 0, 1}, 0.6f, nullptr, &st);
  EXPECT_EQ(p.patch.dxA, 0.0f);
  EXPECT_EQ(p.uv.dyB, 0.0f);
  EXPECT_EQ(p.uv.y, 0.75f);
}

TEST(Footprint, GrazingAndDegenerateQueriesStayFinite) {
  const HitDerivatives poles[] = {{Vec3{}, Vec3{0, 1, 0}}, {Vec3{}, Vec3{}}, {Vec3{1, 0, 0}, Vec3{1, 0, 0}},
                                  {Vec3{1e30f, 0, 0}, Vec3{0, 1e-30f, 0}}};
  for (const HitDerivatives& d : poles)
    for (const float deg : {0.0f, 89.9f, 90.0f}) {
      const float th = deg * kPi / 180;
      const TextureQuery q = footprintQuery(0.5f, 0.5f, Vec3{std::sin(th), 0, -std::cos(th)}, Vec3{0, 0, 1}, 1e20f,
                                            &d, nullptr);
      EXPECT_TRUE(finiteQuery(q.patch)) << deg;
    }
}

TEST(Footprint, CameraRaysFilterOverAPixelScaledDownWithTheSamples) {
  EXPECT_EQ(cameraFootprintScale(1), 1.0f);
  EXPECT_EQ(cameraFootprintScale(4), 0.5f);
  EXPECT_EQ(cameraFootprintScale(16), 0.25f);
  EXPECT_EQ(cameraFootprintScale(64), 0.125f);
  EXPECT_EQ(cameraFootprintScale(1 << 20), 0.125f);  // never below 1/8 (pbrt-v4's floor)
  EXPECT_EQ(cameraFootprintScale(0), 1.0f);
}

}  // namespace
}  // namespace rayes
