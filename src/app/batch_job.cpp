#include "app/batch_job.h"
#include <algorithm>
#include "scene/compiled_scene.h"
#include <cstdio>
#include <fstream>
#include <iterator>
#include <set>
#include <zlib.h>
#include "core/version.h"
#include "core/error.h"

namespace rayes {
namespace {

std::string windowText(const PixelWindow& w) {
  return std::to_string(w.x0) + "," + std::to_string(w.y0) + "," + std::to_string(w.x1) + "," + std::to_string(w.y1);
}

// 64-bit FNV-1a: not cryptographic, only to tell renders apart (with crc32 beside it).
uint64_t fnv1a(const std::string& bytes, uint64_t h = 0xcbf29ce484222325ull) {
  for (unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ull;
  return h;
}

}  // namespace

nlohmann::json imageSettings(const Scene& scene, const RenderOptions& options) {
  const MethodOptions& m = options.method;
  const char* lod = options.lod == LodRule::PerRay ? "per-ray" : options.lod == LodRule::Density ? "density" : "fixed";
  return {{"resolution", std::to_string(scene.width) + "x" + std::to_string(scene.height)},
          {"spp", scene.samplesPerPixel},
          {"seed", scene.integrator.seed},
          {"method", m.name},
          {"caustic_paths", causticPathsName(m.causticPaths)},
          {"later_gathers", m.laterGatherProbability},
          {"photons", m.photons.photonsPerSample},
          {"photon_k", m.photons.neighbours},
          {"photon_radius", m.photons.radius},
          {"photon_alpha", m.photons.alpha},
          {"beam_resolution", m.beams.resolution},
          {"beam_depth", m.beams.maxDepth},
          {"beam_split_depth", m.beams.splitDepth},
          {"beam_area_samples", m.beams.areaSamples},
          {"beam_memory", m.beams.memoryBytes},
          {"beam_lobe_cells", m.beams.lobeCells},
          {"max_lod", options.maxLod},
          {"lod", lod},
          {"lod_bias", options.lodBias},
          {"engine", options.engine == EngineKind::Embree ? "embree" : "rayes"},
          {"embree_lod", options.embreeAutoLod ? "auto" : "fixed"},
          {"progressive", options.progressive}};
}

std::string fingerprintOf(const std::string& scenePath, const nlohmann::json& settings) {
  std::ifstream in(scenePath, std::ios::binary);
  if (!in) throw InputError(scenePath, "", "cannot read the scene file");
  // A compiled scene is named by its header block: its CRC covers the section table and the
  // CRC of every block's CRC, so it stands for the whole file without reading gigabytes.
  std::string bytes;
  if (isCompiledSceneName(scenePath)) {
    bytes.resize(compiled::kBlockBytes);
    in.read(bytes.data(), std::streamsize(bytes.size()));
    bytes.resize(size_t(in.gcount()));
  } else {
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const std::string text = settings.dump() + '\0' + bytes;
  const uint32_t crc = uint32_t(crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(text.data()), uInt(text.size())));
  char hex[32];
  std::snprintf(hex, sizeof hex, "%016llx%08x", (unsigned long long)fnv1a(text), crc);
  return hex;
}

FilmFileHeader filmHeader(const std::string& kind, const std::string& scenePath, const Scene& scene,
                          const RenderOptions& options, const Renderer& renderer) {
  FilmFileHeader h;
  h.kind = kind;
  h.programVersion = programVersion();
  h.settings = imageSettings(scene, options);
  h.fingerprint = fingerprintOf(scenePath, h.settings);
  h.scene = scenePath;
  h.width = scene.width;
  h.height = scene.height;
  h.crop = options.crop.empty() ? PixelWindow::whole(scene.width, scene.height) : options.crop;
  h.window = renderer.filmWindow();
  h.part = options.part;
  h.parts = options.parts;
  h.method = options.method.name;
  h.lightPathIds = renderer.integrator().traits().lightPathIds;
  h.stats = nullptr;
  return h;
}

void checkSameRender(const std::string& path, const FilmFileHeader& found, const FilmFileHeader& expected,
                     const std::string& use, const std::string& expectedName) {
  const std::string there = " in it, ", here = " in " + expectedName;
  auto refuse = [&](const std::string& why) { throw InputError(path, "", "cannot " + use + " it: " + why); };
  if (found.programVersion != expected.programVersion)
    refuse("written by rayes " + found.programVersion + ", " + expectedName + " by rayes " + expected.programVersion +
           " (its pixels may differ)");
  if (found.fingerprint != expected.fingerprint) {
    std::string differ;
    for (const auto& [key, value] : expected.settings.items())
      if (!found.settings.contains(key) || found.settings[key] != value)
        differ += (differ.empty() ? "" : "; ") + key + " " +
                  (found.settings.contains(key) ? found.settings[key].dump() : "(none)") + there + value.dump() + here;
    refuse(differ.empty() ? "rendered from another scene file (" + found.scene + "; its bytes differ)"
                          : "rendered with other settings: " + differ);
  }
  if (found.width != expected.width || found.height != expected.height)
    refuse("an image of " + std::to_string(found.width) + "x" + std::to_string(found.height) + there +
           std::to_string(expected.width) + "x" + std::to_string(expected.height) + here);
  if (!(found.crop == expected.crop)) refuse("another crop: " + windowText(found.crop) + there + windowText(expected.crop) + here);
  if (found.parts != expected.parts || found.part != expected.part)
    refuse("part " + std::to_string(found.part) + "/" + std::to_string(found.parts) + there + std::to_string(expected.part) +
           "/" + std::to_string(expected.parts) + here);
  if (found.method != expected.method) refuse("method " + found.method + there + expected.method + here);
  if (!(found.window == expected.window)) refuse("another window of the image (" + windowText(found.window) + ")");
}

namespace {

enum class Rule { Sum, Max, Min, First };

// How one stats field of several parts combines; `path` is its place ("totals.rays").
Rule ruleFor(const std::string& path) {
  static const std::set<std::string> summedFeatures = {"features.moving_dicings", "features.border_region_hits"};
  static const std::set<std::string> maxTotals = {"totals.peak_rss_bytes", "totals.photon_map_bytes",
                                                  "totals.pixels_per_block", "totals.micropolygons_potential"};
  static const std::set<std::string> beamMax = {"beams.bytes", "beams.peak_bytes", "beams.generations",
                                                "beams.resolution", "beams.requested_resolution", "beams.lobe_cells",
                                                "beams.max_depth", "beams.split_depth", "beams.memory_budget_bytes",
                                                "beams.batches"};
  auto starts = [&](const char* p) { return path.rfind(p, 0) == 0; };
  if (path == "stats_version" || starts("scene.") || starts("settings.") || starts("skipped.")) return Rule::First;
  if (starts("features.")) return summedFeatures.count(path) ? Rule::Sum : Rule::First;
  if (starts("memory.")) return Rule::Max;
  if (starts("totals.")) return maxTotals.count(path) ? Rule::Max : Rule::Sum;
  if (starts("engine.")) {
    if (path == "engine.min_level") return Rule::Min;
    if (path == "engine.cache_hits" || path == "engine.cache_misses" || starts("engine.time_s.")) return Rule::Sum;
    return Rule::Max;
  }
  if (starts("beams.")) return beamMax.count(path) ? Rule::Max : Rule::Sum;
  if (starts("textures.")) {
    // Every part opens the same files under the same bound; each is its own cache.
    if (path == "textures.files" || path == "textures.image_bytes" || path == "textures.texture_memory_bytes")
      return Rule::First;
    if (path == "textures.peak_tiles" || path == "textures.cache_memory_bytes") return Rule::Max;
    return Rule::Sum;
  }
  return Rule::Sum;
}

void combineInto(nlohmann::json& into, const nlohmann::json& more, const std::string& path) {
  if (into.is_object() && more.is_object()) {
    for (const auto& [key, value] : more.items()) {
      const std::string at = path.empty() ? key : path + "." + key;
      if (!into.contains(key)) into[key] = value;
      else combineInto(into[key], value, at);
    }
    return;
  }
  if (!into.is_number() || !more.is_number()) {
    if (into.is_boolean() && more.is_boolean() && ruleFor(path) != Rule::First) into = into.get<bool>() || more.get<bool>();
    return;  // strings, arrays: the first part's
  }
  const bool integral = into.is_number_integer() && more.is_number_integer();
  auto pick = [&](auto a, auto b) -> nlohmann::json {
    switch (ruleFor(path)) {
      case Rule::Sum: return a + b;
      case Rule::Max: return std::max(a, b);
      case Rule::Min: return std::min(a, b);
      case Rule::First: return a;
    }
    return a;
  };
  if (integral && into.is_number_unsigned() && more.is_number_unsigned()) into = pick(into.get<uint64_t>(), more.get<uint64_t>());
  else if (integral) into = pick(into.get<int64_t>(), more.get<int64_t>());
  else into = pick(into.get<double>(), more.get<double>());
}

}  // namespace

nlohmann::json combinedStats(const std::vector<nlohmann::json>& parts) {
  nlohmann::json out = nlohmann::json::object();
  nlohmann::json generations = nlohmann::json::array();
  for (size_t i = 0; i < parts.size(); ++i) {
    nlohmann::json p = parts[i];
    if (!p.is_object()) continue;
    if (p.contains("generations"))
      for (auto g : p["generations"]) {
        g["part"] = i + 1;
        generations.push_back(std::move(g));
      }
    p.erase("generations");
    p.erase("error_vs_time");  // a part's error against its own pixels: not the image's
    p.erase("memory_over_time");  // a part's own process over its own time: each part's page has it
    if (out.empty()) out = std::move(p);
    else combineInto(out, p, "");
  }
  out["generations"] = generations;
  // Ratios again from the combined counts.
  if (out.contains("totals")) {
    nlohmann::json& t = out["totals"];
    const double rays = t.value("rays", 0.0), diced = t.value("leaves_diced", 0.0);
    t["rays_per_dicing"] = diced > 0 ? rays / diced : 0.0;
    const double total = t.contains("time_s") ? t["time_s"].value("total", 0.0) : 0.0;
    t["mrays_per_s"] = total > 0 ? rays / total * 1e-6 : 0.0;
  }
  if (out.contains("textures")) {
    nlohmann::json& x = out["textures"];
    const double read = x.value("tiles_read", 0.0), lookups = x.value("tile_lookups", 0.0);
    x["hit_rate"] = lookups > 0 ? 1.0 - std::min(read, lookups) / lookups : 1.0;
  }
  out["parts"] = parts.size();
  return out;
}

}  // namespace rayes
