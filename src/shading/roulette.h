// What every path (camera or light) does to its throughput after a bounce, in one place so the
// integrators cannot drift apart: Russian roulette once the path is deep enough, then the
// finite and black checks. Pure; thread-safe (the counters are atomic).
#pragma once
#include <algorithm>
#include <cstdint>
#include "core/rng.h"
#include "shading/integrator.h"

namespace rayes {

// False when the path ends here: killed by roulette (counted), a non-finite throughput
// (counted) or a black one. When `roulette`, the path survives with probability
// q = min(1, max(T) · survivalScale), drawing dimension `dim` of `key`, and T is divided by q;
// survivalScale undoes factors the path will regain (η² inside glass), 1 otherwise.
inline bool throughputSurvives(Rgb& T, bool roulette, float survivalScale, const RngKey& key, uint32_t dim,
                               ShadeStats& stats) {
  if (roulette) {
    const float q = std::min(1.0f, maxComponent(T) * survivalScale);
    if (!(sample1D(key, dim) < q)) {
      stats.rouletteKills.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    T = T * (1.0f / q);
  }
  if (!isFinite(T)) {
    stats.nonFinite.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  return !isBlack(T);
}

}  // namespace rayes
