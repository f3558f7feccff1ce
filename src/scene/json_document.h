// Parses the text of a scene file into a json value, or throws InputError naming the file and
// line:column: syntax errors, numbers too large for a double (1e999), and keys given twice in
// one object (nlohmann would silently keep the last). A leading UTF-8 byte-order mark is
// skipped; positions are counted after it.
#pragma once
#include <string>
#include <string_view>
#include <nlohmann/json.hpp>

namespace rayes {

// `text` without a leading UTF-8 byte-order mark.
std::string_view withoutByteOrderMark(std::string_view text);
// `text` must already be without a byte-order mark (so that positions agree with JsonReader's).
nlohmann::json parseJsonDocument(std::string_view text, const std::string& path);

}  // namespace rayes
