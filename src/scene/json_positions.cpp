#include "scene/json_positions.h"
#include <cctype>

namespace rayes {
namespace {

struct Walker {
  const std::string& s;
  size_t i = 0;
  int line = 1, col = 1;
  std::unordered_map<std::string, std::pair<int, int>>& out;

  void advance() {
    if (s[i] == '\n') { ++line; col = 1; } else { ++col; }
    ++i;
  }
  void skipSpace() { while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) advance(); }
  std::string readString() {  // at the opening quote; returns the decoded-enough key
    std::string r;
    advance();
    while (i < s.size() && s[i] != '"') {
      if (s[i] == '\\') { advance(); if (i < s.size()) { r += s[i]; advance(); } continue; }
      r += s[i];
      advance();
    }
    if (i < s.size()) advance();
    return r;
  }
  static std::string escape(const std::string& key) {  // RFC 6901
    std::string r;
    for (char c : key) { if (c == '~') r += "~0"; else if (c == '/') r += "~1"; else r += c; }
    return r;
  }
  void value(const std::string& ptr) {
    skipSpace();
    if (i >= s.size()) return;
    out[ptr] = {line, col};
    const char c = s[i];
    if (c == '{') {
      advance();
      for (;;) {
        skipSpace();
        if (i >= s.size() || s[i] == '}') { if (i < s.size()) advance(); return; }
        if (s[i] == ',') { advance(); continue; }
        if (s[i] != '"') { advance(); continue; }
        const std::string key = readString();
        skipSpace();
        if (i < s.size() && s[i] == ':') advance();
        value(ptr + "/" + escape(key));
      }
    } else if (c == '[') {
      advance();
      int index = 0;
      for (;;) {
        skipSpace();
        if (i >= s.size() || s[i] == ']') { if (i < s.size()) advance(); return; }
        if (s[i] == ',') { advance(); continue; }
        value(ptr + "/" + std::to_string(index++));
      }
    } else if (c == '"') {
      readString();
    } else {
      while (i < s.size() && s[i] != ',' && s[i] != '}' && s[i] != ']' &&
             !std::isspace(static_cast<unsigned char>(s[i])))
        advance();
    }
  }
};

}  // namespace

JsonPositions::JsonPositions(const std::string& text) {
  Walker w{text, 0, 1, 1, pos_};
  w.value("");
}

std::string JsonPositions::place(const std::string& pointer) const {
  std::string p = pointer;
  for (;;) {
    auto it = pos_.find(p);
    if (it != pos_.end()) return std::to_string(it->second.first) + ":" + std::to_string(it->second.second);
    const size_t slash = p.rfind('/');
    if (slash == std::string::npos || p.empty()) return "1:1";
    p.resize(slash);
  }
}

}  // namespace rayes
