#include "scene/json_document.h"
#include <unordered_set>
#include <vector>
#include "core/error.h"
#include "scene/json_positions.h"

namespace rayes {
namespace {

using json = nlohmann::json;

// Builds the document with nlohmann's own DOM builder and watches the keys on the way: the
// parser is iterative, so deep nesting costs heap (one key set per open object), not stack.
class CheckedDomBuilder {
 public:
  CheckedDomBuilder(json& root, std::string_view text, const std::string& path)
      : dom_(root), text_(text), path_(path) {}

  bool null() { return dom_.null(); }
  bool boolean(bool v) { return dom_.boolean(v); }
  bool number_integer(json::number_integer_t v) { return dom_.number_integer(v); }
  bool number_unsigned(json::number_unsigned_t v) { return dom_.number_unsigned(v); }
  bool number_float(json::number_float_t v, const json::string_t& s) { return dom_.number_float(v, s); }
  bool string(json::string_t& v) { return dom_.string(v); }
  bool binary(json::binary_t& v) { return dom_.binary(v); }
  bool start_object(std::size_t n) {
    keys_.emplace_back();
    return dom_.start_object(n);
  }
  bool key(json::string_t& k) {
    if (!keys_.back().insert(k).second)
      throw InputError(path_, JsonPositions(text_).placeOfKey(keyCount_),
                       "key '" + k + "' appears twice in the same object");
    ++keyCount_;
    return dom_.key(k);
  }
  bool end_object() {
    keys_.pop_back();
    return dom_.end_object();
  }
  bool start_array(std::size_t n) { return dom_.start_array(n); }
  bool end_array() { return dom_.end_array(); }
  template <class Exception>
  bool parse_error(std::size_t position, const std::string&, const Exception& e) {
    // `position` counts the characters read, i.e. it stands just past the offending token.
    std::string msg = e.what();
    const auto at = msg.find("] ");
    if (at != std::string::npos) msg = msg.substr(at + 2);
    const auto syntax = msg.find("syntax error");
    if (syntax != std::string::npos) msg = msg.substr(syntax);
    throw InputError(path_, JsonPositions(text_).placeOfOffset(position == 0 ? 0 : position - 1), "JSON " + msg);
  }

 private:
  nlohmann::detail::json_sax_dom_parser<json> dom_;
  std::string_view text_;
  const std::string& path_;
  std::vector<std::unordered_set<std::string>> keys_;
  size_t keyCount_ = 0;
};

}  // namespace

std::string_view withoutByteOrderMark(std::string_view text) {
  return text.substr(0, 3) == "\xEF\xBB\xBF" ? text.substr(3) : text;
}

json parseJsonDocument(std::string_view text, const std::string& path) {
  json doc;
  CheckedDomBuilder builder(doc, text, path);
  json::sax_parse(text.begin(), text.end(), &builder);
  return doc;
}

}  // namespace rayes
