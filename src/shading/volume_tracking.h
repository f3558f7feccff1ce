// Null-collision tracking through the media of a scene (shading/medium.h): the free-flight
// distance of a ray by delta tracking, and the transmittance of a segment by ratio tracking
// (Novák et al. 2014), both with per-brick majorants: a ray walks the brick cells it crosses in
// index space (a 3D DDA, Amanatides and Woo), and within a cell draws tentative collisions at the
// cell's majorant rate, so empty space costs one step per cell and thin bricks few lookups.
//
// Several media overlap by superposition: their real collisions are independent Poisson
// processes, so the first collision of the sum is the earliest of each medium's first collision,
// and the transmittance is the product of theirs.
//
// Random numbers are counter-based (core/rng.h sampleUniform keyed by the path vertex and a
// running dimension), so a path's collisions are the same bits for any thread count or order.
// Thread-safe: the functions read the media and write only the caller's TrackingRng and counts.
#pragma once
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include "core/rng.h"
#include "core/vec.h"
#include "shading/medium.h"

namespace rayes {

using MediumList = std::span<const std::shared_ptr<const Medium>>;

// A stream of independent uniform numbers for one path vertex's tracking.
struct TrackingRng {
  RngKey key;
  uint32_t dimension;  // the next one; streams of one vertex start at distinct bases
  float operator()() { return sampleUniform(key, dimension++); }
};
// Dimension bases far above the path tracer's per-vertex dimensions (path_tracer.cpp's Dim).
constexpr uint32_t kFreeFlightDimensions = 1u << 20, kTransmittanceDimensions = 2u << 20;

struct TrackingCounts {
  uint64_t lookups = 0;  // density lookups (tentative collisions)
  uint64_t cells = 0;    // brick cells visited
};

struct Collision {
  float t = std::numeric_limits<float>::infinity();  // ray parameter (the ray's own units)
  int32_t medium = -1;                                // -1: no collision before tEnd
};

// The first real collision along org + t·dir for t in (0, tEnd) (tEnd may be infinite); the
// rates are per world unit, so t counts in units of |dir|.
// Stored bricks' voxels come through `cache` (null: read from their source at every visit).
Collision sampleCollision(MediumList media, Vec3 org, Vec3 dir, float tEnd, TrackingRng& rng, TrackingCounts& counts,
                          BrickCache* cache = nullptr);
// An unbiased estimate of the transmittance of org + t·dir, t in (0, tEnd), in [0, 1]. Below a
// weight of 1/16 a path survives a Russian roulette (weight raised back to 1/16), so a dense
// medium costs a bounded number of steps on average, not its optical depth.
float ratioTransmittance(MediumList media, Vec3 org, Vec3 dir, float tEnd, TrackingRng& rng, TrackingCounts& counts,
                         BrickCache* cache = nullptr);

// An unbiased estimate of the emitted radiance gathered along org + t·dir for t in (0, tEnd),
// ∫ σ_a ρ Le ds without the transmittance: called with tEnd the ray's free-flight distance
// (sampleCollision's collision, or the surface), whose expectation over that distance supplies
// the transmittance, E[∫₀^tEnd f] = ∫ T(s) f(s) ds. Points at the density's majorant rate
// σ_t·m (so where ρ = 0 nothing is looked up), each adding σ_a ρ(x) Le(x) / (σ_t m). Zero
// without work for media that do not emit.
Rgb emissionAlong(MediumList media, Vec3 org, Vec3 dir, float tEnd, TrackingRng& rng, TrackingCounts& counts,
                  BrickCache* cache = nullptr);
// Dimension base of emissionAlong's stream.
constexpr uint32_t kEmissionDimensions = 3u << 20;

// Henyey-Greenstein phase function over propagation directions: `in` the direction the light
// travelled to the scattering point, `out` the one it leaves along (unit vectors); g > 0 scatters
// forward. Normalised over the sphere, so the density of a sampled direction equals the value.
float henyeyGreenstein(float cosInOut, float g);
// A direction sampled exactly from the phase function about `in` (u1, u2 uniform in [0, 1)).
Vec3 sampleHenyeyGreenstein(Vec3 in, float g, float u1, float u2);

}  // namespace rayes
