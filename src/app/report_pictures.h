// The pictures of a report page (docs/dashboard.md, "Where on the image"): the beauty image
// beside false-colour heat maps of the per-pixel layers (the level of detail at the first hit,
// dicings charged to the pixel, time per pixel; --cost-layers, app/pixel_cost.h), each with a
// legend and a read-out of the value under the cursor. The values go into the page as base64
// float32 (little-endian), drawn on canvases by the page's script, so the read-out shows the
// layer's own number. Pure: the same layers give the same section.
#pragma once
#include <optional>
#include <string>
#include <vector>
#include "app/report_stats_file.h"

namespace rayes {

struct CostPictures {
  int width = 0, height = 0;
  std::vector<float> rgba;                   // the beauty, 4 per pixel (alpha: coverage)
  std::vector<float> lod, dicings, seconds;  // one per pixel; empty: the layer is absent
  std::string source;                        // where they came from, named on the page
};

// The most pixels a page embeds (4 Mpixel: 16 MiB of values per layer); beyond, the section
// says so and draws nothing.
inline constexpr uint64_t kMaxPicturePixels = uint64_t(1) << 22;

// The layers of the image a stats file names (`cost_layers.image`, relative to the stats file's
// folder). None, with `note` saying why, when the stats name no image or it cannot be read: the
// page is still drawn from the stats.
std::optional<CostPictures> picturesOfStats(const StatsFile& f, std::string& note);

// The section: the beauty and one heat map per present layer.
std::string picturesSection(const CostPictures& p);

}  // namespace rayes
