// A method's own statistics (the stats file's section for it, docs/stats.md), as plain data:
// ordered key -> value pairs, where a dotted key nests ("stopped.mixed" is
// {"stopped": {"mixed": ...}}), and what the method left out, by section, with the reason
// (the stats file's "skipped"). Made by an integrator (Integrator::methodStats) and written by
// the app, so no method needs to know the file's format and the app needs no method's types.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

namespace rayes {

struct MethodStats {
  using Value = std::variant<int64_t, uint64_t, double, std::string>;
  std::string section;  // e.g. "beams"; empty: the method keeps no section of its own
  std::vector<std::pair<std::string, Value>> values;
  std::vector<std::pair<std::string, std::string>> skipped;  // (section, why it was not built)

  void add(std::string key, Value v) { values.emplace_back(std::move(key), std::move(v)); }
  // Whether `section` was left out (then its values are not written).
  bool wasSkipped(std::string_view which) const {
    for (const auto& [s, why] : skipped)
      if (s == which) return true;
    return false;
  }
  // A numeric value by key, 0 where there is none (or it is text).
  double number(std::string_view key) const {
    for (const auto& [k, v] : values)
      if (k == key) {
        if (const auto* i = std::get_if<int64_t>(&v)) return double(*i);
        if (const auto* u = std::get_if<uint64_t>(&v)) return double(*u);
        if (const auto* d = std::get_if<double>(&v)) return *d;
      }
    return 0;
  }
};

}  // namespace rayes
