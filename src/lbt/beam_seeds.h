// The first corner rays of light beams (docs/design.md, "Light beam tracing"), seen from each
// light: the light's view of every scatterer leaf (a leaf whose material reflects or refracts
// caustics) is cut into a grid of cells, each cell two generator triangles of corner rays.
// Neighbouring cells share their corner rays, so the beams tile the light's view without gaps.
//   Point and spot lights: a cube map of directions about the light, N×N cells per face; a
//     cell is used when the projection of a scatterer leaf's box covers it. Φ = I·Ω, Ω the
//     solid angle of the triangle of corner directions (exact), I at its central direction
//     (a spot's falloff there).
//   Distant lights: a grid of parallel rays on a plane facing the light, square cells of side
//     (extent of the scatterers' projection)/N; Φ = E·area. A sun disk is treated as its
//     central direction.
// The level of detail the surfaces are diced at follows from the corner rays' cones (one
// cell's width), so the tracer dices scatterers at the light's resolution.
//   Area lights (emissive patches): k×k points at the centres of a grid over the patch's (u, v)
//     square, each a point light with a cosine lobe, I(ω) = L·A_i·max(0, cos(n, ω)) with A_i its
//     stratum's area (exact for parallelograms, the midpoint rule otherwise), so Σ power = π·L·A.
//     A soft caustic becomes k² sharp ones: a bias that falls as k grows (docs/design.md).
// Environment lights get no beams (their caustics stay with the path tracer).
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>
#include "core/box.h"
#include "shading/light.h"

namespace rayes {

struct BeamLights {
  std::vector<PointLight> points;
  std::vector<SpotLight> spots;
  std::vector<DistantLight> distants;
  std::vector<PatchLight> patches;
  int areaSamples = 2;  // k: points per side of an area light's grid
  bool empty() const { return points.empty() && spots.empty() && distants.empty() && (patches.empty() || areaSamples < 1); }
};

// An area light's sample point: a point source of intensity `intensity`·max(0, cos(normal, ω)).
struct AreaLightPoint {
  Vec3 position, normal;
  Rgb intensity;  // L·A_i, W/sr along the normal
};
// The k×k points of each patch light (two-sided: one per side), lifted off the surface.
std::vector<AreaLightPoint> areaLightPoints(std::span<const PatchLight> patches, int k, const Box3& sceneBounds);

struct BeamSeeds {
  // Corner rays: unit directions; the cone of a cell.
  std::vector<Vec3> org, dir;
  std::vector<float> coneWidth, coneSpread;
  // Generator triangles (indices into the corner rays) and their flux.
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<Rgb> flux;

  // The generator triangles [first, last) with the corner rays they use (in their order here),
  // so a batch of beams can be traced alone: each corner ray's path depends on itself only.
  BeamSeeds range(size_t first, size_t last) const;
};

// resolution N ≥ 1 (cells per face side, or per side of a distant light's grid);
// sceneBounds holds every leaf (distant lights start outside it).
BeamSeeds seedBeams(const BeamLights& lights, std::span<const Box3> scattererBoxes, const Box3& sceneBounds,
                    int resolution);

// Solid angle of the spherical triangle of unit directions a, b, c (Van Oosterom–Strackee);
// 0 for degenerate triangles, never negative.
double sphericalTriangleArea(Vec3 a, Vec3 b, Vec3 c);

}  // namespace rayes
