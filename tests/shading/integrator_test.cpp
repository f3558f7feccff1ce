// The path tracer's kernels (start / shade / finish) against analytic answers
// (docs/design.md, "Analytic checks"), with exact analytic geometry in place of the dicing
// pipeline: a small test tracer intersects spheres, planes and disks and fills the RayBatch,
// so the answers test shading alone (NEE, MIS, Russian roulette, delta lobes, lights) with no
// tessellation error. Tolerances: 4 standard errors of the pixel mean (pixels are i.i.d.
// estimates of the same value here), or float rounding where the estimator has no variance.
// The full pipeline (dicing included) is checked end to end in tests/app.
#include <cmath>
#include <limits>
#include <numbers>
#include <gtest/gtest.h>
#include "core/ray_batch.h"
#include "shading/fresnel.h"
#include "shading/path_tracer.h"
#include "shading/sampling.h"
#include "support/temp_folder.h"
#include "support/texture_test_files.h"

namespace rayes {
namespace {
constexpr float kPiF = std::numbers::pi_v<float>;
constexpr float kInf = std::numeric_limits<float>::infinity();

struct Shape {
  enum Kind { Sphere, Plane, Disk } kind;
  Vec3 c;          // centre / a point of the plane
  float r = 1;     // radius (sphere, disk)
  Vec3 n{0, 0, 1}; // plane / disk normal (the patch normal)
  bool inward = false;  // sphere: patch normal points inside
};

// Sphere parametrisation: z = 1 - 2u, phi = 2 pi v; |dP/du x dP/dv| = 4 pi r^2 everywhere.
void spherePoint(const Shape& s, float u, float v, Vec3& p, Vec3& n) {
  const float z = 1 - 2 * u, sxy = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPiF * v;
  const Vec3 d{sxy * std::cos(phi), sxy * std::sin(phi), z};
  p = s.c + d * s.r;
  n = d * (4 * kPiF * s.r * s.r * (s.inward ? -1.0f : 1.0f));
}
// Disk: concentric map, |dP/du x dP/dv| = pi r^2 everywhere.
void diskPoint(const Shape& s, float u, float v, Vec3& p, Vec3& n) {
  Vec3 t, b;
  orthonormalBasis(s.n, t, b);
  float x, y;
  concentricDisk(u, v, x, y);
  p = s.c + (t * x + b * y) * s.r;
  n = s.n * (kPiF * s.r * s.r);
}

struct TestScene {
  std::vector<Shape> shapes;  // leaf = index
  ShadingScene shading;

  void addShape(const Shape& s, uint32_t material) {
    shapes.push_back(s);
    shading.leafMaterial.push_back(material);
    shading.leafSide.push_back(s.kind == Shape::Plane ? 1.0f : 2 * s.r);
    shading.leafDicingError.push_back(0);
  }
  PatchLight patchLight(uint32_t leaf) const {
    const Shape s = shapes[leaf];
    const Material& m = shading.materials[shading.leafMaterial[leaf]];
    auto eval = s.kind == Shape::Sphere ? spherePoint : diskPoint;
    return {[s, eval](float u, float v, Vec3& p, Vec3& n) { eval(s, u, v, p, n); }, m.emission, m.twoSided, leaf};
  }

  bool intersect(const Shape& s, Vec3 o, Vec3 d, float t0, float t1, RayHit& h, uint32_t leaf) const {
    float t = kInf;
    Vec3 nrm;
    float u = 0.5f, v = 0.5f;
    if (s.kind == Shape::Sphere) {
      const Vec3 oc = o - s.c;
      const double b = dot(oc, d), c = double(dot(oc, oc)) - double(s.r) * s.r;
      const double disc = b * b - c;
      if (disc < 0) return false;
      const double sq = std::sqrt(disc);
      const double ta = -b - sq, tb = -b + sq;
      t = float(ta > t0 ? ta : tb);
      if (!(t > t0 && t < t1)) return false;
      const Vec3 dir = normalize(o + d * t - s.c);
      nrm = s.inward ? -dir : dir;
      u = std::clamp((1 - dir.z) / 2, 0.0f, 1.0f);
      float phi = std::atan2(dir.y, dir.x);
      if (phi < 0) phi += 2 * kPiF;
      v = std::min(phi / (2 * kPiF), 0.99999994f);
    } else {
      const float dn = dot(d, s.n);
      if (dn == 0) return false;
      t = dot(s.c - o, s.n) / dn;
      if (!(t > t0 && t < t1)) return false;
      if (s.kind == Shape::Disk) {
        const Vec3 q = o + d * t - s.c;
        if (dot(q, q) > s.r * s.r) return false;
      }
      nrm = s.n;  // (u, v) unused for planes; for the disk the light density is independent of them
    }
    h.t = t; h.u = u; h.v = v; h.leaf = leaf; h.quad = 0; h.level = 0; h.setNormals(nrm, nrm);
    return true;
  }

  void trace(RayBatch& rays) const {
    for (size_t i = 0; i < rays.size(); ++i) {
      if (rays.ray[i].kind == RayKind::Inactive) continue;
      RayHit best;
      for (uint32_t l = 0; l < shapes.size(); ++l) {
        if (l == rays.ray[i].ignoreLeaf) continue;
        RayHit h;
        const float tmax = std::min(rays.ray[i].tmax, best.t);
        if (intersect(shapes[l], rays.ray[i].org, rays.ray[i].dir(), std::max(0.0f, 0.0f), tmax, h, l)) best = h;
      }
      rays.hit[i] = best;
    }
  }

  // Renders and returns the red channel of every pixel.
  std::vector<double> render(ShadeStats* statsOut = nullptr) {
    PathTracer tracer(shading);
    PathBatch paths;
    RayBatch rays;
    ShadeStats stats;
    Film film(shading.width, shading.height);
    const uint32_t total = uint32_t(shading.width * shading.height * shading.samplesPerPixel);
    tracer.start(0, total, paths, rays);
    for (uint32_t bounce = 0;; ++bounce) {
      trace(rays);
      if (tracer.shade(bounce, paths, rays, stats) == 0) break;
    }
    tracer.finish(paths, film, stats);
    EXPECT_EQ(stats.nonFinite.load(), 0u);
    if (statsOut) statsOut->shadowRays = stats.shadowRays.load();
    const auto rgba = film.beautyRgba();
    std::vector<double> red;
    for (size_t p = 0; p < rgba.size() / 4; ++p) red.push_back(rgba[4 * p]);
    return red;
  }
};

struct MeanError { double mean, stderr_; };
MeanError meanOf(const std::vector<double>& v) {
  double s = 0, s2 = 0;
  for (double x : v) { s += x; s2 += x * x; }
  const double n = double(v.size()), m = s / n;
  return {m, std::sqrt(std::max(0.0, (s2 - n * m * m) / (n - 1)) / n)};
}

void expectWithin4Sigma(const std::vector<double>& pixels, double expected, const std::string& what) {
  const MeanError e = meanOf(pixels);
  // Zero-variance estimators: float rounding of the per-sample value (1e-5 relative).
  const double tol = std::max(4 * e.stderr_, 1e-5 * std::fabs(expected));
  EXPECT_NEAR(e.mean, expected, tol) << what << " (stderr " << e.stderr_ << ")";
}

Material lambert(Rgb albedo, Rgb emission = {}) {
  Material m;
  m.type = MaterialType::Diffuse;
  m.albedo = albedo;
  m.emission = emission;
  return m;
}

// Inside a closed sphere of albedo rho emitting exitance E (radiance E / pi) from every
// point, the radiance is E / (pi (1 - rho)) everywhere. The geometry is an exact sphere, so
// uniform area sampling of it is exact: cos cos / r^2 = 1 / (4 R^2) for any two points.
void sphereFurnace(float rho) {
  TestScene s;
  const float exitance = kPiF;  // emitted radiance 1
  s.shading.materials = {lambert({rho, rho, rho}, {exitance / kPiF, exitance / kPiF, exitance / kPiF})};
  s.addShape({Shape::Sphere, {0.1f, -0.2f, 0.3f}, 1.5f, {}, true}, 0);
  s.shading.camera = PerspectiveCamera({0.3f, -0.1f, 0.2f}, {1, 1, 0}, {0, 0, 1}, 90, 16, 16);
  s.shading.width = s.shading.height = 16;
  s.shading.samplesPerPixel = 64;
  s.shading.integrator.maxDepth = 1000;
  s.shading.integrator.seed = 3;
  s.shading.lights = LightSampler({}, {s.patchLight(0)});
  expectWithin4Sigma(s.render(), exitance / (kPiF * (1 - rho)), "sphere furnace rho " + std::to_string(rho));
}

TEST(IntegratorAnalytic, ClosedSphereFurnaceHalfAlbedo) { sphereFurnace(0.5f); }
TEST(IntegratorAnalytic, ClosedSphereFurnaceHighAlbedo) { sphereFurnace(0.9f); }

// A white Lambertian floor under a one-sided disk luminaire of radiance L (exitance E = pi L),
// radius R, at height h, looked at on the axis: irradiance E R^2 / (R^2 + h^2), so the floor's
// radiance is L R^2 / (R^2 + h^2). Direct light only (max depth 1): NEE and BSDF-sampled hits
// of the disk, combined by MIS.
TEST(IntegratorAnalytic, DiskLuminaireOnAxis) {
  for (auto [radius, height] : {std::pair{1.0f, 1.0f}, {0.5f, 2.0f}, {2.0f, 0.5f}}) {
    TestScene s;
    const float le = 2.0f;
    s.shading.materials = {lambert({1, 1, 1}), lambert({0, 0, 0}, {le, le, le})};
    s.addShape({Shape::Plane, {0, 0, 0}, 1, {0, 0, 1}}, 0);
    s.addShape({Shape::Disk, {0, 0, height}, radius, {0, 0, -1}}, 1);
    // A very narrow view of the point on the axis, from the side, under the disk.
    s.shading.camera = PerspectiveCamera({5, 1, 0.2f}, {0, 0, 0}, {0, 0, 1}, 0.002f, 8, 8);
    s.shading.width = s.shading.height = 8;
    s.shading.samplesPerPixel = 256;
    s.shading.integrator.maxDepth = 1;
    s.shading.lights = LightSampler({}, {s.patchLight(1)});
    expectWithin4Sigma(s.render(), le * radius * radius / (radius * radius + height * height),
                       "disk R " + std::to_string(radius) + " h " + std::to_string(height));
  }
}

// MIS with a glossy receiver, where BSDF sampling carries much of the weight: a white Phong
// floor (kd = 0, exponent 1) under the disk, against a fine midpoint rule over the disk.
TEST(IntegratorAnalytic, DiskLuminaireWithGlossyReceiverAgrees) {
  TestScene s;
  const float le = 1.0f, radius = 1.0f, height = 1.0f;
  Material phong;
  phong.type = MaterialType::Phong;
  phong.albedo = Rgb{0, 0, 0};
  phong.specular = Rgb{1, 1, 1};
  phong.exponent = 1;
  s.shading.materials = {phong, lambert({0, 0, 0}, {le, le, le})};
  s.addShape({Shape::Plane, {0, 0, 0}, 1, {0, 0, 1}}, 0);
  s.addShape({Shape::Disk, {0, 0, height}, radius, {0, 0, -1}}, 1);
  // Looking straight down the axis through the disk's centre is blocked by the disk; look from
  // just outside its rim instead, at the axis point: f = 3/(2 pi) cos(alpha) about the mirror.
  const Vec3 eye{1.5f, 0, 1.2f};  // the view line passes z = 1 at x = 1.25, outside the disk
  s.shading.camera = PerspectiveCamera(eye, {0, 0, 0}, {0, 0, 1}, 0.002f, 8, 8);
  s.shading.width = s.shading.height = 8;
  s.shading.samplesPerPixel = 256;
  s.shading.integrator.maxDepth = 1;
  s.shading.lights = LightSampler({}, {s.patchLight(1)});
  // Reference: L = ∫disk f(wo, wi) le cos θi dω, by a fine midpoint rule over the disk.
  const Vec3 wo = normalize(eye), mirror{-wo.x, -wo.y, wo.z};
  double ref = 0;
  const int n = 800;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = -radius + 2 * radius * (i + 0.5) / n, y = -radius + 2 * radius * (j + 0.5) / n;
      if (x * x + y * y > radius * radius) continue;
      const double d2 = x * x + y * y + height * height, d = std::sqrt(d2);
      const double cz = height / d;  // cos at the floor and at the disk
      const double ca = std::max(0.0, (x * mirror.x + y * mirror.y + height * mirror.z) / d);
      ref += 3 / (2 * std::numbers::pi) * ca * le * cz * cz / d2 * (4.0 * radius * radius / (double(n) * n));
    }
  expectWithin4Sigma(s.render(), ref, "phong floor under a disk");
}

// A white Lambertian floor (the plane z = 0) seen from (0, -3, 2), direct light only: the
// receiver of the light tests below, whose radiance is its irradiance / pi.
TestScene whiteFloor(float fovDegrees, int resolution, int spp) {
  TestScene s;
  s.shading.materials = {lambert({1, 1, 1})};
  s.addShape({Shape::Plane, {0, 0, 0}, 1, {0, 0, 1}}, 0);
  s.shading.camera = PerspectiveCamera({0, -3, 2}, {0, 0, 0}, {0, 0, 1}, fovDegrees, resolution, resolution);
  s.shading.width = s.shading.height = resolution;
  s.shading.samplesPerPixel = spp;
  s.shading.integrator.maxDepth = 1;
  return s;
}

// Sun: a uniform disk of angular radius 3 degrees and irradiance E, 40 degrees from the
// zenith, over a white Lambertian floor: irradiance E cos 40° exactly (the cap's first moment
// is along its axis), radiance E cos 40° / pi. NEE samples the cone, BSDF samples that escape
// into it are MIS-weighted.
TEST(IntegratorAnalytic, SunDiskOnLambertianFloor) {
  TestScene s = whiteFloor(30, 8, 256);
  const float theta = 40 * kPiF / 180, radius = 3 * kPiF / 180, e = 3;
  SceneLights more;
  more.distants.push_back({{std::sin(theta), 0, std::cos(theta)}, {e, e, e}, 2 * std::pow(std::sin(0.5 * radius), 2)});
  s.shading.lights = LightSampler({}, {}, more, 10);
  expectWithin4Sigma(s.render(), e * std::cos(theta) / kPiF, "sun");
}

// A lat-long environment of arbitrary texels over a white Lambertian floor: the floor's
// radiance is (1/pi) Σ_texels L ∫_texel cos θ dω, with ∫ = Δφ (sin² θ1 - sin² θ0) / 2 for the
// rows above the horizon. Exercises the map's importance sampling and its MIS weights.
TEST(IntegratorAnalytic, EnvironmentMapIrradianceOnFloor) {
  const testing::TempFolder temp;
  std::vector<Rgb> texels;
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) {
      const float v = float((x * 7 + y * 3) % 5) + (x == 2 && y == 1 ? 40.0f : 0.0f);
      texels.push_back({v, v, v});
    }
  testing::writeRgbExr(temp.path("sky.exr"), 8, 6, texels);
  const auto image = testing::quietCache(temp.dir())->open(temp.path("sky.exr"));
  double irradiance = 0;
  for (int y = 0; y < 3; ++y)  // rows above the horizon (θ < π/2)
    for (int x = 0; x < 8; ++x) {
      const double t0 = std::numbers::pi * y / 6, t1 = std::numbers::pi * (y + 1) / 6;
      irradiance += texels[size_t(y) * 8 + x].x * (2 * std::numbers::pi / 8) *
                    (std::pow(std::sin(t1), 2) - std::pow(std::sin(t0), 2)) / 2;
    }
  for (bool constant : {false, true}) {
    TestScene s = whiteFloor(30, 8, 256);
    SceneLights more;
    more.environment = constant ? std::make_shared<Environment>(Rgb{0.7f, 0.7f, 0.7f})
                                : std::make_shared<Environment>(image, Rgb{1, 1, 1});
    s.shading.lights = LightSampler({}, {}, more, 10);
    expectWithin4Sigma(s.render(), constant ? 0.7 : irradiance / std::numbers::pi,
                       constant ? "constant sky" : "environment map");
  }
}

// Delta lights have zero-variance direct lighting: a spot light over a white floor.
TEST(IntegratorAnalytic, SpotAndPointLightsAreExact) {
  TestScene s = whiteFloor(0.002f, 4, 4);
  SceneLights more;
  const Vec3 pos{1, 0, 2};
  const Vec3 axis = normalize(Vec3{-0.3f, 0, -1});
  more.spots.push_back({pos, axis, {5, 5, 5}, std::cos(0.1f), std::cos(0.5f)});
  s.shading.lights = LightSampler({}, {}, more, 10);
  const Vec3 toPoint = normalize(Vec3{0, 0, 0} - pos);
  const double d2 = dot(pos, pos), cosFloor = pos.z / std::sqrt(d2);
  const double expected = 5 * more.spots[0].falloff(dot(toPoint, axis)) * cosFloor / d2 / std::numbers::pi;
  EXPECT_GT(more.spots[0].falloff(dot(toPoint, axis)), 0.0f);
  EXPECT_LT(more.spots[0].falloff(dot(toPoint, axis)), 1.0f);
  expectWithin4Sigma(s.render(), expected, "spot");
}

// A smooth glass slab (two parallel interfaces, eta 1.5) over a sky that is black above the
// horizon and 1 below: the radiance seen through it is the slab's transmittance, the Fresnel
// series (1 - R)^2 Σ R^(2k) = (1 - R) / (1 + R) with R the single-interface reflectance (the
// same on both faces). The renderer is unpolarised, so R is the unpolarised Fresnel
// reflectance; at normal incidence this equals the polarised answer exactly.
TEST(IntegratorAnalytic, GlassSlabTransmittanceIsTheFresnelSeries) {
  const testing::TempFolder temp;
  testing::writeRgbExr(temp.path("sky.exr"), 1, 2, {{0, 0, 0}, {1, 1, 1}});
  const auto sky = testing::quietCache(temp.dir())->open(temp.path("sky.exr"));
  for (float degrees : {0.0f, 45.0f, 75.0f}) {
    TestScene s;
    Material glass;
    glass.type = MaterialType::Dielectric;
    glass.eta = {1.5f, 1.5f, 1.5f};
    s.shading.materials = {glass};
    s.addShape({Shape::Plane, {0, 0, 0}, 1, {0, 0, 1}}, 0);      // top face, outside up
    s.addShape({Shape::Plane, {0, 0, -0.5f}, 1, {0, 0, -1}}, 0); // bottom face, outside down
    const float th = degrees * kPiF / 180;
    s.shading.camera = PerspectiveCamera({3 * std::sin(th), 0.0f, 3 * std::cos(th)}, {0, 0, 0},
                                         degrees == 0 ? Vec3{0, 1, 0} : Vec3{0, 0, 1}, 0.002f, 8, 8);
    s.shading.width = s.shading.height = 8;
    s.shading.samplesPerPixel = 512;
    s.shading.integrator.maxDepth = 1000;
    SceneLights more;
    more.environment = std::make_shared<Environment>(sky, Rgb{1, 1, 1});
    s.shading.lights = LightSampler({}, {}, more, 10);
    const double r = fresnelDielectric(std::cos(th), 1.5f);
    expectWithin4Sigma(s.render(), (1 - r) / (1 + r), "slab at " + std::to_string(degrees) + " degrees");
    if (degrees == 0) {
      float rs, rp;
      fresnelDielectricPolarised(1, 1.5f, rs, rp);
      const double polarised = 0.5 * ((1 - rs) / (1 + rs) + (1 - rp) / (1 + rp));
      EXPECT_NEAR(polarised, (1 - r) / (1 + r), 1e-6);
      EXPECT_NEAR(r, 0.04, 1e-6);
    }
  }
}

}  // namespace
}  // namespace rayes
