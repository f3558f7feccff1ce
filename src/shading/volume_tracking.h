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
// Delta and ratio tracking draw each brick's tentative collisions from a stream of its own
// (brickStream: keyed by the vertex and the brick's number, never by the order bricks are
// visited in), so tracking restricted to one brick is independent of the others: a ray's first
// collision is the minimum over the bricks it crosses of each brick's first collision, and its
// transmittance the product of each brick's estimate. The per-brick functions (brickCollision,
// brickTransmittance) are the one implementation both routes call: the walk of one ray here,
// and the sorted engine's brick leaves (core/medium_leaves.h, shading/medium_leaf_tracker.h),
// which give the same bits (docs/design.md, "Volumes").
// Thread-safe: the functions read the media and write only the caller's TrackingRng and counts.
#pragma once
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>
#include "core/rng.h"
#include "core/medium_leaves.h"
#include "core/vec.h"
#include "shading/grid_reader.h"
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

// A ray in one medium's index space: the point at t is org + t·dir there as in the world, and
// `length` world units per unit of t.
struct IndexRay {
  Vec3 org, dir;
  float length;
};
IndexRay toIndex(const Medium& m, Vec3 org, Vec3 dir);

// Bricks numbered across a list of media, in list order (medium i's brick b is the number of
// the bricks before medium i, plus b): the brick streams' key. The top level's brick leaves are
// groups of them: the bricks of one medium whose cells share floor(cell / leafSide), leafSide³
// at most (kBrickLeafSide: one brick per leaf), numbered by medium, then by their first brick.
// Memory: 12 bytes per brick (the leaves' tables), only in a scene with media.
class BrickNumbering {
 public:
  BrickNumbering() = default;
  explicit BrickNumbering(MediumList media, int32_t leafSide = kBrickLeafSide);
  // Bricks per top-level leaf along each axis (docs/design.md, "Bricks as top-level leaves").
  static constexpr int32_t kBrickLeafSide = 1;
  struct Brick {
    uint32_t medium;
    int32_t brick;
  };
  Brick brickOf(uint32_t global) const;  // global < total()
  uint32_t firstOf(size_t medium) const { return first_[medium]; }
  uint32_t total() const { return total_; }
  // The top-level leaves: their number, leaf l's medium and its bricks' global numbers.
  uint32_t leaves() const { return uint32_t(leafMedium_.size()); }
  uint32_t mediumOfLeaf(uint32_t leaf) const { return leafMedium_[leaf]; }
  std::span<const uint32_t> bricksOfLeaf(uint32_t leaf) const {
    return {leafBricks_.data() + leafStart_[leaf], leafStart_[leaf + 1] - leafStart_[leaf]};
  }

 private:
  std::vector<uint32_t> first_;
  uint32_t total_ = 0;
  std::vector<uint32_t> leafStart_, leafBricks_, leafMedium_;
};

// The stream of one brick's tracking at a path vertex: the vertex key's seed mixed with the
// brick's number, from dimension `dimensionBase` (kFreeFlightDimensions or
// kTransmittanceDimensions).
TrackingRng brickStream(const RngKey& key, uint32_t dimensionBase, uint32_t globalBrick);
// The part of r inside brick `brick`'s cell, within (0, tEnd): an index-space slab test of the
// cell (both routes compute it so, not from a walk's running cell boundaries). False: empty.
bool brickSegment(const Medium& m, int32_t brick, const IndexRay& r, float tEnd, float& t0, float& t1);
// Delta tracking in one brick: the first real collision of r within its cell and (0, tEnd), or
// +inf. Voxels through `reader` (entered only where a tentative collision lands).
float brickCollision(const Medium& m, int32_t brick, const IndexRay& r, float tEnd, TrackingRng rng,
                     TrackingCounts& counts, GridReader& reader);
// An unbiased estimate in {0} ∪ [1/16, 1] of the transmittance of r within the brick's cell and
// (0, tEnd): ratio tracking with a Russian roulette below 1/16 (`delta`: delta tracking's 1 or 0).
float brickTransmittance(const Medium& m, int32_t brick, const IndexRay& r, float tEnd, bool delta, TrackingRng rng,
                         TrackingCounts& counts, GridReader& reader);

// The first real collision along org + t·dir for t in (0, tEnd) (tEnd may be infinite); the
// rates are per world unit, so t counts in units of |dir|.
// Stored bricks' voxels come through `cache` (null: read from their source at every visit).
Collision sampleCollision(MediumList media, Vec3 org, Vec3 dir, float tEnd, TrackingRng& rng, TrackingCounts& counts,
                          BrickCache* cache = nullptr);
// The walks of one ray: brickCollision's minimum and brickTransmittance's product over the
// bricks the ray crosses (each brick's stream from rng's key and dimension). The product is
// summed as TransmittanceProduct terms, the same bits as the sorted engine's brick leaves.
// An unbiased estimate of the transmittance of org + t·dir, t in (0, tEnd), in [0, 1]. Below a
// weight of 1/16 a brick's estimate survives a Russian roulette (weight raised back to 1/16), so a
// dense medium costs a bounded number of steps per brick on average, not its optical depth.
float walkTransmittance(MediumList media, Vec3 org, Vec3 dir, float tEnd, bool delta, TrackingRng& rng,
                        TrackingCounts& counts, BrickCache* cache = nullptr);
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
