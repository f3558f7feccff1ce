#include "shading/volume_tracking.h"
#include <algorithm>
#include <array>
#include <map>
#include <cmath>
#include <numbers>
#include <optional>
#include "shading/blackbody.h"
#include "shading/bsdf.h"
#include "shading/grid_reader.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kRouletteWeight = 1.0f / 16;

// Calls visit(brick, ta, tb) for each brick cell the ray crosses within (t0, t1), in order along
// the ray, until it returns true. Cells without a brick are skipped without a call.
template <class Visit>
void walkCells(const Medium& m, const IndexRay& r, float t0, float t1, TrackingCounts& counts, Visit&& visit) {
  const BrickCoord lo = m.cellLo(), n = m.cellCount();
  if (n.x == 0) return;
  // Cell coordinates q = (index + ½) / 8: cell c is [c, c + 1) in q.
  const float oq[3] = {(r.org.x + 0.5f) / 8, (r.org.y + 0.5f) / 8, (r.org.z + 0.5f) / 8};
  const float dq[3] = {r.dir.x / 8, r.dir.y / 8, r.dir.z / 8};
  const int32_t l[3] = {lo.x, lo.y, lo.z}, c[3] = {n.x, n.y, n.z};
  for (int a = 0; a < 3; ++a) {
    const float b0 = float(l[a]), b1 = float(l[a] + c[a]);
    if (dq[a] == 0) {
      if (!(oq[a] >= b0 && oq[a] < b1)) return;
      continue;
    }
    float ta = (b0 - oq[a]) / dq[a], tb = (b1 - oq[a]) / dq[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (!(t0 < t1)) return;
  int32_t cell[3], step[3];
  float tNext[3], tDelta[3];
  for (int a = 0; a < 3; ++a) {
    // Rounding may put the entry point a hair outside the grid: clamp into it.
    const float q = oq[a] + dq[a] * t0;
    cell[a] = std::clamp(int32_t(std::floor(q)), l[a], l[a] + c[a] - 1);
    if (dq[a] > 0) {
      step[a] = 1, tDelta[a] = 1 / dq[a], tNext[a] = (float(cell[a] + 1) - oq[a]) / dq[a];
    } else if (dq[a] < 0) {
      step[a] = -1, tDelta[a] = -1 / dq[a], tNext[a] = (float(cell[a]) - oq[a]) / dq[a];
    } else {
      step[a] = 0, tDelta[a] = kInf, tNext[a] = kInf;
    }
  }
  float t = t0;
  while (t < t1) {
    const int a = tNext[0] < tNext[1] ? (tNext[0] < tNext[2] ? 0 : 2) : (tNext[1] < tNext[2] ? 1 : 2);
    const float tb = std::min(tNext[a], t1);
    ++counts.cells;
    const int32_t brick = m.brickAt(cell[0], cell[1], cell[2]);
    if (brick >= 0 && tb > t && visit(brick, t, tb)) return;
    t = std::max(t, tb);
    cell[a] += step[a];
    tNext[a] += tDelta[a];
    if (step[a] == 0 || cell[a] < l[a] || cell[a] >= l[a] + c[a]) return;
  }
}

// The tentative collisions of the majorant process in brick `brick`'s cell over (ta, tb): the
// brick's majorant sets the rate, and the process is memoryless, so every cell starts afresh at
// its entry. visit(t, majorant) at each; a true return ends it (and returns true). The one loop
// that delta tracking, ratio tracking and the emission estimate share.
template <class Visit>
bool tentativeCollisionsIn(const Medium& m, int32_t brick, const IndexRay& r, float sigmaT, float ta, float tb,
                           TrackingRng& rng, TrackingCounts& counts, Visit&& visit) {
  const float majorant = m.majorant(brick);
  const float rate = sigmaT * majorant * r.length;  // tentative collisions per unit t
  if (!(rate > 0)) return false;
  float t = ta;
  for (;;) {
    t -= std::log1p(-rng()) / rate;  // rng() < 1: the logarithm is finite
    if (!(t < tb)) return false;     // memoryless: the next cell starts afresh at tb
    ++counts.lookups;
    if (visit(t, majorant)) return true;
  }
}

// The tentative collisions along r within (0, tEnd), cell after cell, one stream for the whole
// walk (the emission estimate: a sum, so it needs no per-brick streams).
template <class Visit>
void forEachTentativeCollision(const Medium& m, const IndexRay& r, float sigmaT, float tEnd, TrackingRng& rng,
                               TrackingCounts& counts, Visit&& visit) {
  walkCells(m, r, 0.0f, tEnd, counts, [&](int32_t brick, float ta, float tb) {
    return tentativeCollisionsIn(m, brick, r, sigmaT, ta, tb, rng, counts,
                                 [&](float t, float majorant) { return visit(brick, t, majorant); });
  });
}

// The number of the first brick of each medium of the list (in list order, as the top level's
// brick leaves are numbered), then the total.
template <class Each>
void forEachMediumWithFirstBrick(MediumList media, Each&& each) {
  uint32_t first = 0;
  for (size_t i = 0; i < media.size(); ++i) {
    if (each(i, *media[i], first)) return;
    first += uint32_t(media[i]->bricks());
  }
}

}  // namespace

IndexRay toIndex(const Medium& m, Vec3 org, Vec3 dir) {
  return {m.worldToIndex().point(org), applyLinear(m.worldToIndex(), dir), length(dir)};
}

TrackingRng brickStream(const RngKey& key, uint32_t dimensionBase, uint32_t globalBrick) {
  RngKey k = key;
  k.seed = mix64(key.seed ^ (uint64_t(globalBrick) + 1) * 0x9e3779b97f4a7c15ull);
  return {k, dimensionBase};
}

bool brickSegment(const Medium& m, int32_t brick, const IndexRay& r, float tEnd, float& t0, float& t1) {
  const BrickCoord c = m.densityGrid().coord(brick);
  const int32_t cell[3] = {c.x, c.y, c.z};
  const float o[3] = {r.org.x, r.org.y, r.org.z}, d[3] = {r.dir.x, r.dir.y, r.dir.z};
  t0 = 0;
  t1 = tEnd;
  for (int a = 0; a < 3; ++a) {
    // Cell coordinates q = (index + ½) / 8, as walkCells: the cell is [c, c + 1) in q.
    const float oq = (o[a] + 0.5f) / 8, dq = d[a] / 8;
    const float b0 = float(cell[a]), b1 = float(cell[a] + 1);
    if (dq == 0) {
      if (!(oq >= b0 && oq < b1)) return false;
      continue;
    }
    float ta = (b0 - oq) / dq, tb = (b1 - oq) / dq;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 < t1;
}

float brickCollision(const Medium& m, int32_t brick, const IndexRay& r, float tEnd, TrackingRng rng,
                     TrackingCounts& counts, GridReader& reader) {
  const float sigmaT = m.coefficients().sigmaT();
  float t0, t1;
  if (!(sigmaT > 0) || !brickSegment(m, brick, r, tEnd, t0, t1)) return kInf;
  float found = kInf;
  tentativeCollisionsIn(m, brick, r, sigmaT, t0, t1, rng, counts, [&](float t, float majorant) {
    reader.enter(brick);  // voxels are read only where a tentative collision lands
    const float rho = reader.sample(r.org + r.dir * t);
    if (rng() * majorant < rho) {
      found = t;
      return true;
    }
    return false;
  });
  return found;
}

float brickTransmittance(const Medium& m, int32_t brick, const IndexRay& r, float tEnd, bool delta, TrackingRng rng,
                         TrackingCounts& counts, GridReader& reader) {
  if (delta) return brickCollision(m, brick, r, tEnd, rng, counts, reader) < kInf ? 0.0f : 1.0f;
  const float sigmaT = m.coefficients().sigmaT();
  float t0, t1;
  if (!(sigmaT > 0) || !brickSegment(m, brick, r, tEnd, t0, t1)) return 1;
  float T = 1;
  tentativeCollisionsIn(m, brick, r, sigmaT, t0, t1, rng, counts, [&](float t, float majorant) {
    reader.enter(brick);
    T *= std::max(0.0f, 1 - reader.sample(r.org + r.dir * t) / majorant);
    if (T < kRouletteWeight) {
      if (T == 0 || rng() * kRouletteWeight >= T) {
        T = 0;
        return true;
      }
      T = kRouletteWeight;
    }
    return false;
  });
  return T;
}

BrickNumbering::BrickNumbering(MediumList media, int32_t leafSide) {
  forEachMediumWithFirstBrick(media, [&](size_t, const Medium&, uint32_t first) {
    first_.push_back(first);
    return false;
  });
  total_ = media.empty() ? 0 : first_.back() + uint32_t(media.back()->bricks());
  // Each medium's bricks grouped by floor(cell / leafSide), leaves in order of their first brick.
  leafBricks_.reserve(total_);
  leafStart_.push_back(0);
  const auto groupOf = [leafSide](int32_t c) { return c >= 0 ? c / leafSide : -((-c + leafSide - 1) / leafSide); };
  for (size_t i = 0; i < media.size(); ++i) {
    const Medium& m = *media[i];
    std::map<std::array<int32_t, 3>, uint32_t> leafOfGroup;
    std::vector<std::vector<uint32_t>> members;
    for (int32_t b = 0; b < int32_t(m.bricks()); ++b) {
      const BrickCoord c = m.densityGrid().coord(b);
      const auto [it, added] = leafOfGroup.try_emplace({groupOf(c.x), groupOf(c.y), groupOf(c.z)}, uint32_t(members.size()));
      if (added) members.emplace_back();
      members[it->second].push_back(first_[i] + uint32_t(b));
    }
    for (const std::vector<uint32_t>& leaf : members) {
      leafBricks_.insert(leafBricks_.end(), leaf.begin(), leaf.end());
      leafStart_.push_back(uint32_t(leafBricks_.size()));
      leafMedium_.push_back(uint32_t(i));
    }
  }
}

BrickNumbering::Brick BrickNumbering::brickOf(uint32_t global) const {
  const size_t i = size_t(std::upper_bound(first_.begin(), first_.end(), global) - first_.begin()) - 1;
  return {uint32_t(i), int32_t(global - first_[i])};
}

Collision sampleCollision(MediumList media, Vec3 org, Vec3 dir, float tEnd, TrackingRng& rng, TrackingCounts& counts,
                          BrickCache* cache) {
  Collision c;
  float limit = tEnd;
  forEachMediumWithFirstBrick(media, [&](size_t i, const Medium& m, uint32_t first) {
    if (!(m.coefficients().sigmaT() > 0)) return false;
    const IndexRay r = toIndex(m, org, dir);
    GridReader reader(m.densityGrid(), cache);
    // Each brick's first collision from its own stream: the minimum over bricks is the same
    // whichever order they are visited in (the sorted engine's brick leaves).
    walkCells(m, r, 0.0f, tEnd, counts, [&](int32_t brick, float ta, float) {
      if (!(ta < limit)) return true;
      const float t = brickCollision(m, brick, r, limit, brickStream(rng.key, rng.dimension, first + uint32_t(brick)),
                                     counts, reader);
      if (t < limit) {
        limit = t;
        c = {t, int32_t(i)};
      }
      return false;
    });
    return false;
  });
  return c;
}

float walkTransmittance(MediumList media, Vec3 org, Vec3 dir, float tEnd, bool delta, TrackingRng& rng,
                        TrackingCounts& counts, BrickCache* cache) {
  uint64_t sum = 0;
  forEachMediumWithFirstBrick(media, [&](size_t, const Medium& m, uint32_t first) {
    if (!(m.coefficients().sigmaT() > 0)) return false;
    const IndexRay r = toIndex(m, org, dir);
    GridReader reader(m.densityGrid(), cache);
    walkCells(m, r, 0.0f, tEnd, counts, [&](int32_t brick, float, float) {
      TransmittanceProduct::addLocal(
          sum, TransmittanceProduct::term(brickTransmittance(
                   m, brick, r, tEnd, delta, brickStream(rng.key, rng.dimension, first + uint32_t(brick)), counts, reader)));
      return (sum & TransmittanceProduct::kZero) != 0;
    });
    return (sum & TransmittanceProduct::kZero) != 0;
  });
  return TransmittanceProduct::valueOf(sum);
}

float ratioTransmittance(MediumList media, Vec3 org, Vec3 dir, float tEnd, TrackingRng& rng, TrackingCounts& counts,
                         BrickCache* cache) {
  return walkTransmittance(media, org, dir, tEnd, false, rng, counts, cache);
}

Rgb emissionAlong(MediumList media, Vec3 org, Vec3 dir, float tEnd, TrackingRng& rng, TrackingCounts& counts,
                  BrickCache* cache) {
  Rgb L{};
  for (const auto& mp : media) {
    const Medium& m = *mp;
    const float sigmaT = m.coefficients().sigmaT(), sigmaA = m.coefficients().sigmaA;
    if (!m.emits() || !(sigmaA > 0)) continue;
    const MediumEmission& e = m.emission();
    const IndexRay r = toIndex(m, org, dir);
    GridReader density(m.densityGrid(), cache);
    std::optional<GridReader> intensity, temperature;
    if (e.intensity) intensity.emplace(*e.intensity, cache);
    if (e.temperature) temperature.emplace(*e.temperature, cache);
    forEachTentativeCollision(m, r, sigmaT, tEnd, rng, counts, [&](int32_t brick, float t, float majorant) {
      density.enter(brick);
      const Vec3 p = r.org + r.dir * t;
      const float rho = density.sample(p);
      if (!(rho > 0)) return false;
      Rgb Le{};
      if (intensity) Le += e.color * intensity->at(p);
      if (temperature) Le += blackbodyRgb(e.temperatureScale * temperature->at(p)) * e.blackbodyScale;
      L += Le * (sigmaA * rho / (sigmaT * majorant));
      return false;
    });
  }
  return L;
}

float henyeyGreenstein(float cosInOut, float g) {
  const float d = 1 + g * g - 2 * g * cosInOut;  // > 0 for |g| < 1
  return (1 - g * g) / (4 * std::numbers::pi_v<float> * d * std::sqrt(d));
}

Vec3 sampleHenyeyGreenstein(Vec3 in, float g, float u1, float u2) {
  float cosTheta;
  if (std::fabs(g) < 1e-3f) {
    cosTheta = 1 - 2 * u1;  // isotropic: the closed form below divides by g
  } else {
    const float s = (1 - g * g) / (1 - g + 2 * g * u1);
    cosTheta = (1 + g * g - s * s) / (2 * g);
  }
  cosTheta = std::clamp(cosTheta, -1.0f, 1.0f);
  const float sinTheta = std::sqrt(std::max(0.0f, 1 - cosTheta * cosTheta));
  const float phi = 2 * std::numbers::pi_v<float> * u2;
  const ShadingFrame frame(in);
  return normalize(frame.toWorld({sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta}));
}

}  // namespace rayes
