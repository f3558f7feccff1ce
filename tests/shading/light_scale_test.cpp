// The light sampler is scale-free: a rect light and its receiver scaled together by s give the
// same direction, radiance and solid-angle pdf for every s from 1e-6 to 1e8. |dP/du x dP/dv| is
// an area: at 1e8 x a 130-unit light it is 1.7e20, whose float square overflows (the light
// used to vanish from next-event estimation), at 1e-6 x a 1e-4 light its square underflows.
#include <cmath>
#include <gtest/gtest.h>
#include "core/box.h"
#include "shading/light.h"

namespace rayes {
namespace {

LightSampler rectLight(double s) {
  const Vec3 c = Vec3{343, 548.7f, 227} * float(s), eu = Vec3{0, 0, 105} * float(s), ev = Vec3{-130, 0, 0} * float(s);
  PatchLight l;
  l.evaluate = [=](float u, float v, Vec3& p, Vec3& n) {
    p = c + eu * u + ev * v;
    n = cross(eu, ev);
  };
  l.radiance = {17, 12, 4};
  l.twoSided = true;
  return LightSampler({}, {l}, {}, float(278 * s));
}

TEST(LightScale, RectLightSampleIsTheSameAtEveryScale) {
  const LightSampler unit = rectLight(1);
  for (double s : {1e-6, 1e-3, 1e4, 1e8}) {
    SCOPED_TRACE(s);
    const LightSampler scaled = rectLight(s);
    for (float u : {0.1f, 0.5f, 0.9f}) {
      LightSample a, b;
      ASSERT_TRUE(unit.sample(Vec3{278, 10, 270}, 0.5f, u, 1 - u, a));
      ASSERT_TRUE(scaled.sample(Vec3{278, 10, 270} * float(s), 0.5f, u, 1 - u, b));
      // Both are the same float computation up to the rounding of the scaled inputs: a few
      // dozen roundings, relative.
      const float rel = gammaBound(64);
      EXPECT_NEAR(b.pdf, a.pdf, rel * a.pdf);
      EXPECT_NEAR(b.distance, a.distance * float(s), rel * a.distance * float(s));
      EXPECT_NEAR(dot(a.wi, b.wi), 1.0f, rel);
      EXPECT_EQ(b.radiance.x, a.radiance.x);
      // The density MIS uses for the same point found by a BSDF ray agrees with sample()'s.
      EXPECT_NEAR(scaled.patchPdf(0, u, 1 - u, b.wi, b.distance), b.pdf, rel * b.pdf);
    }
  }
}

}  // namespace
}  // namespace rayes
