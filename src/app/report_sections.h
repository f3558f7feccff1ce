// One run's sections of a report page (report_sections.cpp): what the page says about one
// stats object, shared by the single-run page, each column of a job's page, and the
// comparison's figures. Reads only fields checkStats guarantees, or guards the optional ones.
#pragma once
#include <string>
#include <nlohmann/json.hpp>

namespace rayes {

// "lbt (light beam tracing)": the method named as the page's first words say it.
std::string methodTitle(const nlohmann::json& stats);
// The one-paragraph summary: method, resolution, spp, threads, times, rays, peak memory.
std::string runSummary(const nlohmann::json& stats);
// Every chart and table of one run, in the order of docs/dashboard.md.
std::string runSections(const nlohmann::json& stats);

// Figures the job and comparison pages line up (0 when absent).
double number(const nlohmann::json& j, const char* pointer);
// The wall-clock stages (load, setup, the render's stages, outputs) and the thread-summed ones.
struct StageTime {
  std::string name;
  double seconds;
  std::string note;
};
std::vector<StageTime> wallStages(const nlohmann::json& stats);
std::vector<StageTime> threadStages(const nlohmann::json& stats);
// The last point of the error curve (0 when there is none).
double finalRmse(const nlohmann::json& stats);

}  // namespace rayes
