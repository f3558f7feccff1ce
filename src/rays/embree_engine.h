// The peer RayEngine (rays/ray_engine.h): what a renderer without on-demand dicing does. Every
// patch is diced once, up front, by the same Patch::dice the SortedEngine uses (displacement
// included), into one Embree grid (RTC_GEOMETRY_TYPE_GRID) per patch, geometry id = leaf id; rays
// are traced with Embree's stream API (rtcIntersect1M / rtcOccluded1M) in parallel chunks.
//
// Level per patch: `fixed` dices every patch at maxLod; `auto` at the finest level any camera
// ray's footprint needs on it: the box's nearest distance d to the camera position (less the
// lens radius), the footprint there d * pixel spread (camera rays start with width 0), through
// levelForFootprint(Patch::sizeBound(), footprint, maxLod), the rule the SortedEngine applies per
// ray. Nearest distance <= any camera ray's entry distance, so no camera ray sees a patch coarser
// than Rayes would dice it for that ray; secondary rays see the same grids (Rayes gives them
// coarser levels from their wider cones).
//
// Hits are the SortedEngine's at the patch's level: Embree splits a grid cell along (x+1, y)-(x,
// y+1), Rayes along p00-p11, so every grid row is stored mirrored in u, which makes the two
// diagonals, and so the triangles, the same. (u, v), the micro-quad, ng (the triangle's unit
// normal, in double) and ns (blendNormals of the quad's vertex normals) are computed from our
// copy of the vertices, as the micro-quad test does. Shadow rays: any hit; a shadow hit's leaf is
// 0 (Embree does not say which occluder), t is 0. ignoreLeaf: a context filter rejects hits on
// it. Origin-leaf rule: a secondary ray leaves a patch at that patch's only level, so it sees the
// grid it left, as in Rayes; there are no border regions (cracks between patches diced at
// different levels stay open, as in any fixed tessellation: the auto levels of neighbours can
// differ by one or more).
//
// Motion: a moving patch becomes an Embree geometry with S uniform time steps over [0, 1]
// (rtcSetGeometryTimeStepCount; one vertex buffer per step). S - 1 is the smallest N <= 64
// for which every keyframe time (clamped to [0, 1]) is a multiple of 1/N, so Embree's linear
// blend between steps equals the patch's own piecewise-linear motion (each step is the patch at
// time j/N, interpolated like Rayes's MovingPatch); keyframes on no such grid use N = 64 and
// are approximated.
//
// Memory: estimatedBytes() (vertices x time steps x (positions + normals + Embree's bytes per
// vertex, kEmbreeBytesPerVertex)) is checked against the limit before anything is allocated;
// over it, the constructor throws InputError naming --memory-limit. Not thread-safe as a whole;
// trace() runs on all threads.
#pragma once
#include <memory>
#include <vector>
#include "core/box.h"
#include "geometry/leaf_source.h"
#include "rays/leaf_query_runs.h"
#include "rays/ray_engine.h"

namespace rayes {

// What `auto` needs of the camera: camera rays start within apertureRadius of position with width
// 0 and grow by spread per unit distance (one pixel's angle).
struct CameraFootprint {
  Vec3 position;
  float apertureRadius = 0;
  float spread = 0;
};

struct EmbreeSettings {
  int maxLod = 10;
  bool autoLod = false;          // false: every patch at maxLod
  CameraFootprint camera;        // for autoLod
  size_t memoryLimit = 0;        // 0: no limit
  // RTC_SCENE_FLAG_ROBUST: Embree's watertight triangle test. Off for renders (the peer as it is
  // fastest); on where hits are compared ray for ray with ours, where Embree's default test can
  // let a ray through an edge two micro-triangles share.
  bool robust = false;
};

class EmbreeEngine : public RayEngine {
 public:
  // Throws ResourceError("--memory-limit") when estimatedBytes exceeds settings.memoryLimit or
  // what the process's memory limit has available (core/memory.h: a cgroup, RLIMIT_AS). The
  // estimate reads only the leaves' boxes and facts: a generated leaf's patch is made when it
  // is tessellated, never before the check.
  EmbreeEngine(const LeafSource& leaves, const EmbreeSettings& settings);
  ~EmbreeEngine() override;
  EmbreeEngine(const EmbreeEngine&) = delete;
  EmbreeEngine& operator=(const EmbreeEngine&) = delete;

  void trace(RayBatch& batch, GenerationStats& stats, TraceTimes& times) override;
  // Rays go to Embree in fixed-size chunks on the stack: nothing per ray beyond the RayBatch.
  size_t bytesPerRay() const override { return bytesPerRaySlot(); }
  static constexpr size_t bytesPerRaySlot() { return 0; }
  size_t fixedBytes() const override { return stats_.fixedBytes; }
  EngineStats engineStats() const override { return stats_; }

  int level(uint32_t leaf) const { return leaves_[leaf].level; }

  // The `auto` level of a patch with box `bounds` and size bound `size`.
  static int autoLevel(const Box3& bounds, float size, const CameraFootprint& camera, int maxLod);
  // Embree's own bytes per grid vertex and time step: the peak of its allocations during
  // rtcCommitScene, measured on the teapot at levels 8 and 10 (26-33 B; bench/RESULTS-peer.md)
  // and rounded up.
  static constexpr size_t kEmbreeBytesPerVertex = 36;
  // Positions (12 B, mirrored for Embree) and normals (12 B) we keep per vertex and time step.
  static constexpr size_t kOwnBytesPerVertex = 2 * sizeof(Vec3);
  // Time steps Embree gets for a patch (1 for a static one).
  static int timeSteps(const Patch& patch);

 private:
  struct Leaf {
    int level = 0, steps = 1;
    size_t first = 0;  // first vertex of step 0 in positions_/normals_
  };
  struct Device;
  void tessellate(const LeafSource& leaves);
  void build(bool robust);
  // With dpd, also the hit quad's partials (quadPartials, as DiceBuffer gives them).
  void closestHit(const RayBatch& b, uint32_t i, uint32_t leaf, float t, float eu, float ev, RayHit& hit,
                  HitDerivatives* dpd) const;

  std::vector<Leaf> leaves_;
  std::vector<Vec3> positions_;  // per leaf, per step, rows mirrored in u; one Vec3 of padding
  std::vector<Vec3> normals_;    // same slices, not mirrored, unnormalised blends between keyframes
  std::unique_ptr<Device> device_;
  EngineStats stats_;
  LeafQueryRuns queries_;
};

}  // namespace rayes
