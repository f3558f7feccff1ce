#include "geometry/patch_record.h"
#include <cstring>
#include <stdexcept>
#include "geometry/bezier_patch.h"
#include "geometry/bilinear_patch.h"
#include "geometry/displaced_patch.h"
#include "geometry/displacement.h"
#include "geometry/moving_patch.h"

namespace rayes {
namespace {

// Tags: new kinds take new numbers (and a format version bump, geometry/compiled_file.h).
enum Tag : uint8_t { kBezier = 1, kBilinear = 2, kDisplaced = 3, kMoving = 4 };
enum DisplacementTag : uint8_t { kNoise = 1 };
// The largest motion a record may hold: keyframes are few, and a corrupt count must not
// make the decoder reserve gigabytes.
constexpr uint32_t kMaxTimeSamples = 1u << 16;

class Writer {
 public:
  explicit Writer(std::vector<uint8_t>& out) : out_(out) {}
  template <class T>
  void put(const T& v) {
    const size_t at = out_.size();
    out_.resize(at + sizeof(T));
    std::memcpy(out_.data() + at, &v, sizeof(T));
  }
  void put(Vec3 v) {
    put(v.x);
    put(v.y);
    put(v.z);
  }

 private:
  std::vector<uint8_t>& out_;
};

class Reader {
 public:
  Reader(const uint8_t* data, size_t bytes) : p_(data), end_(data + bytes) {}
  template <class T>
  T get() {
    if (size_t(end_ - p_) < sizeof(T)) throw std::invalid_argument("the record ends inside a field");
    T v;
    std::memcpy(&v, p_, sizeof(T));
    p_ += sizeof(T);
    return v;
  }
  Vec3 vec3() {
    const float x = get<float>(), y = get<float>(), z = get<float>();
    return {x, y, z};
  }
  bool atEnd() const { return p_ == end_; }

 private:
  const uint8_t* p_;
  const uint8_t* end_;
};

std::string encodeDisplacement(const Displacement& d, Writer& w) {
  const auto* noise = dynamic_cast<const NoiseDisplacement*>(&d);
  if (!noise) return std::string("a displacement of kind '") + d.kind() + "' (only noise displacement is compiled)";
  const NoiseParams& p = noise->params();
  w.put(uint8_t(kNoise));
  w.put(p.amplitude);
  w.put(p.frequency);
  w.put(int32_t(p.octaves));
  w.put(p.gain);
  w.put(p.lacunarity);
  w.put(p.seed);
  w.put(uint8_t(p.ridged));
  w.put(p.offset);
  return "";
}

DisplacementPtr decodeDisplacement(Reader& r) {
  const uint8_t tag = r.get<uint8_t>();
  if (tag != kNoise) throw std::invalid_argument("unknown displacement tag " + std::to_string(tag));
  NoiseParams p;
  p.amplitude = r.get<float>();
  p.frequency = r.get<float>();
  p.octaves = r.get<int32_t>();
  p.gain = r.get<float>();
  p.lacunarity = r.get<float>();
  p.seed = r.get<uint32_t>();
  p.ridged = r.get<uint8_t>() != 0;
  p.offset = r.get<float>();
  return std::make_shared<NoiseDisplacement>(p);  // refuses parameters out of range
}

std::string encode(const Patch& patch, Writer& w) {
  if (const auto* b = dynamic_cast<const BezierPatch*>(&patch)) {
    w.put(uint8_t(kBezier));
    for (const Vec3& p : b->controlPoints()) w.put(p);
    return "";
  }
  if (const auto* b = dynamic_cast<const BilinearPatch*>(&patch)) {
    w.put(uint8_t(kBilinear));
    for (const Vec3& p : b->corners()) w.put(p);
    return "";
  }
  if (const auto* d = dynamic_cast<const DisplacedPatch*>(&patch)) {
    w.put(uint8_t(kDisplaced));
    w.put(uint8_t(d->givenReference() != nullptr));
    if (std::string why = encodeDisplacement(d->displacement(), w); !why.empty()) return why;
    if (std::string why = encode(d->base(), w); !why.empty()) return why;
    return d->givenReference() ? encode(*d->givenReference(), w) : "";
  }
  if (const auto* m = dynamic_cast<const MovingPatch*>(&patch)) {
    w.put(uint8_t(kMoving));
    w.put(uint32_t(m->timeSamples()));
    for (int s = 0; s < m->timeSamples(); ++s) w.put(m->sampleTime(s));
    for (int s = 0; s < m->timeSamples(); ++s)
      if (std::string why = encode(m->sample(s), w); !why.empty()) return why;
    return "";
  }
  return std::string("a patch of kind '") + patch.kind() + "'";
}

PatchPtr decode(Reader& r, int depth) {
  // Decorators nest at most displaced inside moving (and a reference inside displaced).
  if (depth > 4) throw std::invalid_argument("decorators nested too deep");
  const uint8_t tag = r.get<uint8_t>();
  switch (tag) {
    case kBezier: {
      std::array<Vec3, 16> cp;
      for (Vec3& p : cp) p = r.vec3();
      return std::make_shared<BezierPatch>(cp);
    }
    case kBilinear: {
      const Vec3 p00 = r.vec3(), p10 = r.vec3(), p01 = r.vec3(), p11 = r.vec3();
      return std::make_shared<BilinearPatch>(p00, p10, p01, p11);
    }
    case kDisplaced: {
      const bool hasReference = r.get<uint8_t>() != 0;
      DisplacementPtr d = decodeDisplacement(r);
      PatchPtr base = decode(r, depth + 1);
      PatchPtr reference = hasReference ? decode(r, depth + 1) : nullptr;
      return std::make_shared<DisplacedPatch>(std::move(base), std::move(d), std::move(reference));
    }
    case kMoving: {
      const uint32_t n = r.get<uint32_t>();
      if (n < 2 || n > kMaxTimeSamples) throw std::invalid_argument("a moving patch with " + std::to_string(n) + " time samples");
      std::vector<float> times(n);
      for (float& t : times) t = r.get<float>();
      std::vector<PatchPtr> samples(n);
      for (PatchPtr& s : samples) s = decode(r, depth + 1);
      return std::make_shared<MovingPatch>(std::move(samples), std::move(times));  // refuses bad times
    }
    default:
      throw std::invalid_argument("unknown patch tag " + std::to_string(tag));
  }
}

}  // namespace

std::string encodePatch(const Patch& patch, std::vector<uint8_t>& out) {
  Writer w(out);
  return encode(patch, w);
}

PatchPtr decodePatch(const uint8_t* data, size_t bytes) {
  Reader r(data, bytes);
  PatchPtr p = decode(r, 0);
  if (!r.atEnd()) throw std::invalid_argument("the record is longer than its patch");
  return p;
}

}  // namespace rayes
