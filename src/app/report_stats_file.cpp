#include "app/report_stats_file.h"
#include <cctype>
#include <filesystem>
#include "app/film_file.h"
#include "app/stats_json.h"
#include "core/error.h"
#include "core/text_file.h"

namespace rayes {
namespace {
using json = nlohmann::json;

enum class Kind { Number, String, Object, Array, Count };

struct Field {
  const char* pointer;
  Kind kind;
};

// What the pages read without a guard; optional sections (beams, textures, error_vs_time,
// engine's extras) are checked where they are present.
const Field kRequired[] = {
    {"/scene/file", Kind::String},           {"/scene/resolution", Kind::Array},
    {"/scene/spp", Kind::Count},             {"/scene/leaves", Kind::Count},
    {"/scene/leaf_kinds", Kind::Object},     {"/settings/threads", Kind::Count},
    {"/settings/method", Kind::String},      {"/settings/max_lod", Kind::Count},
    {"/settings/program_version", Kind::String}, {"/generations", Kind::Array},
    {"/totals/rays", Kind::Count},           {"/totals/shadow_rays", Kind::Count},
    {"/totals/leaves_diced", Kind::Count},   {"/totals/micropolygons_created", Kind::Count},
    {"/totals/grid_cache_hits", Kind::Count}, {"/totals/dicings_by_level", Kind::Object},
    {"/totals/peak_rss_bytes", Kind::Count}, {"/totals/rays_per_dicing", Kind::Number},
    {"/totals/time_s", Kind::Object},        {"/memory/by_owner", Kind::Object},
    {"/features", Kind::Object},             {"/skipped", Kind::Object},
};

const char* kTimes[] = {"load", "setup", "toplevel", "sort", "dice", "bottom", "leaf_queries", "shade", "shade_sort", "film", "total", "wall"};
const char* kGenerationCounts[] = {"pass", "batch", "depth", "rays", "shadow_rays", "leaves_diced", "grid_cache_hits",
                                   "micropolygons_created"};

const char* kindName(Kind k) {
  switch (k) {
    case Kind::Number: return "a number";
    case Kind::String: return "a string";
    case Kind::Object: return "an object";
    case Kind::Array: return "an array";
    case Kind::Count: return "a count (an integer of at least 0)";
  }
  return "";
}

bool isKind(const json& v, Kind k) {
  switch (k) {
    case Kind::Number: return v.is_number();
    case Kind::String: return v.is_string();
    case Kind::Object: return v.is_object();
    case Kind::Array: return v.is_array();
    case Kind::Count: return v.is_number_unsigned() || (v.is_number_integer() && v.get<int64_t>() >= 0);
  }
  return false;
}

void need(const json& root, const std::string& pointer, Kind kind, const std::string& path) {
  const json::json_pointer p(pointer);
  if (!root.contains(p)) throw InputError(path, pointer, "missing: a rayes stats file has it (docs/stats.md)");
  if (!isKind(root[p], kind)) throw InputError(path, pointer, std::string("must be ") + kindName(kind));
}

}  // namespace

void checkStats(const json& s, const std::string& path) {
  if (!s.is_object()) throw InputError(path, "", "not a rayes stats file: the JSON is not an object");
  if (!s.contains("stats_version"))
    throw InputError(path, "/stats_version", "missing: not a rayes stats file, or one written before stats version " +
                                                 std::to_string(kStatsVersion) + " (render it again)");
  if (!s["stats_version"].is_number_integer() || s["stats_version"].get<int64_t>() != kStatsVersion)
    throw InputError(path, "/stats_version", "stats version " + s["stats_version"].dump() + ", this rayes reads version " +
                                                 std::to_string(kStatsVersion) + " (render it again with this rayes)");
  for (const Field& f : kRequired) need(s, f.pointer, f.kind, path);
  if (s["scene"]["resolution"].size() != 2)
    throw InputError(path, "/scene/resolution", "must be [width, height]");
  for (int i = 0; i < 2; ++i) need(s, "/scene/resolution/" + std::to_string(i), Kind::Count, path);
  for (const char* t : kTimes) need(s, std::string("/totals/time_s/") + t, Kind::Number, path);
  for (const auto& [owner, v] : s["memory"]["by_owner"].items()) need(s, "/memory/by_owner/" + owner, Kind::Count, path);
  for (const auto& [level, v] : s["totals"]["dicings_by_level"].items()) {
    const std::string at = "/totals/dicings_by_level/" + level;
    if (level.empty() || level.size() > 2 || level.find_first_not_of("0123456789") != std::string::npos)
      throw InputError(path, at, "must be a level of detail (0 to 99)");
    need(s, at, Kind::Count, path);
  }
  for (size_t g = 0; g < s["generations"].size(); ++g) {
    const std::string at = "/generations/" + std::to_string(g);
    need(s, at, Kind::Object, path);
    for (const char* k : kGenerationCounts) need(s, at + "/" + k, Kind::Count, path);
    need(s, at + "/iterations", Kind::Array, path);
    for (size_t i = 0; i < s["generations"][g]["iterations"].size(); ++i) {
      const std::string it = at + "/iterations/" + std::to_string(i);
      need(s, it + "/active_rays", Kind::Count, path);
      need(s, it + "/candidates_per_ray", Kind::Number, path);
    }
  }
  if (s.contains("error_vs_time")) {
    need(s, "/error_vs_time", Kind::Array, path);
    for (size_t i = 0; i < s["error_vs_time"].size(); ++i) {
      const std::string at = "/error_vs_time/" + std::to_string(i);
      need(s, at + "/spp", Kind::Count, path);
      need(s, at + "/time_s", Kind::Number, path);
      need(s, at + "/rmse", Kind::Number, path);
    }
  }
  for (const char* section : {"beams", "textures", "engine"})
    if (s.contains(section)) need(s, std::string("/") + section, Kind::Object, path);
}

StatsFile readStatsFile(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".film") {
    // A part, or a complete render's film: its header holds the run's stats.
    const FilmFileHeader h = readFilmFileHeader(path);
    if (!h.stats.is_object())
      throw InputError(path, "", "a " + h.kind + " film without statistics (a checkpoint has none): give a finished part or its stats file");
    StatsFile f{path, h.stats};
    checkStats(f.stats, path);
    return f;
  }
  const std::string text = readTextFile(path, "the stats file");
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    throw InputError(path, "", "the stats file is empty (was its render stopped before it wrote it?)");
  StatsFile f{path, {}};
  try {
    f.stats = json::parse(text);
  } catch (const json::parse_error& e) {
    throw InputError(path, "byte " + std::to_string(e.byte), std::string("not JSON: ") + e.what());
  }
  checkStats(f.stats, path);
  return f;
}

void checkComparable(const StatsFile& a, const StatsFile& b) {
  const auto name = [](const StatsFile& f) {
    return std::filesystem::path(f.stats["scene"]["file"].get<std::string>()).filename().string();
  };
  const std::string why = "cannot compare it with " + a.path + ": ";
  if (name(a) != name(b))
    throw InputError(b.path, "/scene/file", why + "another scene (" + name(b) + ", not " + name(a) + ")");
  if (a.stats["scene"]["leaves"] != b.stats["scene"]["leaves"])
    throw InputError(b.path, "/scene/leaves", why + "another scene: " + b.stats["scene"]["leaves"].dump() + " leaves, not " +
                                                  a.stats["scene"]["leaves"].dump());
  if (a.stats["scene"]["resolution"] != b.stats["scene"]["resolution"]) {
    const auto res = [](const json& r) { return r[0].dump() + "x" + r[1].dump(); };
    throw InputError(b.path, "/scene/resolution", why + "another resolution (" + res(b.stats["scene"]["resolution"]) +
                                                      ", not " + res(a.stats["scene"]["resolution"]) + ")");
  }
}

}  // namespace rayes
