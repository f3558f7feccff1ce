#include "app/render_data.h"
#include <algorithm>
#include <limits>
#include <map>

namespace rayes {
namespace {

SceneFeatures featuresOf(const Scene& scene) {
  SceneFeatures f;
  for (const PatchPtr& patch : scene.patches) {
    f.movingLeaves += patch->timeSamples() > 1;
    f.displacedLeaves += patch->isDisplaced();
    f.subdivisionLeaves += patch->isSubdivision();
    f.borderClosureLeaves += patch->needsBorderClosure();
    const float spacing = patch->bounds().relativeSpacing();
    f.coarsestRelativeSpacing = std::max(f.coarsestRelativeSpacing, double(spacing));
    f.lowPrecisionLeaves += spacing > 0x1p-16f;
  }
  f.shutterOpen = scene.camera.shutterClose > scene.camera.shutterOpen;
  f.environment = scene.moreLights.environment != nullptr;
  f.distantLights = scene.moreLights.distants.size();
  return f;
}

// Every emissive patch is an area light; shading sees it only through its surface function.
std::vector<PatchLight> patchLightsOf(const Scene& scene) {
  std::vector<PatchLight> lights;
  for (size_t i = 0; i < scene.patches.size(); ++i) {
    const Material& m = scene.materials[scene.patchMaterial[i]];
    if (!m.emits()) continue;
    PatchPtr patch = scene.patches[i];
    lights.push_back({[patch](float u, float v, Vec3& p, Vec3& nrm) {
                        const SurfacePoint sp = patch->evaluate(u, v);
                        p = sp.p; nrm = sp.n;
                      },
                      m.emission, m.twoSided, uint32_t(i)});
  }
  return lights;
}

}  // namespace

RenderData::RenderData(const Scene& scene) {
  const size_t n = scene.patches.size();
  leafBoxes.resize(n);
  std::map<std::string, uint64_t> kinds;
  for (size_t i = 0; i < n; ++i) {
    leafBoxes[i] = scene.patches[i]->bounds();
    ++kinds[scene.patches[i]->kind()];
  }
  leafKinds.assign(kinds.begin(), kinds.end());
  features = featuresOf(scene);
  top.build(leafBoxes);

  const CameraDesc& cam = scene.camera;
  shading.camera = PerspectiveCamera(cam.position, cam.lookAt, cam.up, cam.fovYDegrees, scene.width, scene.height,
                                     cam.apertureRadius, cam.focusDistance, cam.shutterOpen, cam.shutterClose);
  shading.width = scene.width;
  shading.height = scene.height;
  shading.samplesPerPixel = scene.samplesPerPixel;
  shading.integrator = scene.integrator;
  shading.materials = scene.materials;
  shading.leafMaterial = scene.patchMaterial;
  shading.leafSide.resize(n);
  shading.leafDicingError.resize(n);
  for (size_t i = 0; i < n; ++i) {
    shading.leafSide[i] = leafBoxes[i].longestSide();
    shading.leafDicingError[i] = scene.patches[i]->dicingErrorCoefficient();
  }
  // Lights at infinity are picked by power through a disk of the scene's bounding radius, and
  // light paths leave them from such a disk about the scene's centre.
  Box3 all;
  for (const Box3& b : leafBoxes) all.extend(b);
  const float radius = all.empty() ? 1.0f : std::max(std::numeric_limits<float>::min(), 0.5f * length(all.extent()));
  const Vec3 center = all.empty() ? Vec3{} : all.center();
  shading.lights = LightSampler(scene.pointLights, patchLightsOf(scene), scene.moreLights, radius, center);
}

}  // namespace rayes
