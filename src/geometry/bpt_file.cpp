// The .bpt loader (declared in bezier_patch.h). Every failure names the file and line
// (docs/design.md, invariant 6); nothing here aborts.
#include <charconv>
#include <cmath>
#include <fstream>
#include <string_view>
#include "core/error.h"
#include "geometry/bezier_patch.h"

namespace rayes {
namespace {

class LineReader {
 public:
  explicit LineReader(const std::string& path) : path_(path), in_(path) {
    if (!in_) throw InputError(path_, "", "cannot open Bézier patch file");
  }
  // Next non-blank line; throws at end of file, naming what was expected.
  std::string_view next(const char* expected) {
    while (std::getline(in_, line_)) {
      ++lineNo_;
      if (!line_.empty() && line_.back() == '\r') line_.pop_back();
      if (line_.find_first_not_of(" \t") != std::string::npos) return line_;
    }
    ++lineNo_;
    fail(std::string("unexpected end of file, expected ") + expected);
  }
  bool atEnd() {
    while (std::getline(in_, line_)) {
      ++lineNo_;
      if (line_.find_first_not_of(" \t\r") != std::string::npos) return false;
    }
    return true;
  }
  [[noreturn]] void fail(const std::string& message) const {
    throw InputError(path_, "line " + std::to_string(lineNo_), message);
  }
  int lineNo() const { return lineNo_; }

 private:
  std::string path_;
  std::ifstream in_;
  std::string line_;
  int lineNo_ = 0;
};

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// Splits on commas into exactly `count` fields and parses each with from_chars.
template <class T>
void parseFields(LineReader& r, std::string_view line, T* out, int count, const char* what) {
  for (int k = 0; k < count; ++k) {
    const size_t comma = line.find(',');
    if ((comma == std::string_view::npos) != (k == count - 1))
      r.fail("expected " + std::to_string(count) + " comma-separated " + what);
    const std::string_view field = trim(line.substr(0, comma));
    line = comma == std::string_view::npos ? std::string_view() : line.substr(comma + 1);
    const auto res = std::from_chars(field.data(), field.data() + field.size(), out[k]);
    if (res.ec != std::errc() || res.ptr != field.data() + field.size() || field.empty())
      r.fail("malformed number '" + std::string(field) + "'");
    if constexpr (std::is_floating_point_v<T>) {
      if (!std::isfinite(out[k])) r.fail("non-finite coordinate '" + std::string(field) + "'");
    }
  }
}

long parseCount(LineReader& r, std::string_view line, const char* what) {
  long n = 0;
  parseFields(r, line, &n, 1, what);
  if (n < 0 || n > 100'000'000) r.fail(std::string("invalid ") + what);
  return n;
}

}  // namespace

std::vector<std::array<Vec3, 16>> loadBezierPatchFile(const std::string& path) {
  LineReader r(path);
  const long patchCount = parseCount(r, r.next("the patch count"), "patch count");
  std::vector<std::array<long, 16>> indices(static_cast<size_t>(patchCount));
  std::vector<int> indexLines(static_cast<size_t>(patchCount));
  for (auto& idx : indices) {
    parseFields(r, r.next("a line of 16 control-point indices"), idx.data(), 16, "indices");
    indexLines[&idx - indices.data()] = r.lineNo();
  }
  const long pointCount = parseCount(r, r.next("the point count"), "point count");
  std::vector<Vec3> points(static_cast<size_t>(pointCount));
  for (Vec3& p : points) {
    float xyz[3];
    parseFields(r, r.next("a point line x,y,z"), xyz, 3, "coordinates");
    p = {xyz[0], xyz[1], xyz[2]};
  }
  if (!r.atEnd()) r.fail("unexpected content after the " + std::to_string(pointCount) + " points");

  std::vector<std::array<Vec3, 16>> patches(static_cast<size_t>(patchCount));
  for (size_t k = 0; k < indices.size(); ++k) {
    for (int c = 0; c < 16; ++c) {
      const long i = indices[k][c];
      if (i < 1 || i > pointCount)
        throw InputError(path, "line " + std::to_string(indexLines[k]),
                         "control-point index " + std::to_string(i) + " out of range 1.." +
                             std::to_string(pointCount));
      patches[k][c] = points[size_t(i - 1)];
    }
  }
  return patches;
}

}  // namespace rayes
