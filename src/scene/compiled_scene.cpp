#include "scene/compiled_scene.h"
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <tbb/parallel_for.h>
#include "core/error.h"
#include "core/version.h"
#include "geometry/mapped_leaves.h"
#include "geometry/patch_record.h"
#include "scene/json_document.h"
#include "scene/scene_loader.h"

namespace rayes {

using compiled::LeafEntry;
using compiled::SectionKind;

namespace {

// Leaves encoded at a time: their records are held in memory until written.
constexpr size_t kChunkLeaves = size_t(1) << 16;

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

}  // namespace

bool isCompiledSceneName(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".rayes";
}

void writeCompiledScene(const Scene& scene, const std::string& jsonText, const std::string& jsonPath,
                        const std::string& outPath, const std::function<void(size_t, size_t)>& progress) {
  const size_t n = scene.shapeLeaves;
  // Uv sets have no section in format version 1: refused rather than dropped, which would turn
  // a uv-mapped texture into one over the patch parameters.
  if (scene.uvs)
    throw InputError(jsonPath, "/shapes", "uv sets cannot be compiled yet (format version 1 has no uv section); render the JSON scene");
  // Nor have volumes: refused rather than rendered without their media.
  if (!scene.media.empty())
    throw InputError(jsonPath, "/shapes", "volumes cannot be compiled yet (format version 1 has no volume section); render the JSON scene");
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
  const nlohmann::json sceneSection = {{"source", std::filesystem::absolute(jsonPath).lexically_normal().string()},
                                       {"text", doc.dump()},
                                       {"kinds", kinds},
                                       {"leaves", n}};

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
      const PatchPtr p = scene.leaves.patch(i);
      failures[i - c0] = encodePatch(*p, records[i - c0]);
    });
    for (size_t i = c0; i < c1; ++i) {
      if (!failures[i - c0].empty())
        throw InputError(jsonPath, "leaf " + std::to_string(i),
                         "cannot be compiled: " + failures[i - c0] +
                             " (compiled scenes hold Bézier and bilinear patches, noise displacement and motion)");
      offset[i] = w.sectionBytes();
      w.write(records[i - c0].data(), records[i - c0].size());
    }
    offset[c1] = w.sectionBytes();
    if (progress) progress(c1, n);
  }

  w.beginSection(SectionKind::Leaves);
  std::vector<LeafEntry> entries;
  for (size_t c0 = 0; c0 < n; c0 += kChunkLeaves) {
    const size_t c1 = std::min(n, c0 + kChunkLeaves);
    entries.resize(c1 - c0);
    tbb::parallel_for(c0, c1, [&](size_t i) {
      entries[i - c0] = entryOf(scene, i, kindOf[i], offset[i], uint32_t(offset[i + 1] - offset[i]));
    });
    w.write(entries.data(), entries.size() * sizeof(LeafEntry));
  }
  w.finish();
}

Scene loadCompiledScene(const std::string& path, uint64_t residentBudget, const TextureCacheOptions& textures) {
  auto file = std::make_shared<const MappedFile>(path, residentBudget);
  for (SectionKind k : {SectionKind::Scene, SectionKind::Materials, SectionKind::Leaves, SectionKind::Records})
    if (!file->has(k)) throw InputError(path, "header", std::string("no ") + compiled::sectionName(k) + " section");
  const uint64_t sceneBytes = file->sectionBytes(SectionKind::Scene);
  std::string sceneText(sceneBytes, '\0');
  file->read(SectionKind::Scene, 0, sceneBytes, sceneText.data());
  nlohmann::json section;
  std::string text, source;
  std::vector<std::string> kinds;
  try {
    section = nlohmann::json::parse(sceneText);
    text = section.at("text").get<std::string>();
    source = section.at("source").get<std::string>();
    kinds = section.at("kinds").get<std::vector<std::string>>();
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, "section scene", std::string("not the scene's JSON: ") + e.what());
  }
  auto leaves = std::make_shared<const MappedLeaves>(file, std::move(kinds));
  const size_t n = leaves->size();
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
  scene.compiled = std::move(file);
  return scene;
}

}  // namespace rayes
