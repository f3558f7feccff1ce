// The stats files `rayes report` reads (docs/stats.md), checked before any page is built: a
// file that is missing, empty, not JSON, of another `stats_version`, or without a field the
// pages draw (or with one of the wrong type) is an InputError naming the file and the JSON
// pointer. After the check the page builders may read the checked fields without guarding.
#pragma once
#include <string>
#include <vector>
#include <nlohmann/json.hpp>

namespace rayes {

struct StatsFile {
  std::string path;     // as given on the command line
  nlohmann::json stats;
};

// Checks a parsed stats object; `path` only names it in the errors.
void checkStats(const nlohmann::json& stats, const std::string& path);
StatsFile readStatsFile(const std::string& path);

// Throws InputError unless the two runs are of the same scene (file name and leaf count) and
// resolution: a comparison of different images' costs would mislead. Names what differs.
void checkComparable(const StatsFile& a, const StatsFile& b);

}  // namespace rayes
