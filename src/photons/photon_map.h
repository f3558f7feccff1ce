// Photons stored on diffuse surfaces and the searches photon mapping makes over them: a
// balanced kd-tree in place (each range's median photon is its node, split on the range's
// widest axis), built with oneTBB tasks over disjoint halves. Everything is a function of the
// photons in their given order: the median is chosen under the total order (coordinate,
// position in the input), and searches visit photons in a fixed order, so estimates are
// bit-identical for any thread count.
#pragma once
#include <cstdint>
#include <vector>
#include "core/vec.h"

namespace rayes {

struct Photon {
  Vec3 p;      // where it landed
  Vec3 wi;     // unit, toward where it came from
  Vec3 n;      // unit geometric normal of the surface, on wi's side
  Rgb power;   // flux, W (already divided by the number of photons of its map)
  uint32_t vertex = 1;  // the light path's vertex it landed at (1: straight from the light)
};

class PhotonMap {
 public:
  PhotonMap() = default;
  explicit PhotonMap(std::vector<Photon> photons);

  size_t size() const { return photons_.size(); }
  size_t bytes() const { return photons_.capacity() * sizeof(Photon) + axis_.capacity(); }
  const Photon& operator[](size_t i) const { return photons_[i]; }

  // The k nearest photons to x within squared radius maxR2, nearest first (ties by index), into
  // `out`; returns the squared distance of the farthest one kept (maxR2 if fewer than k).
  float nearest(Vec3 x, int k, float maxR2, std::vector<uint32_t>& out) const;
  // Calls visit(index) for every photon within squared radius r2 of x, in a fixed order.
  template <class Visit> void within(Vec3 x, float r2, Visit&& visit) const {
    if (!photons_.empty()) within(x, r2, 0, photons_.size(), visit);
  }

 private:
  template <class Visit> void within(Vec3 x, float r2, size_t lo, size_t hi, Visit& visit) const {
    while (lo < hi) {
      const size_t mid = lo + (hi - lo) / 2;
      const Photon& ph = photons_[mid];
      const Vec3 d = ph.p - x;
      if (dot(d, d) <= r2) visit(uint32_t(mid));
      if (hi - lo == 1) return;
      const float delta = x[axis_[mid]] - ph.p[axis_[mid]];
      // Near side first, far side only if the splitting plane is within reach.
      const bool left = delta <= 0;
      if (delta * delta <= r2) {
        if (left) within(x, r2, mid + 1, hi, visit), hi = mid;
        else within(x, r2, lo, mid, visit), lo = mid + 1;
      } else if (left) {
        hi = mid;
      } else {
        lo = mid + 1;
      }
    }
  }
  void build(size_t lo, size_t hi, std::vector<uint32_t>& order);

  std::vector<Photon> photons_;
  std::vector<uint8_t> axis_;  // split axis of the node at each index
};

}  // namespace rayes
