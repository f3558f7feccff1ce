// Photons stored on diffuse surfaces and the searches photon mapping makes over them: a
// balanced kd-tree in place (each range's median photon is its node, split on the range's
// widest axis), built with oneTBB tasks over disjoint halves. Everything is a function of the
// photons in their given order: the median is chosen under the total order (coordinate,
// position in the input), and searches visit photons in a fixed order, so estimates are
// bit-identical for any thread count.
//
// Gather radii (pm's density estimate, docs/design.md "Caustic paths"): setGatherRadii(k, ...)
// gives every photon its own disk, reaching its k-th nearest other photon, and covering(x)
// visits the photons whose disk contains x. Summing power / (pi r_p²) over them is the
// sample-point ("variable kernel") estimate with a normalised uniform kernel: unbiased for a
// locally uniform density, and each photon's disk integrates to its power (flux is kept).
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
  size_t bytes() const {
    return photons_.capacity() * sizeof(Photon) + axis_.capacity() +
           (radius2_.capacity() + reach2_.capacity()) * sizeof(float);
  }
  const Photon& operator[](size_t i) const { return photons_[i]; }

  // The k nearest photons to x within squared radius maxR2, nearest first (ties by index), into
  // `out`; returns the squared distance of the farthest one kept (maxR2 if fewer than k).
  float nearest(Vec3 x, int k, float maxR2, std::vector<uint32_t>& out) const;
  // Calls visit(index) for every photon within squared radius r2 of x, in a fixed order.
  template <class Visit> void within(Vec3 x, float r2, Visit&& visit) const {
    if (!photons_.empty()) within(x, r2, 0, photons_.size(), visit);
  }

  // Gives photon i the squared radius r²_i = clamp(d_k(i)², minR2, maxR2), d_k(i) the distance
  // to its k-th nearest other photon (k >= 1); a photon with fewer than k others within maxR2
  // gets maxR2. minR2 > 0 keeps more than k coincident photons from a zero radius (their flux
  // would be lost). Parallel over photons; the radii do not depend on the thread count.
  void setGatherRadii(int k, float minR2, float maxR2);
  float gatherRadius2(size_t i) const { return radius2_[i]; }
  // Calls visit(index) for every photon whose gather disk holds x strictly inside
  // (|x - p|² < r²_p), in a fixed order. Requires setGatherRadii.
  template <class Visit> void covering(Vec3 x, Visit&& visit) const {
    if (!photons_.empty()) covering(x, 0, photons_.size(), visit);
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
  template <class Visit> void covering(Vec3 x, size_t lo, size_t hi, Visit& visit) const {
    while (lo < hi) {
      const size_t mid = lo + (hi - lo) / 2;
      const Photon& ph = photons_[mid];
      const Vec3 d = ph.p - x;
      if (dot(d, d) < radius2_[mid]) visit(uint32_t(mid));
      if (hi - lo == 1) return;
      const float delta = x[axis_[mid]] - ph.p[axis_[mid]];
      const bool left = delta <= 0;
      // The far side only if one of its disks can reach across the splitting plane.
      const size_t farLo = left ? mid + 1 : lo, farHi = left ? hi : mid;
      if (farLo < farHi && delta * delta < reach2_[farLo + (farHi - farLo) / 2]) covering(x, farLo, farHi, visit);
      if (left) hi = mid;
      else lo = mid + 1;
    }
  }
  void build(size_t lo, size_t hi, std::vector<uint32_t>& order);
  float buildReach(size_t lo, size_t hi);

  std::vector<Photon> photons_;
  std::vector<uint8_t> axis_;  // split axis of the node at each index
  std::vector<float> radius2_;  // squared gather radius of each photon (setGatherRadii)
  std::vector<float> reach2_;   // the largest radius2_ in the subtree of the node at each index
};

}  // namespace rayes
