#include "scene/json_positions.h"
#include <charconv>
#include <cstdint>
#include <vector>

namespace rayes {
namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

size_t skipSpace(std::string_view s, size_t i) {
  while (i < s.size() && isSpace(s[i])) ++i;
  return i;
}

void appendUtf8(std::string& out, uint32_t cp) {
  if (cp < 0x80) {
    out += char(cp);
  } else if (cp < 0x800) {
    out += char(0xC0 | (cp >> 6));
    out += char(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += char(0xE0 | (cp >> 12));
    out += char(0x80 | ((cp >> 6) & 0x3F));
    out += char(0x80 | (cp & 0x3F));
  } else {
    out += char(0xF0 | (cp >> 18));
    out += char(0x80 | ((cp >> 12) & 0x3F));
    out += char(0x80 | ((cp >> 6) & 0x3F));
    out += char(0x80 | (cp & 0x3F));
  }
}

uint32_t hex4(std::string_view s, size_t i) {
  uint32_t v = 0;
  if (i + 4 > s.size()) return 0;
  std::from_chars(s.data() + i, s.data() + i + 4, v, 16);
  return v;
}

// At the opening quote; returns the index past the closing quote. The decoded text goes to
// `out` when given: keys must compare equal to nlohmann's decoding (escapes, \u surrogates).
size_t readString(std::string_view s, size_t i, std::string* out) {
  ++i;
  while (i < s.size() && s[i] != '"') {
    if (s[i] != '\\') {
      if (out) *out += s[i];
      ++i;
      continue;
    }
    if (i + 1 >= s.size()) return s.size();
    const char e = s[i + 1];
    i += 2;
    if (!out) {
      continue;
    } else if (e == 'u') {
      uint32_t cp = hex4(s, i);
      i += 4;
      if (cp >= 0xD800 && cp < 0xDC00 && i + 6 <= s.size() && s[i] == '\\' && s[i + 1] == 'u') {
        cp = 0x10000 + ((cp - 0xD800) << 10) + (hex4(s, i + 2) - 0xDC00);
        i += 6;
      }
      appendUtf8(*out, cp);
    } else {
      const char* from = "bfnrt";
      const char* to = "\b\f\n\r\t";
      char c = e;
      for (int k = 0; k < 5; ++k)
        if (e == from[k]) c = to[k];
      *out += c;
    }
  }
  return i < s.size() ? i + 1 : i;
}

// At the first character of a value; returns the index just past it. Nesting is followed with
// a depth counter only.
size_t skipValue(std::string_view s, size_t i) {
  if (i >= s.size()) return i;
  if (s[i] == '"') return readString(s, i, nullptr);
  if (s[i] != '{' && s[i] != '[') {
    while (i < s.size() && s[i] != ',' && s[i] != '}' && s[i] != ']' && !isSpace(s[i])) ++i;
    return i;
  }
  size_t depth = 0;
  while (i < s.size()) {
    const char c = s[i];
    if (c == '"') {
      i = readString(s, i, nullptr);
      continue;
    }
    ++i;
    if (c == '{' || c == '[') ++depth;
    else if ((c == '}' || c == ']') && --depth == 0) break;
  }
  return i;
}

std::vector<std::string> pointerTokens(const std::string& pointer) {
  std::vector<std::string> tokens;
  size_t i = 0;
  while (i < pointer.size() && pointer[i] == '/') {
    const size_t end = std::min(pointer.find('/', i + 1), pointer.size());
    std::string t;
    for (size_t k = i + 1; k < end; ++k) {
      if (pointer[k] == '~' && k + 1 < end && (pointer[k + 1] == '0' || pointer[k + 1] == '1')) {
        t += pointer[k + 1] == '0' ? '~' : '/';
        ++k;
      } else {
        t += pointer[k];
      }
    }
    tokens.push_back(std::move(t));
    i = end;
  }
  return tokens;
}

// The start of member `key` of the object at i, or npos.
size_t findMember(std::string_view s, size_t i, const std::string& key) {
  ++i;
  for (;;) {
    i = skipSpace(s, i);
    if (i >= s.size() || s[i] == '}') return std::string_view::npos;
    if (s[i] == ',') {
      ++i;
      continue;
    }
    if (s[i] != '"') return std::string_view::npos;
    std::string k;
    i = skipSpace(s, readString(s, i, &k));
    if (i < s.size() && s[i] == ':') ++i;
    i = skipSpace(s, i);
    if (k == key) return i;
    i = skipValue(s, i);
  }
}

// The start of element `index` of the array at i, or npos.
size_t findElement(std::string_view s, size_t i, const std::string& token) {
  size_t index = 0;
  const auto [p, ec] = std::from_chars(token.data(), token.data() + token.size(), index);
  if (ec != std::errc() || p != token.data() + token.size()) return std::string_view::npos;
  ++i;
  for (size_t k = 0;; ++k) {
    i = skipSpace(s, i);
    if (i >= s.size() || s[i] == ']') return std::string_view::npos;
    if (k == index) return i;
    i = skipSpace(s, skipValue(s, i));
    if (i < s.size() && s[i] == ',') ++i;
  }
}

}  // namespace

std::string JsonPositions::placeOfOffset(size_t offset) const {
  size_t line = 1, col = 1;
  for (size_t i = 0; i < offset && i < text_.size(); ++i) {
    if (text_[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return std::to_string(line) + ":" + std::to_string(col);
}

std::string JsonPositions::place(const std::string& pointer) const {
  const std::string_view s = text_;
  size_t at = skipSpace(s, 0);
  for (const std::string& token : pointerTokens(pointer)) {
    if (at >= s.size()) break;
    const size_t next = s[at] == '{'   ? findMember(s, at, token)
                        : s[at] == '[' ? findElement(s, at, token)
                                       : std::string_view::npos;
    if (next == std::string_view::npos) break;
    at = next;
  }
  return placeOfOffset(at);
}

std::string JsonPositions::placeOfKey(size_t n) const {
  const std::string_view s = text_;
  size_t keys = 0;
  for (size_t i = 0; i < s.size();) {
    if (s[i] != '"') {
      ++i;
      continue;
    }
    const size_t start = i;
    i = skipSpace(s, readString(s, i, nullptr));
    if (i < s.size() && s[i] == ':' && keys++ == n) return placeOfOffset(start);
  }
  return placeOfOffset(s.size());
}

}  // namespace rayes
