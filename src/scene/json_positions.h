// Maps each value of a (syntactically valid) JSON text to its line and column, keyed by JSON
// pointer ("/shapes/2/material"), so that errors found after parsing -- a wrong type, an
// unknown key, an impossible value -- can name the place in the file, not just the path.
// nlohmann::json keeps no source positions, hence this small second pass over the text.
#pragma once
#include <string>
#include <unordered_map>

namespace rayes {

class JsonPositions {
 public:
  explicit JsonPositions(const std::string& text);
  // "line:column" of the value at `pointer` (1-based), or of its nearest recorded ancestor.
  std::string place(const std::string& pointer) const;

 private:
  std::unordered_map<std::string, std::pair<int, int>> pos_;
};

}  // namespace rayes
