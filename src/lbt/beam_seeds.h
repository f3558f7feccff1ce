// The first corner rays of light beams (docs/design.md, "Light beam tracing"), seen from each
// light: every scatterer leaf (a leaf whose material reflects or refracts caustics) is cut into
// a grid over its own (u, v) square, at a level of detail chosen from the light's point of view,
// and each grid cell is two generator triangles whose corner rays leave the light toward the
// cell's corners on the surface. Neighbouring cells of a leaf share their corner rays, so its
// beams tile it without gaps, and no beam spans two leaves (a facet's edge never cuts a beam).
//   Point and spot lights: corner rays leave the light; a leaf's grid has m_u × m_v cells with
//     m = ceil(angle the leaf spans from the light along u or v / (2/N)), N the resolution (2/N:
//     the cell of an N×N cube-map face at its centre). Φ = I·Ω, Ω the solid angle of the
//     triangle of corner directions (exact), I at its central direction (a spot's falloff there).
//   Distant lights: parallel corner rays aimed at the scatterers, not at the scene: they start
//     on the plane across the light twice the scatterers' bounding radius before their centre
//     (so a small mirror in a huge scene gets the same beams, and the same float precision,
//     as in a small one), and each such corner ray's way back toward the light is traced too
//     (`fromAfar`: an occluder there takes it off its aim, as a surface in front would);
//     cells of side about (extent of the scatterers' projection)/N; Φ = E·(the triangle's area
//     across the light). A sun disk is treated as its central direction.
//   Area lights (emissive patches): k×k points at the centres of a grid over the patch's (u, v)
//     square, each a point light with a cosine lobe, I(ω) = L·A_i·max(0, cos(n, ω)) with A_i its
//     stratum's area (exact for parallelograms, the midpoint rule otherwise), so Σ power = π·L·A.
//     A soft caustic becomes k² sharp ones: a bias that falls as k grows (docs/design.md).
// The aim points are inset by kSeedInset of (u, v) from the leaf's borders, so a corner ray does
// not find the neighbouring leaf. A corner ray's first hit must be its own leaf within a quarter
// cell of its aim in (u, v) (BeamSeeds::aim): where another surface is in front, or the leaf
// folds over itself as the light sees it, those directions belong to the front surface's grid,
// and the tracer drops (none on target) or splits (some) such a beam, so nothing is counted twice.
// The level of detail the surfaces are diced at follows from the corner rays' cones (one
// cell's width), so the tracer dices scatterers at the light's resolution.
// Environment lights get no beams (their caustics stay with the path tracer).
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>
#include "core/box.h"
#include "lbt/beam_budget.h"
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

// A scatterer leaf as the seeding sees it: its surface point at (u, v) ∈ [0, 1]² (the patch's
// parameters, those RayHit reports).
struct ScattererSurface {
  uint32_t leaf = 0;
  std::function<Vec3(float u, float v)> position;
};

// How far (in u and v) a grid's aim points keep from the leaf's borders: flux lost ≤ 4·10⁻⁴ of
// a leaf's.
inline constexpr float kSeedInset = 1e-4f;

// Where a first corner ray must land: its leaf, within `tol` of (u, v).
struct SeedAim {
  uint32_t leaf = 0xffffffffu;
  float u = 0, v = 0, tolU = 0, tolV = 0;
  bool hits(uint32_t hitLeaf, float hu, float hv) const {
    return hitLeaf == leaf && std::fabs(hu - u) <= tolU && std::fabs(hv - v) <= tolV;
  }
};

struct BeamSeeds {
  // Corner rays: unit directions; the cone of a cell; where each must land.
  std::vector<Vec3> org, dir;
  std::vector<float> coneWidth, coneSpread;
  std::vector<SeedAim> aim;
  std::vector<uint8_t> fromAfar;  // 1: the way back toward the (distant) light is traced too
  // Generator triangles (indices into the corner rays) and their flux.
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<Rgb> flux;

  // The generator triangles [first, last) with the corner rays they use (in their order here),
  // so a batch of beams can be traced alone: each corner ray's path depends on itself only.
  BeamSeeds range(size_t first, size_t last) const;
  size_t bytes() const { return bytesFor(org.size(), triangles.size()); }
  static size_t bytesFor(size_t corners, size_t triangles) {
    return corners * (2 * sizeof(Vec3) + 2 * sizeof(float) + sizeof(SeedAim) + sizeof(uint8_t)) +
           triangles * (sizeof(std::array<uint32_t, 3>) + sizeof(Rgb));
  }
};

// A chunk of the seeds: generator triangles [first, first + seeds.triangles.size()) of the whole
// order, with the corner rays they use, and the budget's bytes for its arrays.
struct SeedChunk {
  BeamSeeds seeds;
  size_t first = 0;
  BeamCharge charge;
};

// resolution N ≥ 1 (as above); sceneBounds holds every leaf (distant lights start outside it).
// Triangles come light by light, leaf by leaf in the order given, row by row.
BeamSeeds seedBeams(const BeamLights& lights, std::span<const ScattererSurface> scatterers, const Box3& sceneBounds,
                    int resolution);
// The same seeds streamed: chunks of at least chunkTriangles triangles (read at each row's end:
// the sink may lower it for the next chunks; a chunk ends with a row
// of a leaf's grid; the corner rays of the row it starts at are repeated in it), handed to
// `sink` in order, only the triangles of [first, last) (others are skipped). Their bytes, the
// leaves' samples and the area lights' points are taken from `budget` (may be null) before
// they are allocated (BeamBudgetExceeded when they do not fit).
void seedBeams(const BeamLights& lights, std::span<const ScattererSurface> scatterers, const Box3& sceneBounds,
               int resolution, const size_t& chunkTriangles, size_t first, size_t last, BeamBudget* budget,
               const std::function<void(SeedChunk&&)>& sink);

// Solid angle of the spherical triangle of unit directions a, b, c (Van Oosterom–Strackee);
// 0 for degenerate triangles, never negative.
double sphericalTriangleArea(Vec3 a, Vec3 b, Vec3 c);

}  // namespace rayes
