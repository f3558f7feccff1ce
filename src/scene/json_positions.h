// Finds where a value of a (syntactically valid) JSON text stands in the file, so that errors
// found after parsing -- a wrong type, an unknown key, an impossible value, a duplicated key --
// can name the place ("line:column", 1-based, columns in bytes), not just the JSON pointer.
// nlohmann::json keeps no source positions, hence this second look at the text.
//
// Lookups happen only when an error is reported, so nothing is indexed up front: each lookup
// walks the text once, without recursion and with memory independent of the nesting depth
// (a 100 000-deep array costs a counter, not a stack frame or a pointer string per level).
#pragma once
#include <cstddef>
#include <string>
#include <string_view>

namespace rayes {

class JsonPositions {
 public:
  explicit JsonPositions(std::string_view text) : text_(text) {}
  // The place of the value at `pointer` (RFC 6901), or of its deepest ancestor in the text.
  std::string place(const std::string& pointer) const;
  // The place of the n-th object key (0-based) in text order.
  std::string placeOfKey(size_t n) const;
  // The place of byte `offset` (0-based).
  std::string placeOfOffset(size_t offset) const;

 private:
  std::string text_;
};

}  // namespace rayes
