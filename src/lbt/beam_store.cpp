#include "lbt/beam_store.h"
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <string>
#include <utility>
#include <vector>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include "core/error.h"

namespace rayes {
namespace {
constexpr int kMaxCellsPerAxis = 64;
constexpr double kSegmentsPerCell = 4;

// A leaf's grid: about count / kSegmentsPerCell cubic-ish cells over its box, only along the
// axes the box extends in.
void shapeGrid(BeamStore::LeafGrid& g, size_t count) {
  const Vec3 e = g.box.extent();
  const float longest = maxComponent(e);
  int dims = 0;
  for (int a = 0; a < 3; ++a) dims += e[a] > 1e-3f * longest;
  const double target = std::max(1.0, double(count) / kSegmentsPerCell);
  const double h = dims > 0 ? longest / std::pow(target, 1.0 / dims) : 1.0;
  for (int a = 0; a < 3; ++a)
    g.n[a] = e[a] > 1e-3f * longest && h > 0 ? std::clamp(int(std::ceil(e[a] / h)), 1, kMaxCellsPerAxis) : 1;
}

int cellOf(const BeamStore::LeafGrid& g, int a, float x) {
  const float e = g.box.hi[a] - g.box.lo[a];
  if (g.n[a] == 1 || !(e > 0)) return 0;
  const float c = (x - g.box.lo[a]) / e * float(g.n[a]);
  return std::clamp(int(c), 0, g.n[a] - 1);  // NaN and ±inf clamp too (int of NaN avoided below)
}
int safeCell(const BeamStore::LeafGrid& g, int a, float x) { return std::isfinite(x) ? cellOf(g, a, x) : 0; }

// The lobe's growth per unit length of a segment's pieces: tan of kPieceReach·σ (0 for
// specular). Wider than the gather's kLobeReach on purpose: the pieces' boxes are not a proven
// superset of the points the gather reaches (a footprint stretched along a tilted receiver
// reaches past them). Measured on lbt-ring-glossy (160x120 8 spp): pieces at 4σ lose 0.23 % of
// the image mean against 5σ, and 5σ still 0.22 % against 10σ (bench/history/2026-11.md,
// "Glossy gathers"). Bins that provably hold the envelope's reach were built and
// measured (same file, "Exact bins for glossy beams, tried"): against the light tracer they make the
// ring's glossy caustic 1.3 % bright instead of 0.24 % dark (the σ = 0.001 ring: +0.21 %), so
// the gather's flux-plane formula itself is about 1 % bright at σ = 0.05 -- errors of order σ²,
// presumably the receiver's cosine taken with Ψ rather than with the direction the light
// arrives from, and the angular map's planar area element (α/sin α) -- and they cost 2-7x the
// CPU. The model, not the bins, is what to correct first.
constexpr float kPieceReach = 5;
float lobeSpread(const BeamSegment& s) { return s.sigma > 0 ? std::tan(std::min(kPieceReach * s.sigma, 1.3f)) : 0; }

// The box of piece k of a segment's kPieces lengthwise pieces: fractions k/kPieces to
// (k+1)/kPieces of its corner rays' lengths, the last reaching past the ends by the gather's
// cap slack. The cross-sections are linear in u, so the six corner points bound it; glossy:
// grown by kPieceReach·σ of angle at its far end (spread = lobeSpread(s)).
Box3 pieceBox(const BeamSegment& s, int k, float spread) {
  constexpr int n = BeamStore::kPieces;
  const float u0 = float(k) / n, u1 = k + 1 == n ? 1 + kCapSlack : float(k + 1) / n;
  Box3 box;
  float far = 0;
  for (int i = 0; i < 3; ++i) {
    box.extend(s.o[i] + s.d[i] * (s.t[i] * u0));
    box.extend(s.o[i] + s.d[i] * (s.t[i] * u1));
    far = std::max(far, s.t[i] * u1);
  }
  if (s.sigma > 0) {
    const float pad = far * spread;
    box.lo -= Vec3{pad, pad, pad};
    box.hi += Vec3{pad, pad, pad};
  }
  return box;
}

// Appends the cells of leaf grid g that the piece boxes reach (each clipped to the leaf's box),
// in increasing order and once each: row by row, the union of the pieces' x ranges in that row
// (adjacent pieces overlap, so collecting every piece's cells and sorting them cost more).
void appendCells(const BeamStore::LeafGrid& g, const std::array<Box3, BeamStore::kPieces>& boxes,
                 std::vector<uint64_t>& out) {
  int lo[BeamStore::kPieces][3], hi[BeamStore::kPieces][3], m = 0;
  for (const Box3& box : boxes) {
    Box3 part = box;
    part.lo = vmax(part.lo, g.box.lo);
    part.hi = vmin(part.hi, g.box.hi);
    if (part.empty()) continue;
    for (int a = 0; a < 3; ++a) lo[m][a] = safeCell(g, a, part.lo[a]), hi[m][a] = safeCell(g, a, part.hi[a]);
    ++m;
  }
  if (m == 0) return;
  int first[3] = {lo[0][0], lo[0][1], lo[0][2]}, last[3] = {hi[0][0], hi[0][1], hi[0][2]};
  for (int p = 1; p < m; ++p)
    for (int a = 1; a < 3; ++a) first[a] = std::min(first[a], lo[p][a]), last[a] = std::max(last[a], hi[p][a]);
  for (int z = first[2]; z <= last[2]; ++z)
    for (int y = first[1]; y <= last[1]; ++y) {
      std::pair<int, int> runs[BeamStore::kPieces];
      int n = 0;
      for (int p = 0; p < m; ++p)
        if (lo[p][2] <= z && z <= hi[p][2] && lo[p][1] <= y && y <= hi[p][1]) runs[n++] = {lo[p][0], hi[p][0]};
      for (int r = 1; r < n; ++r)  // insertion sort: at most kPieces runs
        for (int q = r; q > 0 && runs[q] < runs[q - 1]; --q) std::swap(runs[q], runs[q - 1]);
      const uint64_t row = g.first + (uint64_t(z) * g.n[1] + y) * g.n[0];
      int next = 0;  // the first x not yet appended in this row
      for (int r = 0; r < n; ++r) {
        for (int x = std::max(runs[r].first, next); x <= runs[r].second; ++x) out.push_back(row + x);
        next = std::max(next, runs[r].second + 1);
      }
    }
}
}  // namespace

bool BeamStore::reaches(const BeamSegment& s, Vec3 x) {
  // The piece that x's distance along the first corner ray points at first (most gathers
  // that reach a segment are in it), then the others: the answer does not depend on the order.
  const float spread = lobeSpread(s);
  const float along = dot(x - s.o[0], s.d[0]) / s.t[0] * kPieces;
  const int guess = along > 0 ? (along < kPieces ? int(along) : kPieces - 1) : 0;  // NaN: 0
  if (pieceBox(s, guess, spread).contains(x)) return true;
  for (int k = 0; k < kPieces; ++k)
    if (k != guess && pieceBox(s, k, spread).contains(x)) return true;
  return false;
}

BeamStore::BeamStore(std::vector<BeamSegment> segments, const TopLevelBvh& top, GatedSpan<Box3> leafBoxes,
                     size_t budget, std::span<const uint8_t> receives, int maxDepth, BeamBudget* account)
    : segments_(std::move(segments)), maxDepth_(maxDepth) {
  const size_t leaves = top.leafCount();
  if (!segments_.empty() && minimumBytes(leaves) > budget)
    throw ResourceError("--beam-memory", "a budget of " + std::to_string(budget) + " bytes cannot hold one beam (" +
                                             std::to_string(minimumBytes(leaves)) + " bytes with the per-leaf grids)");
  // Every array below is taken from the account before it is made; when one does not fit, the
  // store keeps nothing (fits() false), as when its bytes exceed the budget.
  BeamCharge transient(account, 0, "");
  charge_ = BeamCharge(account, 0, "");
  try {
    build(top, leafBoxes, budget, receives, transient);
  } catch (const BeamBudgetExceeded&) {
    if (needed_ == 0) needed_ = budget + 1;  // what it would need is unknown: more than there is
    segments_ = {};
    grids_ = {};
    offsets_ = {};
    envelopes_ = {};
    entries_ = {};
    charge_.release();
  }
}

// The leaves a segment's box overlaps that receive gathers, in increasing order, once each.
void BeamStore::leavesOf(const BeamSegment& s, const TopLevelBvh& top, std::span<const uint8_t> receives,
                         std::vector<uint32_t>& out, TraversalScratch& scratch) {
  out.clear();
  top.overlapping(beamBounds(s), out, scratch);
  if (!receives.empty()) std::erase_if(out, [&](uint32_t l) { return l >= receives.size() || !receives[l]; });
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

// Three passes over the segments, each finding its leaves again (so no per-segment lists are
// held): how many segments reach each leaf (the grids' shapes); how many cells each segment
// reaches (the offsets, and the bytes: checked against the budget before the bins are made);
// each segment's cells (a flat list), then the entries in segment order.
void BeamStore::build(const TopLevelBvh& top, GatedSpan<Box3> leafBoxes, size_t budget,
                      std::span<const uint8_t> receives, BeamCharge& transient) {
  const size_t leaves = top.leafCount(), n = segments_.size();
  struct Scratch {
    TraversalScratch traversal;
    std::vector<uint32_t> leaves;
    std::vector<uint64_t> cells;
  };
  tbb::enumerable_thread_specific<Scratch> scratch;
  // Each leaf's grid, sized by how many segments reach it.
  transient.add(leaves * sizeof(uint64_t), "the beams' per-leaf counts");
  std::vector<uint64_t> perLeaf(leaves, 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const auto& r) {
    Scratch& sc = scratch.local();
    for (size_t i = r.begin(); i != r.end(); ++i) {
      leavesOf(segments_[i], top, receives, sc.leaves, sc.traversal);
      for (uint32_t l : sc.leaves) std::atomic_ref<uint64_t>(perLeaf[l]).fetch_add(1, std::memory_order_relaxed);
    }
  });
  charge_.add(leaves * sizeof(LeafGrid), "the beams' leaf grids");
  grids_.resize(leaves);
  uint64_t cells = 0;
  for (size_t l = 0; l < leaves; ++l) {
    LeafGrid& g = grids_[l];
    g.box = l < leafBoxes.size() ? leafBoxes[l] : Box3{};
    if (perLeaf[l] && !g.box.empty()) shapeGrid(g, perLeaf[l]);
    g.first = cells;
    cells += perLeaf[l] && !g.box.empty() ? uint64_t(g.n[0]) * g.n[1] * g.n[2] : 0;
  }
  transient.sub(leaves * sizeof(uint64_t));
  perLeaf = {};
  // The cells of leaf grids a segment reaches: the segment cut into kPieces along its length,
  // each piece's box (its six corner points, grown by the lobe) clipped to the leaf's box, so
  // a long tilted beam does not claim the whole box of its diagonal. Cells in increasing order.
  const auto cellsOf = [&](size_t i, Scratch& sc) {
    const BeamSegment& seg = segments_[i];
    sc.cells.clear();
    std::array<Box3, kPieces> boxes;
    const float spread = lobeSpread(seg);
    for (int k = 0; k < kPieces; ++k) boxes[k] = pieceBox(seg, k, spread);
    leavesOf(seg, top, receives, sc.leaves, sc.traversal);
    for (uint32_t l : sc.leaves) {
      const LeafGrid& g = grids_[l];
      if (g.first == (l + 1 < leaves ? grids_[l + 1].first : cells)) continue;
      appendCells(g, boxes, sc.cells);
    }
  };
  charge_.add((cells + 1) * sizeof(uint64_t), "the beams' bin offsets");
  offsets_.assign(cells + 1, 0);
  transient.add((n + 1) * sizeof(uint64_t), "the beams' cells per segment");
  std::vector<uint64_t> first(n + 1, 0);  // segment i's cells: [first[i], first[i + 1]) of the flat list
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const auto& r) {
    Scratch& sc = scratch.local();
    for (size_t i = r.begin(); i != r.end(); ++i) {
      cellsOf(i, sc);
      first[i + 1] = sc.cells.size();
      for (uint64_t c : sc.cells) std::atomic_ref<uint64_t>(offsets_[c + 1]).fetch_add(1, std::memory_order_relaxed);
    }
  });
  for (size_t i = 0; i < n; ++i) first[i + 1] += first[i];
  for (uint64_t c = 0; c < cells; ++c) offsets_[c + 1] += offsets_[c];
  const size_t total = offsets_[cells];
  needed_ = bytesFor(n, total, offsets_.size()) + grids_.size() * sizeof(LeafGrid);
  if (needed_ > budget) throw BeamBudgetExceeded(needed_, budget, "the beams' store");
  // The flat list of every segment's cells and a cursor per cell, then the bins.
  transient.add(total * sizeof(uint64_t) + cells * sizeof(uint64_t), "the beams' cells while they are binned");
  std::vector<uint64_t> list(total);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const auto& r) {
    Scratch& sc = scratch.local();
    for (size_t i = r.begin(); i != r.end(); ++i) {
      cellsOf(i, sc);
      std::copy(sc.cells.begin(), sc.cells.end(), list.begin() + int64_t(first[i]));
    }
  });
  charge_.add(total * sizeof(uint32_t) + n * sizeof(BeamEnvelope), "the beams' bins and envelopes");
  entries_.resize(total);
  std::vector<uint64_t> fill(offsets_.begin(), offsets_.end() - 1);
  for (size_t i = 0; i < n; ++i)
    for (uint64_t k = first[i]; k < first[i + 1]; ++k) entries_[fill[list[k]]++] = uint32_t(i);
  envelopes_.resize(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) envelopes_[i] = beamEnvelope(segments_[i]);
  });
}

std::pair<uint64_t, uint64_t> BeamStore::cellRange(uint32_t leaf, Vec3 x) const {
  if (leaf >= grids_.size()) return {0, 0};
  const LeafGrid& g = grids_[leaf];
  const uint64_t end = leaf + 1 < grids_.size() ? grids_[leaf + 1].first : offsets_.size() - 1;
  if (g.first == end) return {0, 0};
  const uint64_t c = g.first + (uint64_t(safeCell(g, 2, x.z)) * g.n[1] + safeCell(g, 1, x.y)) * g.n[0] +
                     safeCell(g, 0, x.x);
  return {offsets_[c], offsets_[c + 1]};
}

Rgb BeamStore::radiance(const DiffuseVertex& v, Rgb sum) const {
  // Segments whose paths are longer than maxDepth are left out before their gather is computed.
  const auto withinDepth = [&](const BeamSegment& segment) {
    return int64_t(v.bounce) + segment.scatterings + 1 <= maxDepth_;
  };
  gather(v.leaf, v.p, v.ng, [&](Vec3 psi, Rgb irradiance) {
    const Vec3 wi = -psi;
    const Vec3 wiL = v.frame->toLocal(wi);
    // Both directions on the sides of the true surface the shading frame claims.
    const float s = dot(v.ng, wi) * dot(v.ng, v.wo);
    if (wiL.z * v.woL.z > 0 ? !(s > 0) : !(s < 0)) return;
    sum += v.bsdf->eval(v.woL, wiL) * irradiance;
  }, withinDepth);
  return sum;
}

}  // namespace rayes
