#include "app/render_data.h"
#include <algorithm>
#include <limits>
#include <map>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace rayes {
namespace {

SceneFeatures featuresOf(const Scene& scene, const std::vector<Box3>& leafBoxes, const std::vector<LeafFacts>& facts) {
  SceneFeatures f;
  for (size_t i = 0; i < facts.size(); ++i) {
    f.movingLeaves += facts[i].timeSamples > 1;
    f.displacedLeaves += facts[i].displaced;
    f.subdivisionLeaves += facts[i].subdivision;
    f.borderClosureLeaves += facts[i].borderClosure;
    const float spacing = leafBoxes[i].relativeSpacing();
    f.coarsestRelativeSpacing = std::max(f.coarsestRelativeSpacing, double(spacing));
    f.lowPrecisionLeaves += spacing > 0x1p-16f;
  }
  if (scene.uvs)
    for (size_t i = 0; i < facts.size(); ++i) f.uvLeaves += scene.uvs->has(uint32_t(i));
  f.uvSetsDropped = scene.uvSetsDropped;
  f.shutterOpen = scene.camera.shutterClose > scene.camera.shutterOpen;
  f.environment = scene.moreLights.environment != nullptr;
  f.distantLights = scene.moreLights.distants.size();
  for (const Material& m : scene.materials) f.texturedMaterials += m.textured();
  f.volumes = scene.media.size();
  for (const auto& m : scene.media) {
    f.volumeBricks += m->bricks();
    f.volumeVoxels += m->voxels();
    f.volumeBytes += m->bytes();
  }
  f.volumeLoadSeconds = scene.volumeLoadSeconds;
  return f;
}

}  // namespace

std::vector<PatchLight> patchLightsOf(const Scene& scene) {
  std::vector<PatchLight> lights;
  for (size_t i = 0; i < scene.leaves.size(); ++i) {
    const Material& m = scene.materials[scene.leafMaterial[i]];
    if (!m.emits()) continue;
    PatchPtr patch = scene.leaves.patch(i);
    lights.push_back({[patch](float u, float v, Vec3& p, Vec3& nrm) {
                        const SurfacePoint sp = patch->evaluate(u, v);
                        p = sp.p; nrm = sp.n;
                      },
                      m.emission, m.twoSided, uint32_t(i)});
  }
  return lights;
}

RenderData::RenderData(const Scene& scene) {
  const size_t n = scene.leaves.size();
  leafBoxes.resize(n);
  // The facts are gathered once (a generated leaf's patch is made and dropped again); only
  // the dicing error is kept per leaf.
  std::vector<LeafFacts> facts(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      leafBoxes[i] = scene.leaves.bounds(i);
      facts[i] = scene.leaves.facts(i);
    }
  });
  std::map<std::string, uint64_t> kinds;
  for (const LeafFacts& f : facts) ++kinds[f.kind];
  leafKinds.assign(kinds.begin(), kinds.end());
  features = featuresOf(scene, leafBoxes, facts);
  top.build(leafBoxes);

  const CameraDesc& cam = scene.camera;
  shading.camera = PerspectiveCamera(cam.position, cam.lookAt, cam.up, cam.fovYDegrees, scene.width, scene.height,
                                     cam.apertureRadius, cam.focusDistance, cam.shutterOpen, cam.shutterClose);
  shading.width = scene.width;
  shading.height = scene.height;
  shading.samplesPerPixel = scene.samplesPerPixel;
  shading.integrator = scene.integrator;
  shading.materials = scene.materials;
  shading.leafMaterial = scene.leafMaterial;
  shading.media = scene.media;
  shading.texCoords = scene.uvs;  // null when no leaf has a uv set: lookups read (u, v) alone
  shading.leafSide.resize(n);
  shading.leafDicingError.resize(n);
  for (size_t i = 0; i < n; ++i) {
    shading.leafSide[i] = leafBoxes[i].longestSide();
    shading.leafDicingError[i] = facts[i].dicingError;
  }
  // Lights at infinity are picked by power through a disk of the scene's bounding radius, and
  // light paths leave them from such a disk about the scene's centre.
  Box3 all;
  for (const Box3& b : leafBoxes) all.extend(b);
  const float radius = all.empty() ? 1.0f : std::max(std::numeric_limits<float>::min(), 0.5f * length(all.extent()));
  const Vec3 center = all.empty() ? Vec3{} : all.center();
  shading.lights = LightSampler(scene.pointLights, patchLightsOf(scene), scene.moreLights, radius, center);
}

size_t RenderData::leafTableBytes() const {
  return leafBoxes.capacity() * sizeof(Box3) + shading.leafMaterial.capacity() * sizeof(uint32_t) +
         shading.leafSide.capacity() * sizeof(float) + shading.leafDicingError.capacity() * sizeof(float);
}

}  // namespace rayes
