#include "app/html_report.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace rayes {
namespace {
using json = nlohmann::json;

std::string escape(const std::string& s) {
  std::string r;
  for (char c : s) {
    switch (c) {
      case '&': r += "&amp;"; break;
      case '<': r += "&lt;"; break;
      case '>': r += "&gt;"; break;
      case '"': r += "&quot;"; break;
      default: r += c;
    }
  }
  return r;
}

std::string number(double v, int digits = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string count(uint64_t v) {  // 12345678 -> 12.3 M
  if (v >= 1000000000ull) return number(double(v) * 1e-9) + " G";
  if (v >= 1000000ull) return number(double(v) * 1e-6) + " M";
  if (v >= 10000ull) return number(double(v) * 1e-3) + " k";
  return std::to_string(v);
}

std::string bytes(uint64_t v) {
  if (v >= (1ull << 30)) return number(double(v) / double(1ull << 30)) + " GiB";
  if (v >= (1ull << 20)) return number(double(v) / double(1ull << 20)) + " MiB";
  if (v >= (1ull << 10)) return number(double(v) / double(1ull << 10)) + " KiB";
  return std::to_string(v) + " B";
}

// A horizontal bar chart: label, value, a bar scaled to the largest value, and a note.
void bars(std::ostringstream& o, const std::vector<std::tuple<std::string, double, std::string>>& rows,
          const std::string& unit) {
  double top = 0;
  for (const auto& [l, v, n] : rows) top = std::max(top, v);
  o << "<table class=bars>";
  for (const auto& [label, v, note] : rows) {
    const double w = top > 0 ? 100.0 * v / top : 0;
    o << "<tr><td>" << escape(label) << "</td><td class=num>" << (v >= 100 ? std::to_string(std::lround(v)) : number(v)) << unit
      << "</td><td class=barcell><div class=bar style=\"width:" << number(w, 4) << "%\"></div></td><td>"
      << escape(note) << "</td></tr>";
  }
  o << "</table>";
}

double get(const json& j, const char* k) { return j.contains(k) && j[k].is_number() ? j[k].get<double>() : 0.0; }

}  // namespace

std::string htmlReport(const json& s, const std::string& preview) {
  std::ostringstream o;
  const json& t = s["totals"];
  const json& ts = t["time_s"];
  o << "<!DOCTYPE html><html><head><meta charset=utf-8><title>rayes report: "
    << escape(s["scene"]["file"].get<std::string>()) << "</title><style>"
       "body{font:14px/1.4 system-ui,sans-serif;margin:2em;max-width:70em;color:#222}"
       "h1{font-size:1.4em}h2{font-size:1.1em;margin-top:1.6em;border-bottom:1px solid #ccc}"
       "table{border-collapse:collapse}td,th{padding:2px 10px;text-align:left;vertical-align:top}"
       "th{border-bottom:1px solid #999}.num{text-align:right;font-variant-numeric:tabular-nums}"
       ".barcell{width:22em}.bar{background:#4a7fb5;height:0.9em}.bars td{border:0}"
       "tr.data:nth-child(even){background:#f3f3f3}.skip{color:#777}img{max-width:100%;border:1px solid #ccc}"
       "</style></head><body>";
  o << "<h1>rayes: " << escape(s["scene"]["file"].get<std::string>()) << "</h1>";
  o << "<p>" << s["scene"]["resolution"][0].get<int>() << "&times;" << s["scene"]["resolution"][1].get<int>()
    << ", " << s["scene"]["spp"].get<int>() << " spp, " << s["settings"]["threads"].get<int>() << " threads, "
    << "row kernels " << escape(s["settings"]["vector_isa"].get<std::string>()) << ", "
    << number(get(ts, "total")) << " s render (" << number(get(ts, "wall")) << " s wall), "
    << count(t["rays"].get<uint64_t>()) << " rays (" << number(get(t, "mrays_per_s")) << " Mrays/s), peak memory "
    << bytes(t["peak_rss_bytes"].get<uint64_t>()) << ".</p>";
  if (!preview.empty()) o << "<p><img src=\"" << escape(preview) << "\" alt=\"preview\"></p>";

  o << "<h2>Where the time went</h2><p>Dice and bottom are summed over threads; the others are wall clock.</p>";
  bars(o,
       {{"load", get(ts, "load"), "reading the scene"},
        {"setup", get(ts, "setup"), "leaf bounds, top-level BVH"},
        {"toplevel", get(ts, "toplevel"), "candidate leaves per ray"},
        {"sort", get(ts, "sort"), "grouping candidates by leaf"},
        {"dice", get(ts, "dice"), "dicing patches + implicit BVH (thread sum)"},
        {"bottom", get(ts, "bottom"), "micro-grid intersection (thread sum)"},
        {"shade", get(ts, "shade"), "materials, lights, next rays"},
        {"shade_sort", get(ts, "shade_sort"), "sorting hits by (material, leaf), part of shade"},
        {"film", get(ts, "film"), "accumulating samples"}},
       " s");

  o << "<h2>Dicing</h2><p>" << count(t["leaves_diced"].get<uint64_t>()) << " dicings created "
    << count(t["micropolygons_created"].get<uint64_t>()) << " micropolygons; tessellating every patch at the finest "
    << "level once would create " << count(t["micropolygons_potential"].get<uint64_t>()) << ".</p><table><tr><th>kind</th><th class=num>leaves</th></tr>";
  for (auto it = s["scene"]["leaf_kinds"].begin(); it != s["scene"]["leaf_kinds"].end(); ++it)
    o << "<tr class=data><td>" << escape(it.key()) << "</td><td class=num>" << count(it.value().get<uint64_t>()) << "</td></tr>";
  o << "</table>";

  // By owner (docs/stats.md): what is fixed by the budgets and what grows with the scene.
  o << "<h2>Memory</h2>";
  const json& m = s["memory"];
  const json& own = m["by_owner"];
  const auto mib = [&](const char* key) { return double(own[key].get<uint64_t>()) / double(1 << 20); };
  bars(o,
       {{"ray buffers", mib("ray_buffers"),
         count(m["paths_per_batch"].get<uint64_t>()) + " paths per batch at " + std::to_string(m["bytes_per_path"].get<uint64_t>()) +
             " B (" + std::to_string(m["bytes_per_ray"].get<uint64_t>()) + " B per ray slot)"},
        {"candidates and sort", mib("candidates_and_sort"), "per ray slot: candidate slots, sort scratch, trace state"},
        {"top level", mib("top_level"), "4-wide BVH over patch boxes"},
        {"dice buffers", mib("dice_buffers"), "one per thread, any scene size"},
        {"grid cache", mib("dice_cache"), "diced grids kept between uses, at its peak"},
        {"border bounds", mib("border_bounds"), "crack-closing border boxes kept between dicings"},
        {"film", mib("film"), "per-pixel sums"},
        {"uv sets", mib("uv_sets"), "the leaves' texture coordinates (none without uvs)"},
        {"beams", double(own.value("beams", uint64_t(0))) / double(1 << 20),
         "lbt: the --beam-memory account at its peak (none for other methods)"},
        {"scene description", mib("scene_description"),
         number(m["scene_bytes_per_leaf"].get<double>()) + " B per leaf: grows with the scene"},
        {"peak resident", double(t["peak_rss_bytes"].get<uint64_t>()) / double(1 << 20), "whole process"}},
       " MiB");

  o << "<h2>Generations</h2><table><tr><th>pass</th><th>batch</th><th>depth</th><th class=num>rays</th>"
       "<th class=num>shadow</th><th class=num>iterations</th><th>active rays / candidates per ray</th>"
       "<th class=num>dicings</th><th class=num>micropolygons</th></tr>";
  for (const auto& g : s["generations"]) {
    std::string its;
    for (const auto& it : g["iterations"])
      its += (its.empty() ? "" : ", ") + count(it["active_rays"].get<uint64_t>()) + " / " +
             number(it["candidates_per_ray"].get<double>());
    o << "<tr class=data><td>" << g["pass"].get<int>() << "</td><td>" << g["batch"].get<int>() << "</td><td>"
      << g["depth"].get<int>() << "</td><td class=num>" << count(g["rays"].get<uint64_t>()) << "</td><td class=num>"
      << count(g["shadow_rays"].get<uint64_t>()) << "</td><td class=num>" << g["iterations"].size() << "</td><td>"
      << escape(its) << "</td><td class=num>" << count(g["leaves_diced"].get<uint64_t>()) << "</td><td class=num>"
      << count(g["micropolygons_created"].get<uint64_t>()) << "</td></tr>";
  }
  o << "</table>";

  o << "<h2>Used and skipped</h2><table>";
  for (auto it = s["features"].begin(); it != s["features"].end(); ++it)
    o << "<tr class=data><td>" << escape(it.key()) << "</td><td>" << escape(it.value().dump()) << "</td></tr>";
  for (auto it = s["skipped"].begin(); it != s["skipped"].end(); ++it)
    o << "<tr class=\"data skip\"><td>skipped: " << escape(it.key()) << "</td><td>" << escape(it.value().get<std::string>())
      << "</td></tr>";
  o << "</table>";
  if (t.contains("nonfinite_samples_dropped") && t["nonfinite_samples_dropped"].get<uint64_t>() > 0)
    o << "<p><b>" << t["nonfinite_samples_dropped"].get<uint64_t>() << " non-finite samples were dropped.</b></p>";

  if (s.contains("error_vs_time")) {
    o << "<h2>Error against time</h2><table><tr><th class=num>spp</th><th class=num>time (s)</th><th class=num>RMSE</th>"
         "<th class=num>RMSE &middot; &radic;spp</th></tr>";
    for (const auto& e : s["error_vs_time"])
      o << "<tr class=data><td class=num>" << e["spp"].get<int>() << "</td><td class=num>" << number(e["time_s"].get<double>())
        << "</td><td class=num>" << number(e["rmse"].get<double>(), 4) << "</td><td class=num>"
        << number(e["rmse"].get<double>() * std::sqrt(e["spp"].get<double>()), 4) << "</td></tr>";
    o << "</table>";
  }
  o << "</body></html>\n";
  return o.str();
}

}  // namespace rayes
