#include "shading/light.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include "shading/sampling.h"

namespace rayes {
namespace {
constexpr float kPiF = std::numbers::pi_v<float>;
constexpr float kInfF = std::numeric_limits<float>::infinity();

// Direction <-> lat-long (u, v), θ from +z.
void toLatLong(Vec3 d, float& u, float& v, float& sinTheta) {
  const float rxy = std::sqrt(d.x * d.x + d.y * d.y);
  const float theta = std::atan2(rxy, d.z);
  float phi = std::atan2(d.y, d.x);
  if (phi < 0) phi += 2 * kPiF;
  u = std::min(phi / (2 * kPiF), 0.99999994f);
  v = std::min(theta / kPiF, 0.99999994f);
  sinTheta = rxy;
}

// Squared lengths and lengths of lights' vectors in double: dP/du x dP/dv is an area per unit
// parameter, so its float square overflows once a light's edges reach ~4e9 scene units (and
// underflows below ~1e-10); double holds every float vector's square exactly enough (its
// exponent range is 8 times wider), and the ratios built from them (pdfs) are back in range.
double lengthSquared(Vec3 a) { return double(a.x) * a.x + double(a.y) * a.y + double(a.z) * a.z; }
double dotD(Vec3 a, Vec3 b) { return double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z; }

// The solid-angle density of picking the point at squared distance d2 on a patch light with
// area density 1 / jacobian, seen along a direction at cosine cosY to its normal.
float patchSolidAnglePdf(float pick, double d2, double jacobian, double cosY) {
  const double pdf = double(pick) * d2 / (jacobian * cosY);
  return pdf < double(std::numeric_limits<float>::max()) ? float(pdf) : kInfF;
}
}  // namespace

float SpotLight::falloff(float c) const {
  if (c >= cosFalloffStart) return 1;
  if (c <= cosFalloffEnd) return 0;
  const float t = (c - cosFalloffEnd) / (cosFalloffStart - cosFalloffEnd);
  return t * t * (3 - 2 * t);
}

Rgb DistantLight::radiance() const {
  if (!(oneMinusCos > 0)) return {};
  const double sin2 = oneMinusCos * (2.0 - oneMinusCos);
  return irradiance * float(1.0 / (std::numbers::pi * sin2));
}

Environment::Environment(std::shared_ptr<const TextureImage> map, Rgb scale) : map_(std::move(map)), scale_(scale) {
  // The finest level at most kEnvironmentCells wide: its texels are box-filtered means of the
  // finest level's (texture/oiio/texture_file.h), so a cell is positive wherever a texel under it is.
  while (level_ + 1 < map_->levels() && map_->levelWidth(level_) > kEnvironmentCells) ++level_;
  const int w = map_->levelWidth(level_), h = map_->levelHeight(level_);
  const std::vector<Rgb> texels = map_->levelRgb(level_);
  std::vector<float> f(size_t(w) * h);
  double wsum = 0, fsum = 0;
  Vec3 sum{};
  for (int y = 0; y < h; ++y) {
    const float sinT = std::sin(kPiF * (y + 0.5f) / h);
    for (int x = 0; x < w; ++x) {
      const Rgb c = texels[size_t(y) * w + x] * scale_;
      f[size_t(y) * w + x] = std::max(0.0f, (c.x + c.y + c.z) / 3) * sinT;
      fsum += f[size_t(y) * w + x];
      sum += c * sinT;
      wsum += sinT;
    }
  }
  // A coarse cell's mean may round to nothing over a bright texel of a finer level: a floor of
  // 1e-4 of the mean keeps the density positive everywhere (unbiased), at a negligible cost in
  // variance. A level-0 distribution needs none (its cells are the texels eval() returns).
  if (level_ > 0 && fsum > 0) {
    const float floor = float(1e-4 * fsum / double(f.size()));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        float& v = f[size_t(y) * w + x];
        v = std::max(v, floor * std::sin(kPiF * (y + 0.5f) / h));
      }
  }
  average_ = wsum > 0 ? sum * float(1.0 / wsum) : Rgb{};
  dist_ = Distribution2D(f, size_t(w), size_t(h));
}

Rgb Environment::eval(Vec3 d) const {
  if (!map_) return constant_;
  float u, v, s;
  toLatLong(d, u, v, s);
  // Texel centres at (x + 0.5) / width: the texel holding u is floor(u * width), as the
  // distribution's cells.
  return map_->closest(u, v) * scale_;
}

float Environment::pdf(Vec3 d) const {
  if (!map_) return 1.0f / (4 * kPiF);
  float u, v, s;
  toLatLong(d, u, v, s);
  if (!(s > 0)) return 0;
  const float p = dist_.pdf(u, v) / (2 * kPiF * kPiF * s);
  return std::isfinite(p) ? p : 0.0f;
}

bool Environment::sample(float u1, float u2, Vec3& d, float& pdf) const {
  if (!map_) {
    const float z = 1 - 2 * u1, r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPiF * u2;
    d = {r * std::cos(phi), r * std::sin(phi), z};
    pdf = 1.0f / (4 * kPiF);
    return true;
  }
  float u, v, p;
  dist_.sample(u1, u2, u, v, p);
  const float theta = v * kPiF, phi = u * 2 * kPiF;
  const float s = std::sin(theta);
  if (!(s > 0) || !(p > 0)) return false;
  d = {s * std::cos(phi), s * std::sin(phi), std::cos(theta)};
  pdf = p / (2 * kPiF * kPiF * s);
  return std::isfinite(pdf);
}

LightSampler::LightSampler(std::vector<PointLight> points, std::vector<PatchLight> patches, SceneLights more,
                           float sceneRadius, Vec3 sceneCenter)
    : points_(std::move(points)), patches_(std::move(patches)), more_(std::move(more)), radius_(sceneRadius),
      center_(sceneCenter) {
  std::vector<double> power;
  for (const auto& p : points_) power.push_back(4.0 * std::numbers::pi * std::max(0.0f, luminance(p.intensity)));
  spot0_ = power.size();
  for (const auto& s : more_.spots)
    power.push_back(2.0 * std::numbers::pi * (1.0 - 0.5 * (s.cosFalloffStart + s.cosFalloffEnd)) *
                    std::max(0.0f, luminance(s.intensity)));
  patch0_ = power.size();
  for (const auto& p : patches_) {
    // Area by a 8x8 midpoint rule: only used to balance the choice between lights, so an
    // estimate is enough; any positive weights keep the estimator unbiased.
    double area = 0;
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i) {
        Vec3 pos, n;
        p.evaluate((i + 0.5f) / 8, (j + 0.5f) / 8, pos, n);
        area += std::sqrt(lengthSquared(n)) / 64.0;
      }
    const double sides = p.twoSided ? 2.0 : 1.0;
    power.push_back(std::numbers::pi * sides * area * std::max(0.0f, luminance(p.radiance)));
  }
  const double disk = std::numbers::pi * double(sceneRadius) * sceneRadius;
  distant0_ = power.size();
  for (const auto& d : more_.distants) power.push_back(disk * std::max(0.0f, luminance(d.irradiance)));
  env_ = power.size();
  if (more_.environment)
    power.push_back(std::numbers::pi * disk * std::max(0.0f, luminance(more_.environment->averageRadiance())));
  double total = 0;
  for (double w : power) total += w;
  if (power.empty()) return;
  // All lights dark (or a zero-area light): fall back to a uniform choice.
  if (!(total > 0) || !std::isfinite(total)) {
    std::fill(power.begin(), power.end(), 1.0);
    total = double(power.size());
  }
  double acc = 0;
  for (double w : power) { acc += w; cdf_.push_back(float(acc / total)); }
  cdf_.back() = 1.0f;
  uint32_t maxLeaf = 0;
  for (const auto& p : patches_) maxLeaf = std::max(maxLeaf, p.leaf + 1);
  leafToPatchLight_.assign(maxLeaf, -1);
  for (size_t i = 0; i < patches_.size(); ++i) leafToPatchLight_[patches_[i].leaf] = int(i);
  hittable_ = !patches_.empty() || more_.environment;
  for (const auto& d : more_.distants) hittable_ |= d.oneMinusCos > 0;
}

int LightSampler::patchLightOfLeaf(uint32_t leaf) const {
  return leaf < leafToPatchLight_.size() ? leafToPatchLight_[leaf] : -1;
}

size_t LightSampler::pickIndex(float u0) const {
  return std::min<size_t>(std::upper_bound(cdf_.begin(), cdf_.end(), u0) - cdf_.begin(), cdf_.size() - 1);
}

bool LightSampler::sample(Vec3 ref, float u0, float u1, float u2, LightSample& out) const {
  if (cdf_.empty()) return false;
  const size_t k = pickIndex(u0);
  const float pk = pick(k);
  if (!(pk > 0)) return false;
  out.leaf = 0xffffffffu;
  out.delta = false;
  out.normal = {};
  if (k < patch0_) {  // point or spot
    const bool spot = k >= spot0_;
    const Vec3 pos = spot ? more_.spots[k - spot0_].position : points_[k].position;
    const Vec3 d = pos - ref;
    const double d2 = lengthSquared(d);
    if (!(d2 > 0) || !std::isfinite(d2)) return false;
    out.distance = float(std::sqrt(d2));
    out.wi = d * float(1.0 / std::sqrt(d2));
    out.point = pos;
    Rgb intensity = spot ? more_.spots[k - spot0_].intensity : points_[k].intensity;
    if (spot) intensity = intensity * more_.spots[k - spot0_].falloff(-dot(out.wi, more_.spots[k - spot0_].direction));
    out.radiance = intensity * float(1.0 / d2);
    out.pdf = pk;
    out.delta = true;
    out.kind = spot ? kSpotLight : kPointLight;
    return true;
  }
  if (k < distant0_) {
    out.kind = kPatchLight;
    const PatchLight& l = patches_[k - patch0_];
    Vec3 p, n;
    l.evaluate(u1, u2, p, n);
    const double jacobian = std::sqrt(lengthSquared(n));
    if (!(jacobian > 0) || !std::isfinite(jacobian)) return false;
    const Vec3 d = p - ref;
    const double d2 = lengthSquared(d);
    if (!(d2 > 0) || !std::isfinite(d2)) return false;
    const double dist = std::sqrt(d2);
    out.distance = float(dist);
    out.wi = d * float(1.0 / dist);
    double cosY = -dotD(n, d) / (jacobian * dist);
    if (l.twoSided) cosY = std::fabs(cosY);
    if (!(cosY > 0)) return false;
    out.radiance = l.radiance;
    out.point = p;
    out.normal = n * float(1.0 / jacobian);
    out.pdf = patchSolidAnglePdf(pk, d2, jacobian, cosY);
    out.leaf = l.leaf;
    return std::isfinite(out.pdf) && out.pdf > 0;
  }
  out.distance = kInfF;
  out.kind = k < env_ ? kDistantLight : kEnvironmentLight;
  if (k < env_) {
    const DistantLight& l = more_.distants[k - distant0_];
    if (!(l.oneMinusCos > 0)) {
      out.wi = l.direction;
      out.radiance = l.irradiance;
      out.pdf = pk;
      out.delta = true;
      return true;
    }
    out.wi = sampleUniformCone(l.direction, l.oneMinusCos, u1, u2);
    out.radiance = l.radiance();
    out.pdf = pk * float(1.0 / (2.0 * std::numbers::pi * l.oneMinusCos));
    return true;
  }
  float pdf = 0;
  if (!more_.environment->sample(u1, u2, out.wi, pdf)) return false;
  out.radiance = more_.environment->eval(out.wi);
  out.pdf = pk * pdf;
  return out.pdf > 0 && std::isfinite(out.pdf);
}

float LightSampler::patchPdf(int i, float u, float v, Vec3 wi, float dist) const {
  if (i < 0) return 0;
  const PatchLight& l = patches_[size_t(i)];
  Vec3 p, n;
  l.evaluate(u, v, p, n);
  const double jacobian = std::sqrt(lengthSquared(n));
  const double cosY = std::fabs(dotD(n, wi)) / jacobian;
  if (!(jacobian > 0) || !(cosY > 0)) return 0;
  const float pdf = patchSolidAnglePdf(pick(patch0_ + size_t(i)), double(dist) * dist, jacobian, cosY);
  return std::isfinite(pdf) ? pdf : 0.0f;
}

Rgb LightSampler::escaped(Vec3 dir, float bsdfPdf, bool bsdfDelta, uint8_t kinds) const {
  Rgb sum{};
  for (size_t i = 0; i < more_.distants.size() && (kinds & kDistantLight); ++i) {
    const DistantLight& l = more_.distants[i];
    if (!(l.oneMinusCos > 0)) continue;
    const Vec3 e = dir - l.direction;
    if (!(0.5 * double(dot(e, e)) <= l.oneMinusCos)) continue;  // 1 - cos θ = |dir - axis|² / 2
    const float pdf = pick(distant0_ + i) * float(1.0 / (2.0 * std::numbers::pi * l.oneMinusCos));
    sum += l.radiance() * (bsdfDelta ? 1.0f : powerHeuristic(bsdfPdf, pdf));
  }
  if (more_.environment && (kinds & kEnvironmentLight)) {
    const Rgb le = more_.environment->eval(dir);
    if (!isBlack(le)) {
      const float pdf = pick(env_) * more_.environment->pdf(dir);
      sum += le * (bsdfDelta ? 1.0f : powerHeuristic(bsdfPdf, pdf));
    }
  }
  return sum;
}

}  // namespace rayes
