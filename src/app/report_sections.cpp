#include "app/report_sections.h"
#include <algorithm>
#include <cmath>
#include <sstream>
#include "app/report_charts.h"
#include "app/report_format.h"

namespace rayes {
namespace {
using json = nlohmann::json;

std::string generationName(const json& g) {
  std::string n = "p" + std::to_string(g["pass"].get<int>()) + " b" + std::to_string(g["batch"].get<int>()) + " d" +
                  std::to_string(g["depth"].get<int>());
  if (g.contains("part") && g["part"].is_number()) n = "part " + g["part"].dump() + " " + n;
  return n;
}

void timeSection(std::ostringstream& o, const json& s) {
  o << "<h2>Where the time went</h2><p>Two charts, never mixed: wall-clock stages add up to the run's "
    << shortNumber(number(s, "/totals/time_s/wall")) << " s; thread time is summed over "
    << s["settings"]["threads"].get<int>() << " threads, so it may exceed the wall time.</p>";
  std::vector<Bar> wall, thread;
  for (const StageTime& t : wallStages(s)) wall.push_back({t.name, t.seconds, t.note});
  for (const StageTime& t : threadStages(s)) thread.push_back({t.name, t.seconds, t.note});
  o << barChart("Wall clock (seconds)", wall, " s") << barChart("Thread time, summed over threads (seconds)", thread, " s");
  // Per generation (stats written since the per-generation times: older files lack them).
  const json& gens = s["generations"];
  bool timed = !gens.empty();
  for (const json& g : gens) timed = timed && g.contains("time_s") && g["time_s"].is_object();
  if (!timed) return;
  ColumnChart wallPer{"Wall clock per generation (seconds, stacked)", " s", {}, {{"toplevel", {}}, {"sort", {}},
                      {"dice + bottom + rest of the trace", {}}, {"shade", {}}}};
  ColumnChart threadPer{"Thread time per generation (seconds summed over threads, stacked)", " s", {},
                        {{"dice", {}}, {"bottom", {}}, {"leaf queries", {}}}};
  for (const json& g : gens) {
    const double trace = number(g, "/time_s/trace"), top = number(g, "/time_s/toplevel"), sort = number(g, "/time_s/sort");
    wallPer.categories.push_back(generationName(g));
    threadPer.categories.push_back(generationName(g));
    wallPer.series[0].values.push_back(top);
    wallPer.series[1].values.push_back(sort);
    wallPer.series[2].values.push_back(std::max(0.0, trace - top - sort));
    wallPer.series[3].values.push_back(number(g, "/time_s/shade"));
    threadPer.series[0].values.push_back(number(g, "/time_s/dice"));
    threadPer.series[1].values.push_back(number(g, "/time_s/bottom"));
    threadPer.series[2].values.push_back(number(g, "/time_s/leaf_queries"));
  }
  o << "<div id=time-per-generation><p>Per generation, the same two kinds of time kept apart: the wall clock of its trace (the top level, the "
       "sort, and the rest of the trace, where dicing and intersection run) and of its shading; and the dicing, "
       "intersection and leaf queries summed over threads.</p>"
    << columnChart(wallPer) << columnChart(threadPer) << "</div>";
}

void generationSection(std::ostringstream& o, const json& s) {
  const json& gens = s["generations"];
  o << "<h2>Generations</h2>";
  if (gens.empty()) {
    o << "<p>No generation was traced.</p>";
    return;
  }
  ColumnChart rays{"Rays per generation", "", {}, {{"continuation and camera", {}}, {"shadow", {}}}};
  ColumnChart dicings{"Dicings and grid-cache hits per generation", "", {}, {{"dicings", {}}, {"grid-cache hits", {}}}};
  ColumnChart micro{"Micropolygons created per generation", "", {}, {{"micropolygons", {}}}};
  ColumnChart perDicing{"Rays per dicing per generation", "", {}, {{"rays per dicing", {}}}};
  LineChart active{"Active rays per top-level iteration (one line per generation)", "iteration", "active rays", false, true};
  LineChart candidates{"Candidates per ray per iteration (N, the thesis's Table 6.3)", "iteration", "candidates per ray"};
  for (const json& g : gens) {
    const std::string name = generationName(g);
    const double r = g["rays"].get<double>(), sh = g["shadow_rays"].get<double>(), d = g["leaves_diced"].get<double>();
    for (ColumnChart* c : {&rays, &dicings, &micro, &perDicing}) c->categories.push_back(name);
    rays.series[0].values.push_back(r - sh);
    rays.series[1].values.push_back(sh);
    dicings.series[0].values.push_back(d);
    dicings.series[1].values.push_back(g["grid_cache_hits"].get<double>());
    micro.series[0].values.push_back(g["micropolygons_created"].get<double>());
    perDicing.series[0].values.push_back(d > 0 ? r / d : 0.0);
    Line a{name, {}}, n{name, {}};
    for (size_t i = 0; i < g["iterations"].size(); ++i) {
      a.points.push_back({double(i + 1), g["iterations"][i]["active_rays"].get<double>(), ""});
      n.points.push_back({double(i + 1), g["iterations"][i]["candidates_per_ray"].get<double>(), ""});
    }
    if (!a.points.empty()) active.lines.push_back(a), candidates.lines.push_back(n);
  }
  dicings.stacked = false;
  o << columnChart(rays);
  if (!active.lines.empty()) o << lineChart(active) << lineChart(candidates);
  if (number(s, "/totals/leaves_diced") > 0 || number(s, "/totals/grid_cache_hits") > 0)
    o << columnChart(dicings) << columnChart(micro) << columnChart(perDicing);
  else
    o << "<p>Nothing was diced on demand (" << htmlEscape(s.value("/engine/name"_json_pointer, std::string("this engine")))
      << "): no dicing charts.</p>";
}

void dicingSection(std::ostringstream& o, const json& s) {
  o << "<h2>Dicing</h2><p>" << shortCount(number(s, "/totals/leaves_diced")) << " dicings created "
    << shortCount(number(s, "/totals/micropolygons_created")) << " micropolygons (tessellating every patch at level "
    << s["settings"]["max_lod"].get<int>() << " once would create " << shortCount(number(s, "/totals/micropolygons_potential"))
    << "); " << shortNumber(number(s, "/totals/rays_per_dicing")) << " rays per dicing.</p>";
  const json& h = s["totals"]["dicings_by_level"];
  if (!h.empty()) {
    int top = 0;
    for (const auto& [level, n] : h.items()) top = std::max(top, std::stoi(level));
    ColumnChart c{"Level-of-detail histogram: dicings per level m (4^m micro-quads each)", "", {}, {{"dicings", {}}}};
    for (int m = 0; m <= top; ++m) {
      c.categories.push_back(std::to_string(m));
      const std::string k = std::to_string(m);
      c.series[0].values.push_back(h.contains(k) ? h[k].get<double>() : 0.0);
    }
    o << columnChart(c);
  }
  const double hits = number(s, "/totals/grid_cache_hits"), diced = number(s, "/totals/leaves_diced");
  if (hits > 0 || s.contains("/engine/cache_hits"_json_pointer)) {
    std::vector<Bar> b = {{"dicings", diced, "leaf visits that diced the patch"},
                          {"grid-cache hits", hits, "leaf visits served by a kept grid (--grid-cache)"}};
    if (s.contains("/engine/cache_hits"_json_pointer))
      b.push_back({"dice-cache hits", number(s, "/engine/cache_hits"), "the --dice-cache engine's hits"});
    o << barChart("Grid cache: visits served without dicing", b, "");
  }
  o << "<table><tr><th>patch kind</th><th class=num>leaves</th></tr>";
  for (const auto& [kind, n] : s["scene"]["leaf_kinds"].items())
    o << "<tr class=data><td>" << htmlEscape(kind) << "</td><td class=num>" << shortCount(n.get<double>()) << "</td></tr>";
  o << "</table>";
}

void memorySection(std::ostringstream& o, const json& s) {
  static const std::pair<const char*, const char*> owners[] = {
      {"ray_buffers", "one full batch of rays and path state (--ray-memory)"},
      {"candidates_and_sort", "candidate slots, sort scratch, trace state"},
      {"top_level", "4-wide BVH over patch boxes"},
      {"dice_buffers", "one per thread (--max-lod); 0 when every dicing went into the grid cache"},
      {"dice_cache", "grids kept between uses, at its peak (--grid-cache)"},
      {"border_bounds", "crack-closing border boxes kept between dicings"},
      {"film", "per-pixel sums (--res)"},
      {"uv_sets", "the leaves' uv sets"},
      {"scene_description", "the leaves: grows with the scene"}};
  std::vector<Bar> b;
  for (const auto& [key, note] : owners)
    if (s["memory"]["by_owner"].contains(key)) b.push_back({key, s["memory"]["by_owner"][key].get<double>(), note});
  if (s.contains("beams")) b.push_back({"beams", number(s, "/beams/peak_bytes"), "lbt's beams at their peak (--beam-memory)"});
  if (number(s, "/totals/photon_map_bytes") > 0)
    b.push_back({"photon map", number(s, "/totals/photon_map_bytes"), "the largest photon map"});
  if (s.contains("textures"))
    b.push_back({"texture cache", number(s, "/textures/cache_memory_bytes"), "tiles resident (--texture-memory)"});
  if (s.contains("volumes")) b.push_back({"volumes", number(s, "/volumes/bytes"), "brick tables, majorants, the out-of-core trees"});
  if (s.contains("volumes") && s["volumes"].contains("cache"))
    b.push_back({"brick cache", number(s, "/volumes/cache/peak_bytes"), "voxels resident at the peak (--volume-memory)"});
  b.push_back({"peak resident", number(s, "/totals/peak_rss_bytes"), "the whole process at its peak"});
  o << "<h2>Memory by owner</h2><p>Each owner at its largest.</p>" << barChart("Memory by owner", b, " B");
  const json& samples = s.contains("memory_over_time") && s["memory_over_time"].is_array() ? s["memory_over_time"] : json::array();
  if (samples.size() < 2) {
    o << "<p>No samples of memory during the render in these stats: no chart of memory over time.</p>";
    return;
  }
  static const std::pair<const char*, const char*> sampled[] = {
      {"rss_bytes", "resident (process)"}, {"ray_buffers", "ray buffers"}, {"candidates_and_sort", "candidates and sort"},
      {"dice_buffers", "dice buffers"}, {"dice_cache", "grid cache"}, {"border_bounds", "border bounds"}, {"film", "film"}};
  LineChart c{"Memory over the render (MiB; sampled after setup and every generation)", "seconds since setup began", "MiB"};
  for (const auto& [key, name] : sampled) {
    Line l{name, {}};
    const std::string p = std::string("/") + key;
    for (const json& x : samples)
      if (x.is_object()) l.points.push_back({number(x, "/t_s"), number(x, p.c_str()) / double(1 << 20), ""});
    c.lines.push_back(l);
  }
  o << "<div id=memory-over-time>" << lineChart(c) << "</div>";
}

void tableOf(std::ostringstream& o, const json& section, const std::string& prefix) {
  for (const auto& [k, v] : section.items()) {
    if (v.is_object()) tableOf(o, v, prefix + k + ".");
    else
      o << "<tr class=data><td>" << htmlEscape(prefix + k) << "</td><td class=num>"
        << htmlEscape(v.is_number() ? (k.find("bytes") != std::string::npos ? shortBytes(v.get<double>()) : shortNumber(v.get<double>(), 4))
                                    : v.dump())
        << "</td></tr>";
  }
}

void methodSections(std::ostringstream& o, const json& s) {
  if (s.contains("beams")) {
    const json& b = s["beams"];
    o << "<h2>Beams (lbt)</h2>";
    std::vector<Bar> counts;
    for (const char* k : {"generator_triangles", "corner_rays", "segments", "bin_entries", "splits", "reflected_branches"})
      if (b.contains(k) && b[k].is_number()) counts.push_back({k, b[k].get<double>(), ""});
    if (!counts.empty()) o << barChart("Beam counts", counts, "");
    if (b.contains("stopped") && b["stopped"].is_object() && !b["stopped"].empty()) {
      std::vector<Bar> stopped;
      for (const auto& [why, n] : b["stopped"].items())
        if (n.is_number()) stopped.push_back({why, n.get<double>(), ""});
      if (!stopped.empty()) o << barChart("Beams stopped before max_depth, by reason", stopped, "");
    }
    o << "<table>";
    tableOf(o, b, "");
    o << "</table>";
  }
  if (number(s, "/totals/photons_traced") > 0) {
    o << "<h2>Photons (" << htmlEscape(s["settings"]["method"].get<std::string>()) << ")</h2>"
      << barChart("Photons and caustic gathers",
                  {{"photons traced", number(s, "/totals/photons_traced"), "photon paths"},
                   {"photons stored", number(s, "/totals/photons_stored"), "over all maps"},
                   {"caustic gathers", number(s, "/totals/caustic_gathers"), "estimates at diffuse vertices"},
                   {"gathers skipped", number(s, "/totals/caustic_gathers_skipped"), "left out by the roulette"}},
                  "")
      << "<p>Largest photon map: " << shortBytes(number(s, "/totals/photon_map_bytes")) << ".</p>";
  }
  if (s.contains("textures")) {
    o << "<h2>Textures</h2>"
      << barChart("Texture cache",
                  {{"tile lookups", number(s, "/textures/tile_lookups"), "in the shared cache"},
                   {"tiles read", number(s, "/textures/tiles_read"), "from disk (again after an eviction)"},
                   {"peak tiles", number(s, "/textures/peak_tiles"), "resident at once"}},
                  "")
      << "<p>Hit rate " << shortNumber(100 * number(s, "/textures/hit_rate")) << " %, "
      << shortBytes(number(s, "/textures/bytes_read")) << " read of " << shortBytes(number(s, "/textures/image_bytes"))
      << " of images, " << shortNumber(number(s, "/textures/io_time_s")) << " s of I/O (thread time).</p>";
  }
  if (s.contains("volumes")) {
    o << "<h2>Volumes</h2>"
      << barChart("Volume tracking",
                  {{"collisions", number(s, "/volumes/collisions"), "real collisions: scattering vertices"},
                   {"transmittance estimates", number(s, "/volumes/transmittance_estimates"), "shadow segments through media"},
                   {"density lookups", number(s, "/volumes/density_lookups"), "tentative collisions of both trackings"},
                   {"brick cells walked", number(s, "/volumes/brick_cells_walked"), "cells the rays' walks visited"}},
                  "")
      << "<p>" << shortCount(number(s, "/volumes/volumes")) << " volume(s), " << shortCount(number(s, "/volumes/bricks"))
      << " bricks; " << shortNumber(number(s, "/volumes/time_s/load")) << " s loading, "
      << shortNumber(number(s, "/volumes/time_s/tracking")) << " s tracking (thread time).</p>";
    if (s["volumes"].contains("cache")) {
      o << barChart("Brick cache (--volume-memory)",
                    {{"hits", number(s, "/volumes/cache/hits"), "bricks found resident"},
                     {"bricks loaded", number(s, "/volumes/cache/bricks_loaded"), "misses: decoded from the file"},
                     {"evictions", number(s, "/volumes/cache/evictions"), "to stay within the budget"}},
                    "")
        << "<p>Hit rate " << shortNumber(100 * number(s, "/volumes/cache/hit_rate")) << " %, "
        << shortBytes(number(s, "/volumes/cache/bytes_read")) << " decoded, "
        << shortNumber(number(s, "/volumes/time_s/brick_reads")) << " s reading bricks (thread time).</p>";
    }
  }
}

void errorSection(std::ostringstream& o, const json& s) {
  if (!s.contains("error_vs_time") || s["error_vs_time"].empty()) return;
  LineChart c{"Error against time (log-log)", "seconds since the render started", "RMSE", true, true};
  Line run{methodTitle(s), {}};
  for (const json& e : s["error_vs_time"])
    run.points.push_back({e["time_s"].get<double>(), e["rmse"].get<double>(), e["spp"].dump() + " spp"});
  c.lines.push_back(run);
  // The 1/sqrt(t) slope of an unbiased estimator, through the first point.
  const LinePoint first = run.points.front(), last = run.points.back();
  if (first.x > 0 && last.x > first.x)
    c.lines.push_back({"1/√t slope", {{first.x, first.y, ""}, {last.x, first.y * std::sqrt(first.x / last.x), ""}}, true});
  o << "<h2>Error against time</h2>" << lineChart(c);
}

void usedSection(std::ostringstream& o, const json& s) {
  o << "<h2>Used and skipped</h2><table>";
  for (const auto& [k, v] : s["features"].items())
    o << "<tr class=data><td>" << htmlEscape(k) << "</td><td>" << htmlEscape(v.dump()) << "</td></tr>";
  for (const auto& [k, v] : s["skipped"].items())
    o << "<tr class=\"data skip\"><td>skipped: " << htmlEscape(k) << "</td><td>"
      << htmlEscape(v.is_string() ? v.get<std::string>() : v.dump()) << "</td></tr>";
  o << "</table>";
  if (number(s, "/totals/nonfinite_samples_dropped") > 0)
    o << "<p class=warn>" << shortCount(number(s, "/totals/nonfinite_samples_dropped")) << " non-finite samples were dropped.</p>";
}

}  // namespace

double number(const json& j, const char* pointer) {
  const json::json_pointer p(pointer);
  return j.contains(p) && j[p].is_number() ? j[p].get<double>() : 0.0;
}

std::string methodTitle(const json& s) {
  const std::string m = s["settings"]["method"].get<std::string>();
  const char* full = m == "pt" ? "path tracing" : m == "lt" ? "light tracing" : m == "pm" ? "photon mapping"
                     : m == "ppm" ? "progressive photon mapping" : m == "lbt" ? "light beam tracing" : "";
  return *full ? m + " (" + full + ")" : m;
}

std::vector<StageTime> wallStages(const json& s) {
  const auto t = [&](const char* k) { return number(s, (std::string("/totals/time_s/") + k).c_str()); };
  const double total = t("total"), shade = t("shade");
  const double known = t("toplevel") + t("sort") + shade + t("film");
  return {{"load", t("load"), "reading the scene"},
          {"setup", t("setup"), "leaf bounds, top-level BVH, the method's preparation"},
          {"toplevel", t("toplevel"), "candidate leaves per ray"},
          {"sort", t("sort"), "grouping candidates by leaf"},
          {"dice + bottom + rest", std::max(0.0, total - known), "the render's remaining wall time: dicing and intersection run here"},
          {"shade", shade, "materials, lights, next rays (" + shortNumber(t("shade_sort")) + " s of it sorting hits)"},
          {"film", t("film"), "accumulating samples"},
          {"outputs and the rest", std::max(0.0, t("wall") - t("load") - t("setup") - total), "writing files, stats"}};
}

std::vector<StageTime> threadStages(const json& s) {
  const auto t = [&](const char* k) { return number(s, (std::string("/totals/time_s/") + k).c_str()); };
  return {{"dice", t("dice"), "dicing patches + implicit BVH"},
          {"bottom", t("bottom"), "micro-grid intersection"},
          {"leaf queries", t("leaf_queries"), "per-leaf queries (lbt's caustic gathers)"},
          // Setup counts too: lbt traces its beams' corner rays there, through dice and bottom.
          {"threads × (setup + render)", (t("setup") + t("total")) * number(s, "/settings/threads"),
           "what the threads could give in the wall time of setup and render"}};
}

double finalRmse(const json& s) {
  if (!s.contains("error_vs_time") || s["error_vs_time"].empty()) return 0.0;
  return s["error_vs_time"].back()["rmse"].get<double>();
}

std::string runSummary(const json& s) {
  std::ostringstream o;
  o << "<p class=summary><b>" << htmlEscape(methodTitle(s)) << "</b>, " << htmlEscape(s["scene"]["file"].get<std::string>())
    << ": " << s["scene"]["resolution"][0].dump() << "&times;" << s["scene"]["resolution"][1].dump() << ", "
    << s["scene"]["spp"].dump() << " spp, " << s["settings"]["threads"].dump() << " threads; "
    << shortNumber(number(s, "/totals/time_s/total")) << " s render, " << shortNumber(number(s, "/totals/time_s/wall"))
    << " s wall; " << shortCount(number(s, "/totals/rays")) << " rays (" << shortNumber(number(s, "/totals/mrays_per_s"))
    << " Mrays/s); peak memory " << shortBytes(number(s, "/totals/peak_rss_bytes"));
  if (s.contains("parts")) o << "; " << s["parts"].dump() << " parts merged";
  o << ". <span class=note>" << htmlEscape(s["settings"]["program_version"].get<std::string>()) << "</span></p>";
  return o.str();
}

std::string runSections(const json& s) {
  std::ostringstream o;
  timeSection(o, s);
  generationSection(o, s);
  dicingSection(o, s);
  memorySection(o, s);
  methodSections(o, s);
  errorSection(o, s);
  usedSection(o, s);
  return o.str();
}

}  // namespace rayes
