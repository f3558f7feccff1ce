// Uv sets end to end: a checker in uv space on a subdivision surface renders as the checker of
// its uv set, pixel by pixel; the shipped uv-mapped scene renders the same bits whatever the
// threads, order and batches; and the stats say what the uv sets cost. The surface is a flat
// grid, so each pixel's piece of it is known exactly (the camera's rays through the pixel's
// corners) and its uvs are an affine function of the position (below), which makes the albedo
// of every pixel inside one checker square exact.
#include <gtest/gtest.h>
#include <cmath>
#include "support/render_fixtures.h"

namespace rayes {
namespace {

using testing::sourcePath;

// A flat n x n grid over [-n/2, n/2]^2 in z = 0, one uv per vertex equal to its (x, y) / 2, seen
// from straight above. Catmull-Clark on a flat grid of unit squares gives each interior face the
// unit square it spans, its (u, v) affinely (uniform B-splines reproduce linear functions); the
// uvs use the same weights (uv_interpolation none: smooth like the positions), so uv = (x, y) / 2
// there. The bilinear scheme gives that on every face.
std::string gridScene(const std::string& scheme, const std::string& coordinates) {
  const int n = 6;
  std::string verts, faces, uvs;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const std::string x = std::to_string(i - n / 2), y = std::to_string(j - n / 2);
      verts += (verts.empty() ? "" : ",") + ("[" + x + "," + y + ",0]");
      uvs += (uvs.empty() ? "" : ",") +
             ("[" + std::to_string(0.5 * (i - n / 2)) + "," + std::to_string(0.5 * (j - n / 2)) + "]");
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      faces += (faces.empty() ? "" : ",") + ("[" + std::to_string(a) + "," + std::to_string(a + 1) + "," +
                                             std::to_string(a + n + 2) + "," + std::to_string(a + n + 1) + "]");
    }
  return R"({
  "camera": {"position": [0, 0, 6], "look_at": [0, 0, 0], "fov": 40},
  "film": {"resolution": [40, 40], "spp": 4},
  "materials": {"c": {"type": "diffuse", "albedo": {"type": "checker", "colors": [0.2, 0.8], "scale": 2, "coordinates": ")" +
         coordinates + R"("}}},
  "shapes": [{"type": "subdiv", "material": "c", "scheme": ")" + scheme + R"(", "uv_interpolation": "none",
              "vertices": [)" + verts + R"(], "faces": [)" + faces + R"(], "uvs": [)" + uvs + R"(]}],
  "lights": [{"type": "point", "position": [0, 0, 5], "intensity": [10, 10, 10]}]
})";
}

// Where the pinhole ray through film position (px, py) meets z = 0.
Vec3 onPlane(const PerspectiveCamera& cam, float px, float py) {
  const CameraRay r = cam.generate(px, py, 0.5f, 0.5f, 0);
  return r.org + r.dir * (-r.org.z / r.dir.z);
}

// The checker of the uv set (scale 2 of (x, y) / 2: unit squares in (x, y)) against the albedo of
// every pixel whose piece of the plane lies inside one square of the interior faces' [-2, 2]^2,
// by more than the texture footprint's reach past the pixel and the rounding of a hit's position
// and uv (1e-3 of a square is far above it). A camera ray's footprint is its pixel's width times
// max(1/8, 1/sqrt(spp)) (shading/footprint.h; 1/2 at 4 spp), centred on the ray's hit; the cone
// is a little wider than the pixel's piece of the plane off the axis (the ray's length over the
// distance along the axis, at most 1.1 here, and the ellipse's stretch 1 / cos θ, at most 1.1),
// so the filtered checker reads less than half a pixel's width past the pixel.
// Returns the pixels checked.
int expectCheckerOfTheUvSet(const Scene& scene) {
  Renderer r(scene, RenderOptions{});
  const Film film = r.render();
  const std::vector<float> albedo = film.albedo();
  // In world coordinates, where the checker's squares are (the scene's camera is in its render frame).
  const PerspectiveCamera cam(scene.frame.toWorld(scene.camera.position), scene.frame.toWorld(scene.camera.lookAt),
                              scene.camera.up, scene.camera.fovYDegrees, scene.width, scene.height);
  int checked = 0;
  for (int py = 0; py < scene.height; ++py)
    for (int px = 0; px < scene.width; ++px) {
      const Vec3 a = onPlane(cam, float(px), float(py)), b = onPlane(cam, float(px + 1), float(py + 1));
      const float x0 = std::min(a.x, b.x), x1 = std::max(a.x, b.x), y0 = std::min(a.y, b.y), y1 = std::max(a.y, b.y);
      if (x0 < -2 || x1 > 2 || y0 < -2 || y1 > 2) continue;
      const float margin = 1e-3f + 0.5f * std::max(x1 - x0, y1 - y0);
      const float cx = std::floor(x0 - margin), cy = std::floor(y0 - margin);
      if (cx != std::floor(x1 + margin) || cy != std::floor(y1 + margin)) continue;
      const bool odd = std::fmod(std::fabs(cx + cy), 2.0f) >= 1.0f;
      const float want = odd ? 0.8f : 0.2f;
      const size_t p = size_t(py) * size_t(scene.width) + size_t(px);
      for (int c = 0; c < 3; ++c)
        EXPECT_FLOAT_EQ(albedo[3 * p + size_t(c)], want) << "pixel " << px << ", " << py << " at x " << x0 << ".." << x1
                                                          << ", y " << y0 << ".." << y1;
      ++checked;
    }
  return checked;
}

TEST(UvRender, CheckerInUvSpaceOnACatmullClarkSurface) {
  const Scene s = parseScene(gridScene("catmull-clark", "uv"), "grid.json");
  // About (4 / 4.37)^2 of the pixels lie over the interior faces, and a unit square spans 9.2
  // pixels, of which 7.2 are inside it in each direction: about half of the image.
  EXPECT_GT(expectCheckerOfTheUvSet(s), s.width * s.height / 3);
}

TEST(UvRender, CheckerInUvSpaceOnAPlainPolygonMesh) {
  const Scene s = parseScene(gridScene("bilinear", "uv"), "grid.json");
  EXPECT_GT(expectCheckerOfTheUvSet(s), s.width * s.height / 3);
}

TEST(UvRender, PatchCoordinatesIgnoreTheUvSet) {
  // Each face is one unit of (u, v): at scale 2 its patch checker has four squares of side 1/2,
  // where the uv checker has one unit square per face.
  const Scene uv = parseScene(gridScene("bilinear", "uv"), "grid.json");
  const Scene patch = parseScene(gridScene("bilinear", "patch"), "grid.json");
  const auto a = Renderer(uv, RenderOptions{}).render().albedo(), b = Renderer(patch, RenderOptions{}).render().albedo();
  EXPECT_NE(a, b);
}

TEST(UvRender, ShippedUvCheckerIsOrderIndependent) {
  // Uv lookups go through per-thread caches of Bfr surfaces: the image must not depend on which
  // thread shaded what, in which order, or in how many batches.
  const Scene s = testing::resized(loadScene(sourcePath("scenes/uv-checker.json")), 32, 24, 2);
  ASSERT_TRUE(s.uvs);
  testing::expectOrderIndependent(s, 150);
}

TEST(UvRender, StatsCountTheUvSetsBytesOnlyWhenThereAreSome) {
  const Scene with = parseScene(gridScene("bilinear", "uv"), "grid.json");
  Renderer r(with, RenderOptions{});
  // 49 values of (s, t), 4 indices per face for 36 faces, an 8-byte record per leaf.
  EXPECT_GE(r.stats().memory.uvSets, 49u * 8 + 36u * 4 * 4 + 36u * 8);
  EXPECT_EQ(r.stats().features.uvLeaves, 36u);
  const Scene without = testing::smallTeapot();
  EXPECT_EQ(Renderer(without, RenderOptions{}).stats().memory.uvSets, 0u);
  EXPECT_FALSE(without.uvs);
  // Uv sets that no texture reads are left out at load.
  const Scene unread = parseScene(gridScene("bilinear", "patch"), "grid.json");
  Renderer u(unread, RenderOptions{});
  EXPECT_EQ(u.stats().memory.uvSets, 0u);
  EXPECT_EQ(u.stats().features.uvLeaves, 0u);
  EXPECT_TRUE(u.stats().features.uvSetsDropped);
}

}  // namespace
}  // namespace rayes
