#include "photons/photon_map.h"
#include <algorithm>
#include <limits>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include "core/box.h"

namespace rayes {

PhotonMap::PhotonMap(std::vector<Photon> photons) : axis_(photons.size(), 0) {
  std::vector<uint32_t> order(photons.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = uint32_t(i);
  photons_ = std::move(photons);
  build(0, order.size(), order);
  std::vector<Photon> sorted(order.size());
  for (size_t i = 0; i < order.size(); ++i) sorted[i] = photons_[order[i]];
  photons_ = std::move(sorted);
}

// order[lo, hi) holds input positions; afterwards order[mid] is the node of the range and its
// halves are the subtrees. Halves are disjoint, so they are built in parallel.
void PhotonMap::build(size_t lo, size_t hi, std::vector<uint32_t>& order) {
  if (hi - lo <= 1) return;
  Box3 box;
  for (size_t i = lo; i < hi; ++i) box.extend(photons_[order[i]].p);
  const Vec3 e = box.hi - box.lo;
  const int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
  const size_t mid = lo + (hi - lo) / 2;
  std::nth_element(order.begin() + lo, order.begin() + mid, order.begin() + hi, [&](uint32_t a, uint32_t b) {
    const float pa = photons_[a].p[axis], pb = photons_[b].p[axis];
    return pa != pb ? pa < pb : a < b;
  });
  axis_[mid] = uint8_t(axis);
  if (hi - lo > 8192)
    tbb::parallel_invoke([&] { build(lo, mid, order); }, [&] { build(mid + 1, hi, order); });
  else
    build(lo, mid, order), build(mid + 1, hi, order);
}

float PhotonMap::nearest(Vec3 x, int k, float maxR2, std::vector<uint32_t>& out) const {
  // A max-heap of (squared distance, index) of the best k so far; its top bounds the search.
  struct Entry {
    float d2;
    uint32_t i;
    bool operator<(const Entry& o) const { return d2 != o.d2 ? d2 < o.d2 : i < o.i; }
  };
  std::vector<Entry> heap;
  heap.reserve(size_t(k) + 1);
  float bound = maxR2;
  // The radius only shrinks, so visiting with the current bound finds the same set as an
  // exact k-nearest search: recurse by hand to use the shrinking bound.
  struct Frame { size_t lo, hi; };
  Frame stack[64];
  int top = 0;
  if (!photons_.empty()) stack[top++] = {0, photons_.size()};
  while (top > 0) {
    Frame f = stack[--top];
    while (f.lo < f.hi) {
      const size_t mid = f.lo + (f.hi - f.lo) / 2;
      const Photon& ph = photons_[mid];
      const Vec3 d = ph.p - x;
      const float d2 = dot(d, d);
      const Entry entry{d2, uint32_t(mid)};
      if (d2 <= bound && (int(heap.size()) < k || entry < heap.front())) {
        heap.push_back(entry);
        std::push_heap(heap.begin(), heap.end());
        if (int(heap.size()) > k) {
          std::pop_heap(heap.begin(), heap.end());
          heap.pop_back();
        }
        if (int(heap.size()) == k) bound = heap.front().d2;
      }
      if (f.hi - f.lo == 1) break;
      const float delta = x[axis_[mid]] - ph.p[axis_[mid]];
      const bool left = delta <= 0;
      // The far side waits on the stack; it is tested against the bound when popped.
      if (delta * delta <= bound && top < 64) stack[top++] = left ? Frame{mid + 1, f.hi} : Frame{f.lo, mid};
      if (left) f.hi = mid;
      else f.lo = mid + 1;
    }
  }
  std::sort(heap.begin(), heap.end());
  out.clear();
  for (const Entry& e : heap) out.push_back(e.i);
  return int(heap.size()) == k ? bound : maxR2;
}

void PhotonMap::setGatherRadii(int k, float minR2, float maxR2) {
  radius2_.assign(photons_.size(), maxR2);
  reach2_.assign(photons_.size(), maxR2);
  if (photons_.empty()) return;
  // The photon itself is its own nearest (distance 0): the k-th other is the (k + 1)-th found.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, photons_.size(), 256), [&](const auto& r) {
    std::vector<uint32_t> near;
    for (size_t i = r.begin(); i != r.end(); ++i)
      radius2_[i] = std::clamp(nearest(photons_[i].p, k + 1, maxR2, near), minR2, maxR2);
  });
  buildReach(0, photons_.size());
}

// reach2_[mid] of the node of [lo, hi): the largest squared radius in the range.
float PhotonMap::buildReach(size_t lo, size_t hi) {
  if (lo >= hi) return 0;
  const size_t mid = lo + (hi - lo) / 2;
  return reach2_[mid] = std::max({radius2_[mid], buildReach(lo, mid), buildReach(mid + 1, hi)});
}

}  // namespace rayes
