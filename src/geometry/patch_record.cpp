#include "geometry/patch_record.h"
#include <cstring>
#include <stdexcept>
#include "geometry/bezier_patch.h"
#include "geometry/bilinear_patch.h"
#include "geometry/displaced_patch.h"
#include "geometry/displacement.h"
#include "geometry/moving_patch.h"
#include "geometry/subdiv_patch.h"

namespace rayes {
namespace {

// Tags: new kinds take new numbers (and a format version bump, geometry/compiled_file.h).
// kForestLeaf (format version 4): a forest leaf named by its forest and its ForestLeaf, made by
// the forest's ForestPatches over its mapped tables.
enum Tag : uint8_t { kBezier = 1, kBilinear = 2, kDisplaced = 3, kMoving = 4, kSubdivFace = 5, kForestLeaf = 6 };
enum DisplacementTag : uint8_t { kNoise = 1, kHeightMap = 2 };
// A topology's counts are checked against the record's length before anything is reserved.
constexpr uint32_t kTopologyVersion = 1;
// A vertex count beyond any mesh a scene loads (its positions alone 3 GiB): a corrupt record.
constexpr uint32_t kMaxVertices = 1u << 28;
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
  size_t left() const { return size_t(end_ - p_); }
  // n values of T, checked against what is left first (a corrupt count reserves nothing).
  template <class T>
  std::vector<T> array(uint32_t n) {
    if (left() / sizeof(T) < n) throw std::invalid_argument("a count larger than the record");
    std::vector<T> v(n);
    if (n != 0) std::memcpy(v.data(), p_, size_t(n) * sizeof(T));  // an empty vector's data() may be null
    p_ += size_t(n) * sizeof(T);
    return v;
  }

 private:
  const uint8_t* p_;
  const uint8_t* end_;
};

std::string encodeDisplacement(const Displacement& d, Writer& w, const RecordTableIndex* shared) {
  if (const auto* map = dynamic_cast<const HeightMapDisplacement*>(&d)) {
    if (!shared) return "a height-map displacement without a table of shared objects";
    if (map->origin().file.empty()) return "a height map made in memory (no file to name)";
    w.put(uint8_t(kHeightMap));
    w.put(shared->heightMapIndex(map));
    return "";
  }
  const auto* noise = dynamic_cast<const NoiseDisplacement*>(&d);
  if (!noise) return std::string("a displacement of kind '") + d.kind() + "'";
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

DisplacementPtr decodeDisplacement(Reader& r, const RecordTables* shared) {
  const uint8_t tag = r.get<uint8_t>();
  if (tag == kHeightMap) {
    const uint32_t k = r.get<uint32_t>();
    if (!shared || k >= shared->heightMaps.size())
      throw std::invalid_argument("height map " + std::to_string(k) + " of " +
                                  std::to_string(shared ? shared->heightMaps.size() : 0));
    return shared->heightMaps[k];
  }
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

std::string encode(const Patch& patch, Writer& w, const RecordTableIndex* shared) {
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
    if (std::string why = encodeDisplacement(d->displacement(), w, shared); !why.empty()) return why;
    if (std::string why = encode(d->base(), w, shared); !why.empty()) return why;
    return d->givenReference() ? encode(*d->givenReference(), w, shared) : "";
  }
  if (const auto* m = dynamic_cast<const MovingPatch*>(&patch)) {
    w.put(uint8_t(kMoving));
    w.put(uint32_t(m->timeSamples()));
    for (int s = 0; s < m->timeSamples(); ++s) w.put(m->sampleTime(s));
    for (int s = 0; s < m->timeSamples(); ++s)
      if (std::string why = encode(m->sample(s), w, shared); !why.empty()) return why;
    return "";
  }
  if (const auto* f = dynamic_cast<const SubdivFacePatch*>(&patch)) {
    if (!shared) return "a subdivision face without a table of shared objects";
    w.put(uint8_t(kSubdivFace));
    w.put(shared->meshIndex(&f->mesh()));
    w.put(int32_t(f->leaf()));
    return "";
  }
  return std::string("a patch of kind '") + patch.kind() + "'";
}

PatchPtr decode(Reader& r, int depth, const RecordTables* shared) {
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
      DisplacementPtr d = decodeDisplacement(r, shared);
      PatchPtr base = decode(r, depth + 1, shared);
      PatchPtr reference = hasReference ? decode(r, depth + 1, shared) : nullptr;
      return std::make_shared<DisplacedPatch>(std::move(base), std::move(d), std::move(reference));
    }
    case kMoving: {
      const uint32_t n = r.get<uint32_t>();
      if (n < 2 || n > kMaxTimeSamples) throw std::invalid_argument("a moving patch with " + std::to_string(n) + " time samples");
      std::vector<float> times(n);
      for (float& t : times) t = r.get<float>();
      std::vector<PatchPtr> samples(n);
      for (PatchPtr& s : samples) s = decode(r, depth + 1, shared);
      return std::make_shared<MovingPatch>(std::move(samples), std::move(times));  // refuses bad times
    }
    case kSubdivFace: {
      const uint32_t mesh = r.get<uint32_t>();
      const int32_t leaf = r.get<int32_t>();
      if (!shared || mesh >= shared->meshes.size())
        throw std::invalid_argument("subdivision mesh " + std::to_string(mesh) + " of " +
                                    std::to_string(shared ? shared->meshes.size() : 0));
      const SubdivMeshPtr& m = shared->meshes[mesh];
      if (leaf < 0 || leaf >= m->leafCount())
        throw std::invalid_argument("face leaf " + std::to_string(leaf) + " of a mesh of " + std::to_string(m->leafCount()));
      return std::make_shared<SubdivFacePatch>(m, leaf);
    }
    case kForestLeaf: {
      const uint32_t forest = r.get<uint32_t>();
      ForestLeaf leaf;
      leaf.part = ForestLeaf::Part(r.get<uint8_t>());
      leaf.quarter = r.get<uint8_t>();
      leaf.segment = r.get<uint16_t>();
      leaf.index = r.get<uint32_t>();
      if (!shared || forest >= shared->forests.size())
        throw std::invalid_argument("forest " + std::to_string(forest) + " of " + std::to_string(shared ? shared->forests.size() : 0));
      return shared->forests[forest]->make(leaf);  // refuses a leaf outside the forest's tables
    }
    default:
      throw std::invalid_argument("unknown patch tag " + std::to_string(tag));
  }
}

}  // namespace

void RecordTableIndex::add(const Patch& patch) {
  if (const auto* d = dynamic_cast<const DisplacedPatch*>(&patch)) {
    if (const auto* map = dynamic_cast<const HeightMapDisplacement*>(&d->displacement()))
      if (heightMapIndex_.emplace(map, uint32_t(heightMaps_.size())).second) heightMaps_.push_back(map);
    add(d->base());
    if (d->givenReference()) add(*d->givenReference());
  } else if (const auto* m = dynamic_cast<const MovingPatch*>(&patch)) {
    for (int s = 0; s < m->timeSamples(); ++s) add(m->sample(s));
  } else if (const auto* f = dynamic_cast<const SubdivFacePatch*>(&patch)) {
    const SubdivMesh* mesh = &f->mesh();
    if (!meshIndex_.emplace(mesh, uint32_t(meshes_.size())).second) return;
    meshes_.push_back(mesh);
    const SubdivTopology* t = &mesh->topology();
    const auto [it, added] = topologyIndex_.emplace(t, uint32_t(topologies_.size()));
    if (added) topologies_.push_back(t);
    meshTopology_.push_back(it->second);
  }
}

uint32_t RecordTableIndex::addForest(const Forest& forest) {
  const auto [it, added] = forestIndex_.emplace(&forest, uint32_t(forests_.size()));
  if (added) forests_.push_back(&forest);
  return it->second;
}

void encodeForestLeaf(uint32_t forest, const ForestLeaf& leaf, std::vector<uint8_t>& out) {
  Writer w(out);
  w.put(uint8_t(kForestLeaf));
  w.put(forest);
  w.put(uint8_t(leaf.part));
  w.put(leaf.quarter);
  w.put(leaf.segment);
  w.put(leaf.index);
}

std::string encodePatch(const Patch& patch, std::vector<uint8_t>& out, const RecordTableIndex* shared) {
  Writer w(out);
  return encode(patch, w, shared);
}

PatchPtr decodePatch(const uint8_t* data, size_t bytes, const RecordTables* shared) {
  Reader r(data, bytes);
  PatchPtr p = decode(r, 0, shared);
  if (!r.atEnd()) throw std::invalid_argument("the record is longer than its patch");
  return p;
}

void encodeSubdivTopology(const SubdivTopology& topology, std::vector<uint8_t>& out) {
  const SubdivMeshDesc d = describeTopology(topology);
  Writer w(out);
  w.put(kTopologyVersion);
  w.put(uint8_t(d.scheme));
  w.put(uint8_t(d.boundary));
  w.put(uint8_t(d.uvInterpolation));
  w.put(uint8_t(builtRegularAsBezier(topology)));
  w.put(uint32_t(d.positions.size()));
  const auto ints = [&](const std::vector<int>& v) {
    w.put(uint32_t(v.size()));
    for (int x : v) w.put(int32_t(x));
  };
  ints(d.faceSizes);
  ints(d.faceVertices);
  w.put(uint32_t(d.creases.size()));
  for (const SubdivCrease& c : d.creases) {
    w.put(int32_t(c.v0));
    w.put(int32_t(c.v1));
    w.put(c.sharpness);
  }
  w.put(uint32_t(d.corners.size()));
  for (const SubdivCorner& c : d.corners) {
    w.put(int32_t(c.v));
    w.put(c.sharpness);
  }
  ints(d.holes);
  w.put(uint32_t(d.uvs.size()));
  for (const auto& st : d.uvs) {
    w.put(st[0]);
    w.put(st[1]);
  }
  ints(d.uvIndices);
}

std::shared_ptr<const SubdivTopology> decodeSubdivTopology(const uint8_t* data, size_t bytes) {
  Reader r(data, bytes);
  if (const uint32_t v = r.get<uint32_t>(); v != kTopologyVersion)
    throw std::invalid_argument("unknown topology record version " + std::to_string(v));
  SubdivMeshDesc d;
  const uint8_t scheme = r.get<uint8_t>(), boundary = r.get<uint8_t>(), fvar = r.get<uint8_t>();
  const bool regularAsBezier = r.get<uint8_t>() != 0;
  if (scheme > uint8_t(SubdivScheme::Bilinear) || boundary > uint8_t(SubdivBoundary::EdgeAndCorner) ||
      fvar > uint8_t(SubdivUvInterpolation::All))
    throw std::invalid_argument("an unknown scheme, boundary rule or uv interpolation");
  d.scheme = SubdivScheme(scheme);
  d.boundary = SubdivBoundary(boundary);
  d.uvInterpolation = SubdivUvInterpolation(fvar);
  const uint32_t vertices = r.get<uint32_t>();
  if (vertices > kMaxVertices) throw std::invalid_argument(std::to_string(vertices) + " vertices");
  d.positions.assign(vertices, Vec3{});
  const auto ints = [&] {
    const std::vector<int32_t> v = r.array<int32_t>(r.get<uint32_t>());
    return std::vector<int>(v.begin(), v.end());
  };
  d.faceSizes = ints();
  d.faceVertices = ints();
  const uint32_t creases = r.get<uint32_t>();
  if (r.left() / 12 < creases) throw std::invalid_argument("a count larger than the record");
  d.creases.resize(creases);
  for (SubdivCrease& c : d.creases) {
    c.v0 = r.get<int32_t>();
    c.v1 = r.get<int32_t>();
    c.sharpness = r.get<float>();
  }
  const uint32_t corners = r.get<uint32_t>();
  if (r.left() / 8 < corners) throw std::invalid_argument("a count larger than the record");
  d.corners.resize(corners);
  for (SubdivCorner& c : d.corners) {
    c.v = r.get<int32_t>();
    c.sharpness = r.get<float>();
  }
  d.holes = ints();
  // Checked before doubling: a corrupt count of 2^31 + n would wrap to the 2n floats that follow.
  const uint32_t uvCount = r.get<uint32_t>();
  if (r.left() / 8 < uvCount) throw std::invalid_argument("a count larger than the record");
  const std::vector<float> uvs = r.array<float>(uvCount * 2);
  d.uvs.resize(uvs.size() / 2);
  for (size_t k = 0; k < d.uvs.size(); ++k) d.uvs[k] = {uvs[2 * k], uvs[2 * k + 1]};
  d.uvIndices = ints();
  if (!r.atEnd()) throw std::invalid_argument("the record is longer than its topology");
  try {
    return buildSubdivTopology(d, regularAsBezier);
  } catch (const SubdivInputError& e) {
    throw std::invalid_argument(std::string("the topology is refused: ") + e.what());
  }
}

}  // namespace rayes
