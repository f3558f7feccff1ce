// START HERE for light beam tracing. The beam segments of a render binned to the top-level
// leaves their volume overlaps (docs/design.md, "Light beam tracing"), and the caustic gather
// over them: the path tracer's CausticRadiance (shading/path_tracer.h). A segment's volume is the box of its corner rays up to
// their ends, widened for glossy segments by 5σ of angle (beamBounds); the boxes are binned
// with the same top-level BVH the camera rays use (TopLevelBvh::overlapping), so segments need
// no hierarchy of their own. Within a leaf the segments are binned again into a uniform grid
// over the leaf's box (about 4 segments per cell, at most 64 cells per axis; a segment goes to
// the cells its eight lengthwise pieces' boxes reach), so a large
// receiver patch under many beams does not make every gather visit all of them; a gather at a
// point of leaf L visits the segments of the cell of L's grid that holds the point.
//
// What is and is not in the reorder pipeline: corner rays are traced as RayBatch generations by
// the ray engine (sorted by leaf, diced on demand); the binning uses the top level; the gathers
// run in the path tracer's shading step, whose paths are sorted by (material, leaf), so a
// leaf's gathers run together -- but not inside the Tracer's per-leaf stage.
//
// Memory: bytes() = segments + bin entries + cell offsets; the constructor refuses (InputError
// naming --beam-memory) when that exceeds the budget. Immutable and thread-safe after
// construction; gathers visit a leaf's segments in segment order (deterministic).
#pragma once
#include <cstdint>
#include <span>
#include <vector>
#include "lbt/beam_segment.h"
#include "shading/path_tracer.h"
#include "toplevel/toplevel_bvh.h"

namespace rayes {

class BeamStore final : public CausticRadiance {
 public:
  // leafBoxes: the boxes the top level was built over (Patch::bounds per leaf); receives: per
  // leaf, whether gathers happen there (empty: every leaf), so scatterers get no bins.
  BeamStore(std::vector<BeamSegment> segments, const TopLevelBvh& top, std::span<const Box3> leafBoxes,
            size_t memoryBudget, std::span<const uint8_t> receives = {});
  // Calls add(psi, E) for each segment of the cell of `leaf`'s grid holding x that lights x
  // (psi: the light's unit direction there, E: irradiance, cosine included), in segment order.
  template <class Add>
  void gather(uint32_t leaf, Vec3 x, Vec3 normal, Add&& add) const {
    const auto [first, last] = cellRange(leaf, x);
    for (uint64_t e = first; e != last; ++e) {
      Vec3 psi;
      const Rgb irradiance = beamIrradiance(segments_[entries_[e]], x, normal, psi);
      if (maxComponent(irradiance) > 0) add(psi, irradiance);
    }
  }
  // The caustic radiance at a diffuse vertex: Σ f(wo, -psi)·E over the gathered segments.
  Rgb radiance(const DiffuseVertex& v) const override;

  size_t segmentCount() const { return segments_.size(); }
  size_t binEntries() const { return entries_.size(); }
  size_t bytes() const {
    return bytesFor(segments_.size(), entries_.size(), offsets_.size()) + grids_.size() * sizeof(LeafGrid);
  }
  static size_t bytesFor(size_t segments, size_t entries, size_t cells) {
    return segments * sizeof(BeamSegment) + entries * sizeof(uint32_t) + cells * sizeof(uint64_t);
  }
  std::span<const BeamSegment> segments() const { return segments_; }

  // One leaf's grid of bins (its cells are [first, the next leaf's first); none when equal).
  struct LeafGrid {
    Box3 box;
    int n[3] = {1, 1, 1};
    uint64_t first = 0;
  };

 private:
  std::pair<uint64_t, uint64_t> cellRange(uint32_t leaf, Vec3 x) const;
  std::vector<BeamSegment> segments_;
  std::vector<LeafGrid> grids_;
  std::vector<uint64_t> offsets_;   // cell c's segments: entries_[offsets_[c], offsets_[c + 1])
  std::vector<uint32_t> entries_;
};

}  // namespace rayes
