#include "lbt/beam_tracer.h"
#include <algorithm>
#include <cmath>
#include <map>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include "shading/fresnel.h"
#include "shading/ray_spawning.h"
#include "shading/surface_hit.h"

namespace rayes {
namespace {

enum class Event : uint8_t { Stop, Reflect, Refract };
constexpr uint32_t kNone = 0xffffffffu;  // no material: the corner ray left the scene
enum class Outcome : uint8_t { Continue, End, Mixed, Silhouette, Tir, Divergent };

// A corner ray's state between generations. reflectAt: bit g set makes the corner reflect at a
// dielectric in generation g (the Fresnel-reflected branch of a beam) instead of refracting.
struct Corner {
  Vec3 org, dir;
  float width = 0, spread = 0;
  uint32_t fromLeaf = kNoLeaf;
  uint8_t fromLevel = 0;
  bool fromAfar = false;  // a distant light's first corner ray: its way back is traced too (BeamSeeds)
  uint32_t reflectAt = 0;
  SeedAim aim;  // a first corner ray's target (lbt/beam_seeds.h); none after a scattering
};

// What a corner ray found and what it becomes.
struct Scatter {
  float t = 0;          // hit distance (dir is unit), or the far length
  Event event = Event::Stop;
  uint32_t material = kNone;
  bool front = false;   // arrived on the geometric normal's side
  bool onAim = false;   // landed on its aim (first corner rays)
  bool dielectric = false;
  Corner next;
  Rgb rho;
  float sigma = 0;
};

Scatter scatterAt(const ShadingScene& scene, const Corner& c, const RayHit& h, float far, int generation) {
  Scatter s;
  s.t = h.valid() ? h.t : far;
  if (!h.valid()) return s;
  const Vec3 p = c.org + c.dir * h.t;
  const Vec3 ng = h.ng(), ns = h.ns();
  s.material = scene.materialOf(h.leaf);
  s.front = dot(ng, c.dir) < 0;
  s.onAim = c.aim.hits(h.leaf, h.u, h.v);
  const Material& m = scene.materials[s.material];
  if (!isCausticScatterer(m) || !isFinite(p)) return s;
  const Vec3 w = -c.dir;  // toward where the light came from
  Vec3 next;
  if (m.type == MaterialType::Dielectric) {
    s.dielectric = true;
    float etaRel;
    const float cosI = dot(w, ns);
    const float f = fresnelDielectric(cosI, m.eta.x);
    const bool reflectBranch = generation < 32 && ((c.reflectAt >> generation) & 1u);
    if (!reflectBranch && refract(w, ns, m.eta.x, next, etaRel)) {
      s.event = Event::Refract;
      s.rho = Rgb{1, 1, 1} * (1 - f);
    } else {
      // The reflected branch (weight F), or total internal reflection (F = 1).
      s.event = Event::Reflect;
      next = reflect(w, cosI >= 0 ? ns : -ns);
      s.rho = Rgb{1, 1, 1} * f;
    }
  } else {
    const Vec3 n = dot(ns, w) >= 0 ? ns : -ns;
    next = reflect(w, n);
    s.event = Event::Reflect;
    if (m.type == MaterialType::Conductor) {
      s.rho = fresnelConductor(dot(w, n), m.eta, m.k);
    } else {
      s.rho = m.specular.at(textureQueryAt(scene, h));
      s.sigma = GaussianLobe{s.rho, m.sigma}.smooth() ? 0.0f : m.sigma;
    }
  }
  next = normalize(next);
  // The new direction must leave the true surface on the side the event claims: a shading
  // normal past a silhouette would send it through the surface.
  const float side = dot(ng, next) * dot(ng, w);
  if (!isFinite(next) || next == Vec3{} || (s.event == Event::Reflect ? !(side > 0) : !(side < 0))) {
    s.event = Event::Stop;
    return s;
  }
  const float offset = originOffset(scene.sideOf(h.leaf), scene.dicingErrorOf(h.leaf), h.level, p, c.org);
  const SurfaceHit at{p, ng, offset};
  s.next = {at.originToward(next), next, c.width + h.t * c.spread, c.spread, h.leaf, uint8_t(h.level), false, c.reflectAt, SeedAim{}};
  return s;
}

bool coaxial(const Vec3 (&d)[3]) {
  const Vec3 c = normalize(d[0] + d[1] + d[2]);
  for (const Vec3& di : d)
    if (!(dot(di, c) >= kCoaxialCos)) return false;
  return true;
}

// The beams of one pass: first corner rays with their branch bits, triangles over them, and
// per triangle its root (the seed triangle it descends from), the generation up to which an
// ancestor already emitted its segments, and how often it was split.
struct Pass {
  std::vector<Corner> corners;
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<Rgb> flux;
  std::vector<uint32_t> root;
  std::vector<int> emitted;   // segments of generations ≤ this come from an ancestor
  std::vector<int> branched;  // reflected branches of generations ≤ this were spawned by an ancestor
  std::vector<uint8_t> level;
  BeamCharge charge;  // its arrays' bytes (and, while it is built, the ids of its new corners)

  static constexpr size_t kCornerBytes = sizeof(Corner);
  static constexpr size_t kTriangleBytes =
      sizeof(std::array<uint32_t, 3>) + sizeof(Rgb) + sizeof(uint32_t) + 2 * sizeof(int) + sizeof(uint8_t);
  void reserve(size_t nv, size_t nt) {
    corners.reserve(nv), triangles.reserve(nt), flux.reserve(nt), root.reserve(nt), emitted.reserve(nt);
    branched.reserve(nt), level.reserve(nt);
  }
};

// A beam to trace again in the next pass: split into four (its corner rays did not stay
// together) or its Fresnel-reflected branch at a dielectric, both from generation `at` on.
struct Derived {
  uint32_t triangle;
  int at;
  bool branch;             // else a split
  bool branchedToo = false;  // a split whose parent also spawned its reflected branch at `at`
};

// The next pass: the derived beams, in the order of their parents. Split children subdivide
// the parent's first corner rays at edge midpoints (shared by the siblings and by neighbours
// split along the same edge), with flux in proportion to their solid angle (point-like origins)
// or area (a quarter, parallel rays); a branch keeps the corners, with generation `at`'s bit set.
// The bytes of one entry of derive()'s map of new corner ids: a red-black tree node (three
// pointers and a colour) around its key and value, with the allocator's header.
constexpr size_t kIdEntryBytes = 4 * sizeof(void*) + 4 * sizeof(uint32_t) + 2 * sizeof(void*);

Pass derive(const Pass& p, const std::vector<Derived>& derived, BeamBudget* budget) {
  Pass out;
  // Taken before anything is built: the most corners and triangles the derived beams can have
  // (a split: its 3 corners and 3 midpoints, 4 triangles; a branch: 3 corners, 1 triangle).
  size_t nv = 0, nt = 0;
  for (const Derived& d : derived) nv += d.branch ? 3 : 6, nt += d.branch ? 1 : 4;
  out.charge = BeamCharge(budget, nv * Pass::kCornerBytes + nt * Pass::kTriangleBytes, "split children of beams");
  BeamCharge idBytes(budget, nv * kIdEntryBytes, "the corner ids of split children");
  out.reserve(nv, nt);
  std::map<std::tuple<uint32_t, uint32_t, uint32_t>, uint32_t> ids;  // (corner, corner or self, bits) -> new id
  auto copy = [&](uint32_t a, uint32_t bits) {
    auto [it, fresh] = ids.try_emplace({a, a, bits}, uint32_t(out.corners.size()));
    if (fresh) {
      Corner c = p.corners[a];
      c.reflectAt = bits;
      out.corners.push_back(c);
    }
    return it->second;
  };
  auto mid = [&](uint32_t a, uint32_t b, uint32_t bits) {
    if (a > b) std::swap(a, b);
    auto [it, fresh] = ids.try_emplace({a, b, bits}, uint32_t(out.corners.size()));
    if (fresh) {
      const Corner &ca = p.corners[a], &cb = p.corners[b];
      Corner c = ca;
      c.org = (ca.org + cb.org) * 0.5f;
      c.dir = normalize(ca.dir + cb.dir);
      c.width = std::min(ca.width, cb.width);
      c.spread = std::min(ca.spread, cb.spread);
      c.reflectAt = bits;
      // Halfway between the aims in (u, v); the ray between the two directions lands there up
      // to the surface's curvature over the cell, far inside the tolerance.
      c.aim = {ca.aim.leaf == cb.aim.leaf ? ca.aim.leaf : kNoLeaf, (ca.aim.u + cb.aim.u) / 2, (ca.aim.v + cb.aim.v) / 2,
               std::min(ca.aim.tolU, cb.aim.tolU), std::min(ca.aim.tolV, cb.aim.tolV)};
      out.corners.push_back(c);
    }
    return it->second;
  };
  auto add = [&](std::array<uint32_t, 3> t, Rgb flux, uint32_t root, int emitted, int branched, uint8_t level) {
    out.triangles.push_back(t);
    out.flux.push_back(flux);
    out.root.push_back(root);
    out.emitted.push_back(emitted);
    out.branched.push_back(branched);
    out.level.push_back(level);
  };
  for (const Derived& d : derived) {
    const auto& v = p.triangles[d.triangle];
    const uint32_t bits = p.corners[v[0]].reflectAt;
    const int emitted = std::max(p.emitted[d.triangle], d.at);
    if (d.branch) {
      const uint32_t b = bits | (1u << d.at);
      add({copy(v[0], b), copy(v[1], b), copy(v[2], b)}, p.flux[d.triangle], p.root[d.triangle], emitted, d.at,
          p.level[d.triangle]);
      continue;
    }
    const uint32_t a = copy(v[0], bits), b = copy(v[1], bits), c = copy(v[2], bits);
    const uint32_t ab = mid(v[0], v[1], bits), bc = mid(v[1], v[2], bits), ca = mid(v[2], v[0], bits);
    const bool pointLike = p.corners[v[0]].org == p.corners[v[1]].org && p.corners[v[1]].org == p.corners[v[2]].org;
    const double whole = pointLike ? sphericalTriangleArea(p.corners[v[0]].dir, p.corners[v[1]].dir, p.corners[v[2]].dir) : 0;
    for (const std::array<uint32_t, 3> t : {std::array<uint32_t, 3>{a, ab, ca}, std::array<uint32_t, 3>{ab, b, bc},
                                            std::array<uint32_t, 3>{ca, bc, c}, std::array<uint32_t, 3>{ab, bc, ca}}) {
      double share = 0.25;
      if (pointLike && whole > 0)
        share = sphericalTriangleArea(out.corners[t[0]].dir, out.corners[t[1]].dir, out.corners[t[2]].dir) / whole;
      add(t, p.flux[d.triangle] * float(share), p.root[d.triangle], emitted,
          std::max(p.branched[d.triangle], d.branchedToo ? d.at : d.at - 1), uint8_t(p.level[d.triangle] + 1));
    }
  }
  return out;
}

struct Tagged {
  uint32_t root;
  BeamSegment segment;
};

// The segments of one generation, tagged with their roots, and the budget's bytes for them.
struct TaggedRun {
  std::vector<Tagged> segments;
  BeamCharge charge;
};

// Bytes tracePass holds per corner ray and per triangle of its pass (besides the pass itself).
constexpr size_t kPassCornerBytes = sizeof(Corner) + sizeof(uint8_t) + sizeof(Scatter) + sizeof(uint32_t);
constexpr size_t kPassTriangleBytes = 2 * sizeof(uint8_t) + sizeof(Rgb) + sizeof(float) + sizeof(BeamSegment) +
                                      2 * sizeof(uint8_t) + sizeof(Outcome) + 2 * sizeof(Derived);

// Traces one pass generation by generation; appends its segments (tagged with their root) and
// the beams to trace again in the next pass.
// Its arrays (and the rays of one trace() call) are taken from the budget first.
void tracePass(const ShadingScene& scene, const Pass& pass, const BeamTraceOptions& o, const TraceRays& trace,
               BeamBudget* budget, BeamTraceStats& stats, std::vector<TaggedRun>& segments,
               std::vector<Derived>& derived) {
  const size_t nv = pass.corners.size(), nt = pass.triangles.size();
  const size_t rayCount = std::min(o.raysPerTrace, nv);
  const BeamCharge working(budget, nv * kPassCornerBytes + nt * kPassTriangleBytes +
                                       rayCount * RayBatch::bytesPerRay(true),
                           "the beam tracer's generation of corner rays");
  derived.reserve(2 * nt);  // a split and a branch per triangle at most (counted above)
  std::vector<Corner> corners(pass.corners);
  // Only corner rays some triangle uses are traced (a chunk of seeds may carry others).
  std::vector<uint8_t> cornerLive(nv, 0), triLive(nt, 1);
  for (const auto& t : pass.triangles)
    for (uint32_t i : t) cornerLive[i] = 1;
  std::vector<Rgb> power(pass.flux);
  std::vector<float> sigma2(nt, 0.0f);
  std::vector<Scatter> scatter(nv);
  std::vector<BeamSegment> generation(nt);
  std::vector<uint8_t> emitted(nt), branch(nt);
  std::vector<Outcome> outcome(nt);
  std::vector<uint32_t> live;
  RayBatch rays;
  for (int g = 0; g <= o.maxDepth; ++g) {
    live.clear();
    for (uint32_t i = 0; i < nv; ++i)
      if (cornerLive[i]) live.push_back(i);
    if (live.empty()) break;
    stats.generations = std::max(stats.generations, g + 1);
    // One generation of corner rays, in chunks the engine's budget holds.
    for (size_t first = 0; first < live.size(); first += o.raysPerTrace) {
      const size_t count = std::min(o.raysPerTrace, live.size() - first);
      rays.resize(count);
      for (size_t k = 0; k < count; ++k) {
        Corner& c = corners[live[first + k]];
        c.dir = Ray::traced(c.dir);  // the direction traced: the hit point and the beam's shape use it
        rays.set(k, RayKind::Closest, c.org, c.dir, std::numeric_limits<float>::infinity(), c.width, c.spread,
                 kNoLeaf, c.fromLeaf, c.fromLevel, /*shutterTime=*/0.0f);  // beams see the shutter's opening
      }
      trace(rays);
      stats.cornerRays += count;
      tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1024), [&](const auto& r) {
        for (size_t k = r.begin(); k != r.end(); ++k) {
          const uint32_t i = live[first + k];
          scatter[i] = scatterAt(scene, corners[i], rays.hitOf(k), o.far, g);
        }
      });
      // A distant light's first corner rays start near the scatterers: their way back toward
      // the light, past where they start, must be clear too, or the light never got there.
      size_t back = 0;
      for (size_t k = 0; k < count; ++k) {
        const Corner& c = corners[live[first + k]];
        if (g > 0 || !c.fromAfar) continue;
        rays.set(back++, RayKind::Shadow, c.org, -c.dir, std::numeric_limits<float>::infinity(), c.width, c.spread,
                 kNoLeaf, kNoLeaf, 0, 0.0f);
      }
      if (back == 0) continue;
      rays.resize(back);
      trace(rays);
      stats.cornerRays += back;
      for (size_t k = 0, b = 0; k < count; ++k) {
        const uint32_t i = live[first + k];
        if (!corners[i].fromAfar) continue;
        if (rays.occluded(b++)) scatter[i].onAim = false;
      }
    }
    // Each live beam: its segment (after a scattering) and whether it goes on.
    tbb::parallel_for(tbb::blocked_range<size_t>(0, nt, 1024), [&](const auto& r) {
      for (size_t t = r.begin(); t != r.end(); ++t) {
        emitted[t] = 0;
        branch[t] = 0;
        if (!triLive[t]) continue;
        const auto& v = pass.triangles[t];
        const Scatter* s[3] = {&scatter[v[0]], &scatter[v[1]], &scatter[v[2]]};
        const Vec3 dirs[3] = {corners[v[0]].dir, corners[v[1]].dir, corners[v[2]].dir};
        // A segment all of whose corners left the scene has nothing to light.
        const bool reachesSomething = s[0]->material != kNone || s[1]->material != kNone || s[2]->material != kNone;
        if (g > 0 && g > pass.emitted[t] && reachesSomething) {
          BeamSegment& seg = generation[t];
          for (int i = 0; i < 3; ++i) seg.o[i] = corners[v[i]].org, seg.d[i] = dirs[i], seg.t[i] = s[i]->t;
          seg.power = power[t];
          seg.sigma = std::sqrt(sigma2[t]);
          seg.scatterings = uint8_t(std::min(g, 255));
          emitted[t] = 1;
        }
        Outcome out = Outcome::Continue;
        // First corner rays must land on their leaf's aims: none on target, the beam's
        // directions belong to the surface in front (its own beams carry them); some, split.
        const int onAim = s[0]->onAim + s[1]->onAim + s[2]->onAim;
        const bool allScatter = s[0]->event != Event::Stop && s[1]->event != Event::Stop && s[2]->event != Event::Stop;
        const bool sameMaterial = s[0]->material == s[1]->material && s[1]->material == s[2]->material;
        const bool sameSide = s[0]->front == s[1]->front && s[1]->front == s[2]->front;
        if (g >= o.maxDepth || (g == 0 && onAim == 0)) out = Outcome::End;
        else if (g == 0 && onAim < 3) out = Outcome::Mixed;
        else if (!sameMaterial || !allScatter) out = sameMaterial && s[0]->event == Event::Stop && s[1]->event == Event::Stop &&
                                                         s[2]->event == Event::Stop ? Outcome::End : Outcome::Mixed;
        else if (!sameSide) out = Outcome::Silhouette;
        else if (s[0]->dielectric && g <= pass.branched[t] && !((corners[v[0]].reflectAt >> g) & 1u) &&
                 (s[0]->event == Event::Reflect || s[1]->event == Event::Reflect || s[2]->event == Event::Reflect))
          // The refracted part of a beam whose reflected branch at g exists: totally reflected
          // corners carry nothing here (the branch has them).
          out = s[0]->event == Event::Reflect && s[1]->event == Event::Reflect && s[2]->event == Event::Reflect
                    ? Outcome::End : Outcome::Tir;
        else if (s[0]->event != s[1]->event || s[1]->event != s[2]->event) out = Outcome::Tir;
        else {
          const Vec3 next[3] = {s[0]->next.dir, s[1]->next.dir, s[2]->next.dir};
          if (!coaxial(next)) out = Outcome::Divergent;
        }
        // At a dielectric that this beam does not yet reflect at, its reflected part is a beam
        // of its own (traced in the next pass; TIR corners reflect in both).
        branch[t] = g < o.maxDepth && g < 31 && g > pass.branched[t] && allScatter && sameMaterial && sameSide && s[0]->dielectric &&
                    (s[0]->event == Event::Refract || s[1]->event == Event::Refract || s[2]->event == Event::Refract);
        outcome[t] = out;
        if (out == Outcome::Continue) {
          power[t] = power[t] * ((s[0]->rho + s[1]->rho + s[2]->rho) * (1.0f / 3));
          const float sg = (s[0]->sigma + s[1]->sigma + s[2]->sigma) / 3;
          sigma2[t] += sg * sg;
        } else {
          triLive[t] = 0;
        }
      }
    });
    std::fill(cornerLive.begin(), cornerLive.end(), 0);
    size_t emitting = 0;
    for (size_t t = 0; t < nt; ++t) emitting += emitted[t] && maxComponent(generation[t].power) > 0;
    if (emitting > 0) {
      segments.push_back({{}, BeamCharge(budget, emitting * sizeof(Tagged), "beam segments")});
      segments.back().segments.reserve(emitting);
    }
    for (size_t t = 0; t < nt; ++t) {
      if (emitted[t] && maxComponent(generation[t].power) > 0) segments.back().segments.push_back({pass.root[t], generation[t]});
      if (branch[t]) derived.push_back({uint32_t(t), g, true}), ++stats.reflectedBranches;
      const Outcome out = outcome[t];
      if (out != Outcome::Continue && out != Outcome::End) {
        if (pass.level[t] < o.splitDepth) {
          derived.push_back({uint32_t(t), g, false, branch[t] != 0});
          ++stats.splits;
        } else {
          // The part of the beam whose corners would have gone on is lost (of a first beam,
          // only what lands on its aims: the rest is another surface's, which has its own beams).
          const auto& v = pass.triangles[t];
          int going = 0;
          for (uint32_t i : v) going += scatter[i].event != Event::Stop && (g > 0 || scatter[i].onAim);
          const Rgb lost = power[t] * (float(going) / 3);
          stats.droppedFlux += (double(lost.x) + double(lost.y) + double(lost.z)) / 3;
          switch (out) {
            case Outcome::Mixed: ++stats.stoppedMixed; break;
            case Outcome::Silhouette: ++stats.stoppedSilhouette; break;
            case Outcome::Tir: ++stats.stoppedTir; break;
            case Outcome::Divergent: ++stats.stoppedDivergent; break;
            default: break;
          }
        }
      }
      if (triLive[t])
        for (uint32_t i : pass.triangles[t]) cornerLive[i] = 1;
    }
    for (uint32_t i = 0; i < nv; ++i)
      if (cornerLive[i]) corners[i] = scatter[i].next;
    std::fill(outcome.begin(), outcome.end(), Outcome::End);
  }
}

}  // namespace

std::vector<BeamSegment> traceBeams(const ShadingScene& scene, const BeamSeeds& seeds, const BeamTraceOptions& o,
                                    const TraceRays& trace, BeamTraceStats& stats, BeamBudget* budget,
                                    BeamCharge* keep) {
  const size_t nt = seeds.triangles.size();
  BeamTraceStats own;  // added to stats only when the whole run fits
  own.generatorTriangles = nt;
  Pass pass;
  pass.charge = BeamCharge(budget, seeds.org.size() * Pass::kCornerBytes + nt * Pass::kTriangleBytes,
                           "the first corner rays of beams");
  pass.reserve(seeds.org.size(), nt);
  pass.corners.resize(seeds.org.size());
  for (size_t i = 0; i < seeds.org.size(); ++i)
    pass.corners[i] = {seeds.org[i], seeds.dir[i], seeds.coneWidth[i], seeds.coneSpread[i], kNoLeaf, 0,
                       i < seeds.fromAfar.size() && seeds.fromAfar[i] != 0, 0, seeds.aim[i]};
  pass.triangles = seeds.triangles;
  pass.flux = seeds.flux;
  pass.root.resize(nt);
  for (uint32_t t = 0; t < nt; ++t) pass.root[t] = t;
  pass.emitted.assign(nt, -1);
  pass.branched.assign(nt, -1);
  pass.level.assign(nt, 0);
  std::vector<TaggedRun> tagged;
  while (!pass.triangles.empty()) {
    std::vector<Derived> derived;
    tracePass(scene, pass, o, trace, budget, own, tagged, derived);
    Pass next = derive(pass, derived, budget);
    pass = std::move(next);
  }
  // Segment order: by root triangle, then pass, generation and triangle (a stable counting
  // sort), so the segments of a range of roots traced alone come out as the same run of this order.
  size_t total = 0;
  for (const TaggedRun& run : tagged) total += run.segments.size();
  BeamCharge order(budget, (nt + 1) * sizeof(uint64_t), "the order of beam segments");
  std::vector<uint64_t> at(nt + 1, 0);
  for (const TaggedRun& run : tagged)
    for (const Tagged& t : run.segments) ++at[t.root + 1];
  for (size_t t = 0; t < nt; ++t) at[t + 1] += at[t];
  BeamCharge out(budget, total * sizeof(BeamSegment), "beam segments");
  std::vector<BeamSegment> segments(total);
  for (TaggedRun& run : tagged) {
    for (const Tagged& t : run.segments) segments[at[t.root]++] = t.segment;
    run = {};
  }
  own.segments = total;
  stats.add(own);
  if (keep) *keep = std::move(out);
  return segments;
}

}  // namespace rayes
