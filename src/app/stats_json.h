// The stats file (--stats FILE.json): what the render did, where time and memory went, and
// what was left out because the scene did not need it. Field names are documented in
// docs/stats.md; the file is written with the other outputs, all or nothing (app/output_set.h).
#pragma once
#include <string>
#include <nlohmann/json.hpp>
#include "app/renderer.h"

namespace rayes {

// The stats file's format version (field `stats_version`): raised when a field changes meaning
// or place, so that `rayes report` refuses a file it would misread.
inline constexpr int kStatsVersion = 1;

struct RunInfo {
  std::string scenePath;
  int threads = 0;
  int width = 0, height = 0, spp = 0;
  double loadSeconds = 0;
  double wallSeconds = 0;  // whole program run, load to outputs
};

// With --cost-layers the caller sets `cost_layers.image` (the EXR holding them, relative to the
// stats file's folder, as `rayes report` finds it).
nlohmann::json statsToJson(const Scene& scene, const RenderOptions& options, const RenderStats& stats,
                           const RunInfo& run);

}  // namespace rayes
