// START HERE for light beam tracing. The beam segments of a render binned to the top-level
// leaves their volume overlaps (docs/design.md, "Light beam tracing"), and the caustic gather
// over them: the path tracer's CausticRadiance (shading/path_tracer.h). A segment's volume is
// the box of its corner rays up to their ends, widened for glossy segments by kLobeReach·σ (4σ)
// of angle (beamBounds; the per-leaf cells below by 5σ pieces); the boxes are binned
// with the same top-level BVH the camera rays use (TopLevelBvh::overlapping), so segments need
// no hierarchy of their own. Within a leaf the segments are binned again into a uniform grid
// over the leaf's box (about 4 segments per cell, at most 64 cells per axis; a segment goes to
// the cells its eight lengthwise pieces' boxes reach), so a large
// receiver patch under many beams does not make every gather visit all of them; a gather at a
// point of leaf L visits the segments of the cell of L's grid that holds the point.
//
// All of it runs through the reorder pipeline: corner rays are traced as RayBatch generations by
// the ray engine (sorted by leaf, diced on demand); the binning uses the top level; the gathers
// are leaf queries (core/leaf_queries.h): the path tracer posts one at a diffuse vertex, the
// engine sorts them by leaf with the candidates' sort and runs each leaf's gathers in that
// leaf's task of its per-leaf stage during the next trace() (rays/sorted_engine.cpp), and the path
// adds the result after that trace, where the direct call used to add it (same bits).
//
// Memory: bytes() = segments and their envelopes + bin entries + cell offsets + leaf grids. The constructor refuses
// (ResourceError naming --beam-memory) a budget below minimumBytes (one beam); a store that needs
// more than its budget, or whose arrays (and the counts and cell lists it holds while it bins,
// three passes over the segments that keep no per-segment lists) do not fit the account it is
// given, keeps nothing and says so (fits() false, neededBytes()): the caller processes its
// beams in batches (lbt/beam_batches.h). Its bytes besides the segments stay on that account
// until it is destroyed. Immutable and thread-safe after
// construction; gathers visit a leaf's segments in segment order (deterministic).
// A gather counts a segment only where x, clamped into the leaf's box, lies in the segment's
// reach (the boxes of its pieces, `reaches`), which its bins always cover: so what a gather
// sums does not depend on how the grid was shaped, nor on which other segments share the store.
// Before its irradiance, each segment's envelope (lbt/beam_segment.h, kept beside it) rules out
// the points where it is dark: most of what a cell offers.
#pragma once
#include <cstdint>
#include <span>
#include <utility>
#include <vector>
#include "lbt/beam_budget.h"
#include "lbt/beam_segment.h"
#include "shading/path_tracer.h"
#include "toplevel/toplevel_bvh.h"

namespace rayes {

class BeamStore final : public CausticRadiance {
 public:
  // leafBoxes: the boxes the top level was built over (Patch::bounds per leaf); receives: per
  // leaf, whether gathers happen there (empty: every leaf), so scatterers get no bins.
  BeamStore(std::vector<BeamSegment> segments, const TopLevelBvh& top, GatedSpan<Box3> leafBoxes,
            size_t memoryBudget, std::span<const uint8_t> receives = {}, int maxDepth = 1 << 30,
            BeamBudget* account = nullptr);
  // Calls add(psi, E) (or add(psi, E, segment)) for each segment of the cell of `leaf`'s grid
  // holding x that lights x (psi: the light's unit direction there, E: irradiance, cosine
  // included), in segment order.
  template <class Add>
  void gather(uint32_t leaf, Vec3 x, Vec3 normal, Add&& add) const {
    gather(leaf, x, normal, std::forward<Add>(add), [](const BeamSegment&) { return true; });
  }
  // The same over the segments `counts` accepts, asked before any work on a segment.
  template <class Add, class Counts>
  void gather(uint32_t leaf, Vec3 x, Vec3 normal, Add&& add, Counts&& counts) const {
    const auto [first, last] = cellRange(leaf, x);
    if (first == last) return;
    const Box3& box = grids_[leaf].box;
    const Vec3 inside = vmin(vmax(x, box.lo), box.hi);
    for (uint64_t e = first; e != last; ++e) {
      const BeamSegment& s = segments_[entries_[e]];
      if (!counts(s) || envelopes_[entries_[e]].excludes(x)) continue;
      // The reach test after the irradiance: its eight boxes (a tan each) cost about as much as
      // the irradiance's early outs, and most points in a segment's cell are in its reach.
      Vec3 psi;
      const Rgb irradiance = beamIrradiance(s, x, normal, psi);
      if (!(maxComponent(irradiance) > 0 && reaches(s, inside))) continue;
      add(psi, irradiance);
    }
  }
  // The caustic radiance at a diffuse vertex: sum + f(wo, -psi)·E over the gathered segments,
  // added one by one in segment order (a batch continues the previous batch's sum). As the path
  // tracer it complements counts them, only paths within maxDepth: camera bounce + light-path
  // vertex (scatterings + 1) ≤ maxDepth.
  Rgb radiance(const DiffuseVertex& v, Rgb sum) const;
  Rgb radiance(const DiffuseVertex& v) const override { return radiance(v, Rgb{}); }

  // Whether the segments and their bins fit the budget (else the store holds nothing).
  bool fits() const { return needed_ == bytes(); }
  size_t neededBytes() const { return needed_; }
  // The smallest budget that holds one segment in one cell with `leaves` leaf grids.
  static size_t minimumBytes(size_t leaves) { return bytesFor(1, 1, leaves + 1) + leaves * sizeof(LeafGrid); }
  // x lies in one of the boxes a segment is binned by (its kPieces lengthwise pieces).
  static bool reaches(const BeamSegment& s, Vec3 x);
  static constexpr int kPieces = 8;

  size_t segmentCount() const { return segments_.size(); }
  size_t binEntries() const { return entries_.size(); }
  size_t bytes() const {
    return bytesFor(segments_.size(), entries_.size(), offsets_.size()) + grids_.size() * sizeof(LeafGrid);
  }
  static size_t bytesFor(size_t segments, size_t entries, size_t cells) {
    return segments * (sizeof(BeamSegment) + sizeof(BeamEnvelope)) + entries * sizeof(uint32_t) +
           cells * sizeof(uint64_t);
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
  void build(const TopLevelBvh& top, GatedSpan<Box3> leafBoxes, size_t budget, std::span<const uint8_t> receives,
             BeamCharge& transient);
  static void leavesOf(const BeamSegment& s, const TopLevelBvh& top, std::span<const uint8_t> receives,
                       std::vector<uint32_t>& out, TraversalScratch& scratch);
  std::vector<BeamSegment> segments_;
  std::vector<BeamEnvelope> envelopes_;  // per segment: the gather's cheap early out
  std::vector<LeafGrid> grids_;
  std::vector<uint64_t> offsets_;   // cell c's segments: entries_[offsets_[c], offsets_[c + 1])
  std::vector<uint32_t> entries_;
  size_t needed_ = 0;
  int maxDepth_;
  BeamCharge charge_;  // what it holds besides the segments, on the account it was built with
};

}  // namespace rayes
