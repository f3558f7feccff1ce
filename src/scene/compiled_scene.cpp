#include "scene/compiled_scene.h"
#include <array>
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <tbb/parallel_for.h>
#include "core/error.h"
#include "core/version.h"
#include "geometry/forest_leaves.h"
#include "geometry/mapped_leaves.h"
#include "geometry/patch_record.h"
#include "scene/json_document.h"
#include "scene/scene_loader.h"
#include "scene/shape_kinds.h"
#include "shading/shading_scene.h"

namespace rayes {

using compiled::LeafEntry;
using compiled::SectionKind;

namespace {

// Leaves encoded at a time: their records are held in memory until written.
constexpr size_t kChunkLeaves = size_t(1) << 16;

// Writes n fixed-size rows made by row(i), filled in parallel a chunk at a time: a section of
// 10 M leaves never holds more than a chunk of its rows.
template <class Row, class MakeRow>
void writeRows(CompiledFileWriter& w, size_t n, MakeRow&& row) {
  std::vector<Row> rows;
  for (size_t c0 = 0; c0 < n; c0 += kChunkLeaves) {
    const size_t c1 = std::min(n, c0 + kChunkLeaves);
    rows.resize(c1 - c0);
    tbb::parallel_for(c0, c1, [&](size_t i) { rows[i - c0] = row(i); });
    w.write(rows.data(), rows.size() * sizeof(Row));
  }
}

LeafEntry entryOf(const Scene& scene, size_t i, uint8_t kind, uint64_t offset, uint32_t bytes) {
  const Box3 b = scene.leaves.bounds(i);
  const LeafFacts f = scene.leaves.facts(i);
  LeafEntry e{};
  for (int k = 0; k < 3; ++k) {
    e.lo[k] = b.lo[k];
    e.hi[k] = b.hi[k];
  }
  e.sizeBound = f.sizeBound;
  e.dicingError = f.dicingError;
  e.recordOffset = offset;
  e.recordBytes = bytes;
  e.timeSamples = uint16_t(f.timeSamples);
  e.kind = kind;
  e.flags = uint8_t((f.displaced ? LeafEntry::kDisplaced : 0) | (f.subdivision ? LeafEntry::kSubdivision : 0) |
                    (f.borderClosure ? LeafEntry::kBorderClosure : 0));
  return e;
}

// The UvSets section: a record per shape leaf (subdivision sets renumbered by topology), then
// every corner entry of the table.
void writeUvSets(const LeafUvTable& uvs, size_t n, const RecordTableIndex& shared, CompiledFileWriter& w) {
  w.beginSection(SectionKind::UvSets);
  std::vector<LeafUvTable::Ref> refs;
  for (size_t c0 = 0; c0 < n; c0 += kChunkLeaves) {
    const size_t c1 = std::min(n, c0 + kChunkLeaves);
    refs.resize(c1 - c0);
    for (size_t i = c0; i < c1; ++i) {
      LeafUvTable::Ref r = uvs.ref(uint32_t(i));
      if (r.table >= 2) r.table = 2 + shared.topologyIndex(&uvs.subdivSet(r.table)->topology());
      refs[i - c0] = r;
    }
    w.write(refs.data(), refs.size() * sizeof(LeafUvTable::Ref));
  }
  for (size_t k = 0; k < uvs.cornerCount(); ++k) {
    const UvCorners c = uvs.corners(uint32_t(k));
    w.write(&c, sizeof c);
  }
}

// What shading reads per hit, for every leaf of the render (the lights' too), as RenderData
// and the PathTracer make it for the JSON route.
void writeLeafShading(const Scene& scene, CompiledFileWriter& w) {
  const size_t total = scene.leaves.size();
  const std::vector<uint32_t> ranks = shadeRanks(scene.leafMaterial);
  w.beginSection(SectionKind::LeafShading);
  writeRows<LeafShadingRow>(w, total, [&](size_t i) {
    return LeafShadingRow{scene.leafMaterial[i], scene.leaves.bounds(i).longestSide(), scene.leaves.facts(i).dicingError,
                          ranks[i]};
  });
}

// The forest that generated shape leaf i, and i's leaf in it; null for any other leaf.
std::pair<const Forest*, size_t> forestOf(const Scene& scene, size_t i) {
  const auto [source, k] = scene.leaves.locate(i);
  const auto* forest = dynamic_cast<const ForestLeaves*>(source);
  return {forest ? &forest->forest() : nullptr, k};
}

// Forests section: where each forest's tables lie, and what they hold (compiled::ForestHeader).
constexpr uint64_t kForestAlign = 64;  // each forest starts aligned: its tables are read in place
uint64_t forestBytes(const Forest& f) {
  return sizeof(compiled::ForestHeader) + f.branchCount() * sizeof(ForestBranch) + f.foliageCount() * sizeof(ForestFoliage);
}

void writeForests(const std::vector<const Forest*>& forests, CompiledFileWriter& w) {
  static const uint8_t zeros[kForestAlign] = {};
  w.beginSection(SectionKind::Forests);
  for (const Forest* f : forests) {
    const ForestParams& p = f->params();
    compiled::ForestHeader h;
    h.seed = p.seed;
    h.branchCount = f->branchCount();
    h.foliageCount = f->foliageCount();
    h.trees = p.trees;
    h.detail = p.detail;
    h.branching = p.branching;
    h.terrainTiles = p.terrainTiles;
    h.leavesPerTwig = p.leavesPerTwig;
    h.area = p.area;
    h.treeHeight = p.treeHeight;
    h.terrainAmplitude = p.terrainAmplitude;
    std::memcpy(h.placement, p.placement.m, sizeof h.placement);
    w.write(&h, sizeof h);
    // The tables' own bytes (no implicit padding: geometry/forest_patches.h).
    if (f->branchCount()) w.write(&f->branch(0), f->branchCount() * sizeof(ForestBranch));
    if (f->foliageCount()) w.write(&f->foliage(0), f->foliageCount() * sizeof(ForestFoliage));
    w.write(zeros, (kForestAlign - forestBytes(*f) % kForestAlign) % kForestAlign);
  }
}

}  // namespace

bool isCompiledSceneName(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".rayes";
}

void writeCompiledScene(const Scene& scene, const std::string& jsonText, const std::string& jsonPath,
                        const std::string& outPath, const compiled::StoredTopLevel& top,
                        const std::function<void(size_t, size_t)>& progress) {
  const size_t n = scene.shapeLeaves;
  if (top.leafCount != scene.leaves.size()) throw std::logic_error("writeCompiledScene: the top level is not over the scene's leaves");
  // What records share (meshes, their topologies, height maps), numbered in leaf order.
  // A forest's leaves are stored by their forest (its generator tables, once), not as patches.
  RecordTableIndex shared;
  for (size_t i = 0; i < n; ++i) {
    if (const auto [forest, k] = forestOf(scene, i); forest) {
      shared.addForest(*forest);
      i += forest->size() - k - 1;
      continue;
    }
    shared.add(*scene.leaves.patch(i));
  }
  // Volumes have no section in the format: refused rather than rendered without their media.
  if (!scene.media.empty())
    throw InputError(jsonPath, "/shapes", "volumes cannot be compiled yet (the compiled format has no volume section); render the JSON scene");
  // The leaf kinds' names, in order of first appearance.
  std::vector<std::string> kinds;
  std::vector<uint8_t> kindOf(n);
  for (size_t i = 0; i < n; ++i) {
    const std::string k = scene.leaves.facts(i).kind;
    auto it = std::find(kinds.begin(), kinds.end(), k);
    if (it == kinds.end()) {
      if (kinds.size() == 255) throw InputError(jsonPath, "leaf " + std::to_string(i), "more than 255 kinds of leaf");
      it = kinds.insert(kinds.end(), k);
    }
    kindOf[i] = uint8_t(it - kinds.begin());
    const LeafFacts f = scene.leaves.facts(i);
    if (f.timeSamples > 65535) throw InputError(jsonPath, "leaf " + std::to_string(i), "more than 65535 time samples");
  }
  nlohmann::json doc = parseJsonDocument(withoutByteOrderMark(jsonText), jsonPath);
  doc["shapes"] = nlohmann::json::array();  // compiled: the leaves
  nlohmann::json sceneSection = {{"source", std::filesystem::absolute(jsonPath).lexically_normal().string()},
                                 {"text", doc.dump()},
                                 {"kinds", kinds},
                                 {"leaves", n},
                                 {"uv_sets_dropped", scene.uvSetsDropped},
                                 // The leaves are in the render frame of this origin (RenderFrame);
                                 // the load checks that the text's camera gives the same one.
                                 {"frame_origin", {scene.frame.origin.x, scene.frame.origin.y, scene.frame.origin.z}}};

  // The Meshes section, built first (its index goes into the Scene section): each topology's
  // record, then each mesh's control points.
  std::vector<uint8_t> meshBytes;
  nlohmann::json topologies = nlohmann::json::array(), meshes = nlohmann::json::array(),
                 heightMaps = nlohmann::json::array();
  for (const SubdivTopology* t : shared.topologies()) {
    const size_t at = meshBytes.size();
    encodeSubdivTopology(*t, meshBytes);
    topologies.push_back({at, meshBytes.size() - at});
  }
  for (size_t k = 0; k < shared.meshes().size(); ++k) {
    const std::vector<Vec3> points = shared.meshes()[k]->controlPoints();
    const size_t at = meshBytes.size();
    meshBytes.resize(at + points.size() * sizeof(Vec3));
    if (!points.empty()) std::memcpy(meshBytes.data() + at, points.data(), points.size() * sizeof(Vec3));
    meshes.push_back({shared.topologyOfMesh(uint32_t(k)), at, points.size() * sizeof(Vec3)});
  }
  for (const HeightMapDisplacement* d : shared.heightMaps())
    heightMaps.push_back({{"file", d->origin().file}, {"channel", d->origin().channel},
                          {"amplitude", d->amplitude()}, {"offset", d->offset()}});
  sceneSection["topologies"] = topologies;
  sceneSection["meshes"] = meshes;
  sceneSection["height_maps"] = heightMaps;
  nlohmann::json forests = nlohmann::json::array();
  for (uint64_t k = 0, at = 0; k < shared.forests().size(); ++k) {
    const uint64_t bytes = forestBytes(*shared.forests()[k]);
    forests.push_back({at, bytes});
    at += (bytes + kForestAlign - 1) / kForestAlign * kForestAlign;
  }
  sceneSection["forests"] = forests;

  CompiledFileWriter w(outPath, programVersion());
  const std::string sceneText = sceneSection.dump();
  w.beginSection(SectionKind::Scene);
  w.write(sceneText.data(), sceneText.size());
  w.beginSection(SectionKind::Materials);
  w.write(scene.leafMaterial.data(), n * sizeof(uint32_t));

  // Records, a chunk of leaves at a time: encoded in parallel, written in leaf order.
  w.beginSection(SectionKind::Records);
  std::vector<uint64_t> offset(n + 1, 0);
  std::vector<std::vector<uint8_t>> records;
  std::vector<std::string> failures;
  for (size_t c0 = 0; c0 < n; c0 += kChunkLeaves) {
    const size_t c1 = std::min(n, c0 + kChunkLeaves);
    records.assign(c1 - c0, {});
    failures.assign(c1 - c0, {});
    tbb::parallel_for(c0, c1, [&](size_t i) {
      if (const auto [forest, k] = forestOf(scene, i); forest) {
        encodeForestLeaf(shared.forestIndex(forest), forest->leaf(k), records[i - c0]);
        return;
      }
      const PatchPtr p = scene.leaves.patch(i);
      failures[i - c0] = encodePatch(*p, records[i - c0], &shared);
    });
    for (size_t i = c0; i < c1; ++i) {
      if (!failures[i - c0].empty())
        throw InputError(jsonPath, "leaf " + std::to_string(i),
                         "cannot be compiled: " + failures[i - c0] +
                             " (compiled scenes hold Bézier, bilinear and subdivision patches, noise and height-map "
                             "displacement and motion)");
      offset[i] = w.sectionBytes();
      w.write(records[i - c0].data(), records[i - c0].size());
    }
    offset[c1] = w.sectionBytes();
    if (progress) progress(c1, n);
  }

  w.beginSection(SectionKind::Leaves);
  writeRows<LeafEntry>(w, n, [&](size_t i) { return entryOf(scene, i, kindOf[i], offset[i], uint32_t(offset[i + 1] - offset[i])); });
  if (!meshBytes.empty()) {
    w.beginSection(SectionKind::Meshes);
    w.write(meshBytes.data(), meshBytes.size());
  }
  if (scene.uvs) writeUvSets(*scene.uvs, n, shared, w);
  if (!shared.forests().empty()) writeForests(shared.forests(), w);
  w.beginSection(SectionKind::TopLevel);
  compiled::TopLevelHeader th;
  th.nodeCount = top.nodeCount;
  th.leafCount = top.leafCount;
  th.root = top.root;
  th.nodeBytes = top.nodeBytes;
  w.write(&th, sizeof th);
  w.write(top.nodes, top.nodeCount * top.nodeBytes);
  w.beginSection(SectionKind::LeafBoxes);
  w.write(top.leafBoxes, top.leafCount * sizeof(Box3));
  writeLeafShading(scene, w);
  w.finish();
}

namespace {

// The topologies and meshes the Scene section indexes, built from the Meshes section.
void loadMeshes(const MappedFile& file, const nlohmann::json& section, RecordTables& tables,
                std::vector<std::shared_ptr<const SubdivTopology>>& topologies) {
  const std::string& path = file.path();
  const nlohmann::json& ts = section.at("topologies");
  const nlohmann::json& ms = section.at("meshes");
  if ((!ts.empty() || !ms.empty()) && !file.has(SectionKind::Meshes))
    throw InputError(path, "header", "no meshes section, while the scene section names " + std::to_string(ms.size()) + " meshes");
  std::vector<uint8_t> bytes;
  for (size_t k = 0; k < ts.size(); ++k) {
    const uint64_t at = ts[k].at(0).get<uint64_t>(), n = ts[k].at(1).get<uint64_t>();
    bytes.resize(n);
    file.read(SectionKind::Meshes, at, n, bytes.data(), "topology", k);
    try {
      topologies.push_back(decodeSubdivTopology(bytes.data(), n));
    } catch (const std::invalid_argument& e) {
      throw InputError(path, "section meshes (topology " + std::to_string(k) + ")", std::string("does not decode: ") + e.what());
    }
  }
  for (size_t k = 0; k < ms.size(); ++k) {
    const uint64_t t = ms[k].at(0).get<uint64_t>(), at = ms[k].at(1).get<uint64_t>(), n = ms[k].at(2).get<uint64_t>();
    const std::string place = "section meshes (mesh " + std::to_string(k) + ")";
    if (t >= topologies.size() || n % sizeof(Vec3) != 0)
      throw InputError(path, place, "names topology " + std::to_string(t) + " of " + std::to_string(topologies.size()) +
                                        " with " + std::to_string(n) + " bytes of points: the file is corrupt");
    std::vector<Vec3> points(n / sizeof(Vec3));
    file.read(SectionKind::Meshes, at, n, points.data(), "mesh", k);
    try {
      tables.meshes.push_back(SubdivMesh::build(topologies[t], std::move(points)));
    } catch (const std::invalid_argument& e) {
      throw InputError(path, place, std::string("does not build: ") + e.what());
    }
  }
}

// The forests the Scene section names: each one's parameters read from its header, its tables
// read in place through the mapping (`file` keeps it) by the ForestPatches that makes its leaves.
void loadForests(const std::shared_ptr<const MappedFile>& file, const nlohmann::json& section, RecordTables& tables) {
  const std::string& path = file->path();
  const nlohmann::json& fs = section.at("forests");
  if (fs.empty()) return;
  if (!file->has(SectionKind::Forests))
    throw InputError(path, "header", "no forests section, while the scene section names " + std::to_string(fs.size()) + " forests");
  const uint64_t sectionBytes = file->sectionBytes(SectionKind::Forests);
  const MappedFile::GatedSection g = file->gated(SectionKind::Forests);
  for (size_t k = 0; k < fs.size(); ++k) {
    const std::string place = "section forests (forest " + std::to_string(k) + ")";
    const uint64_t at = fs[k].at(0).get<uint64_t>(), bytes = fs[k].at(1).get<uint64_t>();
    compiled::ForestHeader h;
    if (at % kForestAlign != 0 || bytes < sizeof h)
      throw InputError(path, place, "at byte " + std::to_string(at) + " with " + std::to_string(bytes) + " bytes: the file is corrupt");
    file->read(SectionKind::Forests, at, sizeof h, &h, "forest", k);
    // Counts checked by division first: a corrupt count must not wrap the product.
    const uint64_t tableBytes = bytes - sizeof h;
    if (h.branchCount > tableBytes / sizeof(ForestBranch) || h.foliageCount > tableBytes / sizeof(ForestFoliage) ||
        h.branchCount * sizeof(ForestBranch) + h.foliageCount * sizeof(ForestFoliage) != tableBytes || at > sectionBytes ||
        bytes > sectionBytes - at)
      throw InputError(path, place, std::to_string(h.branchCount) + " branches and " + std::to_string(h.foliageCount) +
                                        " foliage leaves do not fill its " + std::to_string(bytes) + " bytes at byte " +
                                        std::to_string(at) + " of a section of " + std::to_string(sectionBytes) +
                                        ": the file is truncated or corrupt");
    ForestParams p;
    p.seed = h.seed;
    p.trees = h.trees;
    p.detail = h.detail;
    p.branching = h.branching;
    p.terrainTiles = h.terrainTiles;
    p.leavesPerTwig = h.leavesPerTwig;
    p.area = h.area;
    p.treeHeight = h.treeHeight;
    p.terrainAmplitude = h.terrainAmplitude;
    std::memcpy(p.placement.m, h.placement, sizeof h.placement);
    const uint64_t branchesAt = at + sizeof h, foliageAt = branchesAt + h.branchCount * sizeof(ForestBranch);
    try {
      tables.forests.push_back(std::make_shared<const ForestPatches>(
          p, GatedSpan<ForestBranch>(reinterpret_cast<const ForestBranch*>(g.data + branchesAt), h.branchCount, g.gate, branchesAt),
          GatedSpan<ForestFoliage>(reinterpret_cast<const ForestFoliage*>(g.data + foliageAt), h.foliageCount, g.gate, foliageAt),
          file));
    } catch (const std::invalid_argument& e) {
      throw InputError(path, place, std::string("its parameters are refused: ") + e.what());
    }
  }
}

// The height maps the Scene section names, opened as the JSON route opens them (relative to
// the source scene's folder) into the scene's texture cache.
void loadHeightMaps(const std::string& path, const nlohmann::json& section, const std::string& source, Scene& scene,
                    RecordTables& tables) {
  const nlohmann::json& hs = section.at("height_maps");
  const std::filesystem::path dir = std::filesystem::path(source).parent_path();
  for (size_t k = 0; k < hs.size(); ++k) {
    const std::string place = "section scene (height map " + std::to_string(k) + ")";
    const std::string f = hs[k].at("file").get<std::string>();
    std::string channel = hs[k].at("channel").get<std::string>();
    const float amplitude = hs[k].at("amplitude").get<float>(), offset = hs[k].at("offset").get<float>();
    const std::filesystem::path fp = std::filesystem::path(f).is_absolute() ? std::filesystem::path(f) : dir / f;
    if (!std::filesystem::is_regular_file(fp)) throw InputError(path, place, "cannot open height map '" + fp.string() + "'");
    auto map = openHeightMap(fp, channel, scene, [&](const char*, const std::string& why) { throw InputError(path, place, why); });
    try {
      tables.heightMaps.push_back(std::make_shared<const HeightMapDisplacement>(std::move(map), amplitude, offset,
                                                                                HeightMapOrigin{f, channel}));
    } catch (const std::invalid_argument& e) {
      throw InputError(path, place, e.what());
    }
  }
}

}  // namespace

Scene loadCompiledScene(const std::string& path, uint64_t residentBudget, const TextureCacheOptions& textures) {
  auto file = std::make_shared<const MappedFile>(path, residentBudget);
  for (SectionKind k : {SectionKind::Scene, SectionKind::Materials, SectionKind::Leaves, SectionKind::Records,
                        SectionKind::TopLevel, SectionKind::LeafBoxes, SectionKind::LeafShading})
    if (!file->has(k)) throw InputError(path, "header", std::string("no ") + compiled::sectionName(k) + " section");
  const uint64_t sceneBytes = file->sectionBytes(SectionKind::Scene);
  std::string sceneText(sceneBytes, '\0');
  file->read(SectionKind::Scene, 0, sceneBytes, sceneText.data());
  nlohmann::json section;
  std::string text, source;
  std::vector<std::string> kinds;
  size_t leafCount = 0;
  auto tables = std::make_shared<RecordTables>();
  std::vector<std::shared_ptr<const SubdivTopology>> topologies;
  try {
    section = nlohmann::json::parse(sceneText);
    text = section.at("text").get<std::string>();
    source = section.at("source").get<std::string>();
    kinds = section.at("kinds").get<std::vector<std::string>>();
    leafCount = section.at("leaves").get<size_t>();
    loadMeshes(*file, section, *tables, topologies);
    loadForests(file, section, *tables);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, "section scene", std::string("not the scene's JSON: ") + e.what());
  }
  auto leaves = std::make_shared<const MappedLeaves>(file, std::move(kinds), tables);
  const size_t n = leaves->size();
  if (n != leafCount)
    throw InputError(path, "section leaves", std::to_string(n) + " leaf entries, while the scene section says " +
                                                 std::to_string(leafCount) + ": the file is corrupt");
  if (file->sectionBytes(SectionKind::Materials) != n * sizeof(uint32_t))
    throw InputError(path, "section materials", "not one material per leaf of the leaf table");
  std::vector<uint32_t> material(n);
  for (uint64_t at = 0; at < n * sizeof(uint32_t); at += compiled::kBlockBytes)
    file->read(SectionKind::Materials, at, std::min<uint64_t>(compiled::kBlockBytes, n * sizeof(uint32_t) - at),
               reinterpret_cast<uint8_t*>(material.data()) + at);
  // The text is parsed as its source was (relative file names resolve against the source's
  // folder); messages then name the .rayes.
  Scene scene = parseSceneWithShapes(text, source, std::move(leaves), std::move(material), textures);
  scene.path = path;
  try {
    // Height maps go into the scene's texture cache, made by the parse; no patch() was asked
    // for before this.
    loadHeightMaps(path, section, source, scene, *tables);
    scene.uvSetsDropped = section.at("uv_sets_dropped").get<bool>();
    // The records were placed relative to the camera the text names; a text whose camera lies
    // elsewhere would put the lights and the camera in another frame than the leaves.
    const auto origin = section.at("frame_origin").get<std::array<double, 3>>();
    if (Vec3d{origin[0], origin[1], origin[2]} != scene.frame.origin)
      throw InputError(path, "section scene", "the leaves were compiled in the render frame of a camera at (" +
                                                  std::to_string(origin[0]) + ", " + std::to_string(origin[1]) + ", " +
                                                  std::to_string(origin[2]) + "), not the scene's camera: the file is corrupt");
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, "section scene", std::string("not the scene's JSON: ") + e.what());
  }
  if (file->has(SectionKind::UvSets)) {
    std::vector<std::shared_ptr<const SubdivUvSet>> sets;
    for (const auto& t : topologies) sets.push_back(hasUvSet(*t) ? std::make_shared<const SubdivUvSet>(t) : nullptr);
    scene.uvs = LeafUvTable::mapped(file, n, std::move(sets));
  }
  scene.compiled = std::move(file);
  return scene;
}

}  // namespace rayes
