// The closed-form caustic of scenes/caustic-closed-form.json (tests/support/closed_form_caustic.h:
// a point light in a tilted planar mirror on a diffuse ceiling, E = ρ·I·cos θ / D² from the
// light's mirror image) as a reference image, and renders measured against it
// (bench/converge_pm.sh).
//
// usage: bench_app_closed_form_caustic reference SCENE WxH OUT.exr MASK.exr [MARGIN]
//          the closed-form image at WxH (each pixel the mean of albedo/π·E on a 16 x 16 grid)
//          and the interior mask: 1 where the pixel's square on the ceiling, widened by MARGIN
//          (default 0.3, ceiling units), lies inside the footprint
//        bench_app_closed_form_caustic measure SCENE WxH MASK.exr IMAGE.exr...
//          per image: the interior ratio (the image's sum over the mask over the closed form's)
//          and the flux ratio (the image summed times the pixels' ceiling area times π/albedo,
//          over ρ·I·Ω); then their means and standard errors over the images (independent seeds)
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>
#include "app/image_io.h"
#include "core/error.h"
#include "rgb_exr.h"
#include "scene/scene_loader.h"
#include "support/closed_form_caustic.h"

namespace {

using namespace rayes;

struct Setup {
  testing::ClosedFormCaustic caustic;
  PerspectiveCamera camera;
  int w = 0, h = 0;
};

Setup setup(const std::string& scenePath, const std::string& res) {
  Setup s;
  if (std::sscanf(res.c_str(), "%dx%d", &s.w, &s.h) != 2 || s.w < 1 || s.h < 1)
    throw InputError(res, "", "the resolution must be WxH");
  const Scene scene = loadScene(scenePath);
  if (scene.pointLights.size() != 1 || !(scene.pointLights[0].position == s.caustic.light))
    throw InputError(scenePath, "", "not the closed-form caustic scene (its light differs)");
  const CameraDesc& c = scene.camera;
  s.camera = PerspectiveCamera(c.position, c.lookAt, c.up, c.fovYDegrees, s.w, s.h);
  return s;
}

// The closed form's radiance in pixel (x, y), and whether the pixel is interior.
double pixelRadiance(const Setup& s, int x, int y) {
  double e = 0;
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i)
      e += s.caustic.irradiance(testing::ceilingPoint(s.camera, x + (i + 0.5f) / 16, y + (j + 0.5f) / 16)) / 256;
  return s.caustic.kAlbedo / std::numbers::pi * e;
}
bool interior(const Setup& s, int x, int y, float margin) {
  const Vec3 a = testing::ceilingPoint(s.camera, float(x), float(y));
  const Vec3 b = testing::ceilingPoint(s.camera, x + 1.0f, y + 1.0f);
  for (float sx : {-1.0f, 1.0f})
    for (float sy : {-1.0f, 1.0f}) {
      const float px = (sx < 0 ? std::fmin(a.x, b.x) : std::fmax(a.x, b.x)) + sx * margin;
      const float py = (sy < 0 ? std::fmin(a.y, b.y) : std::fmax(a.y, b.y)) + sy * margin;
      if (!s.caustic.inside({px, py, float(s.caustic.kCeilingZ)}, 0)) return false;
    }
  return true;
}

int reference(const Setup& s, const std::string& out, const std::string& mask, float margin) {
  std::vector<float> image(size_t(3) * s.w * s.h), inside(image.size());
  size_t kept = 0;
  for (int y = 0; y < s.h; ++y)
    for (int x = 0; x < s.w; ++x) {
      const size_t p = 3 * (size_t(y) * s.w + x);
      image[p] = image[p + 1] = image[p + 2] = float(pixelRadiance(s, x, y));
      const bool in = interior(s, x, y, margin);
      inside[p] = inside[p + 1] = inside[p + 2] = in ? 1.0f : 0.0f;
      kept += in;
    }
  writeRgbExr(out, s.w, s.h, image);
  writeRgbExr(mask, s.w, s.h, inside);
  std::printf("%zu of %d pixels interior (margin %g); reflected flux %.6f W\n", kept, s.w * s.h, margin,
              s.caustic.reflectedFlux());
  return 0;
}

int measure(const Setup& s, const std::string& mask, const std::vector<std::string>& images) {
  int w = 0, h = 0;
  const std::vector<float> in = readExrRgb(mask, w, h);
  if (w != s.w || h != s.h) throw InputError(mask, "", "the mask's size differs from WxH");
  std::vector<double> closed(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) closed[size_t(y) * w + x] = pixelRadiance(s, x, y);
  const Vec3 a = testing::ceilingPoint(s.camera, 0, 0), b = testing::ceilingPoint(s.camera, 1, 1);
  const double pixelArea = std::fabs(double(b.x - a.x) * double(b.y - a.y));
  double sum[2] = {0, 0}, sum2[2] = {0, 0};
  for (const std::string& path : images) {
    int iw = 0, ih = 0;
    const std::vector<float> img = readExrRgb(path, iw, ih);
    if (iw != w || ih != h) throw InputError(path, "", "the image's size differs from WxH");
    double num = 0, den = 0, flux = 0;
    for (size_t p = 0; p < closed.size(); ++p) {
      const double v = (double(img[3 * p]) + img[3 * p + 1] + img[3 * p + 2]) / 3;
      if (in[3 * p] > 0) num += v, den += closed[p];
      flux += v * pixelArea * std::numbers::pi / s.caustic.kAlbedo;
    }
    const double r[2] = {num / den, flux / s.caustic.reflectedFlux()};
    std::printf("%s: interior %.5f, flux %.5f\n", path.c_str(), r[0], r[1]);
    for (int i = 0; i < 2; ++i) sum[i] += r[i], sum2[i] += r[i] * r[i];
  }
  const double n = double(images.size());
  for (int i = 0; i < 2; ++i) {
    const double m = sum[i] / n, se = n > 1 ? std::sqrt(std::fmax(0.0, (sum2[i] - n * m * m) / (n - 1)) / n) : 0;
    std::printf("%s %.5f +- %.5f (%zu images)\n", i == 0 ? "interior" : "flux", m, se, images.size());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (!((mode == "reference" && (argc == 6 || argc == 7)) || (mode == "measure" && argc >= 6))) {
    std::fprintf(stderr, "usage: %s reference SCENE WxH OUT.exr MASK.exr [MARGIN]\n"
                         "       %s measure SCENE WxH MASK.exr IMAGE.exr...\n", argv[0], argv[0]);
    return 2;
  }
  try {
    const Setup s = setup(argv[2], argv[3]);
    if (mode == "reference") return reference(s, argv[4], argv[5], argc == 7 ? std::stof(argv[6]) : 0.3f);
    return measure(s, argv[4], std::vector<std::string>(argv + 5, argv + argc));
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.message().c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
