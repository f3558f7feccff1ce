#include "app/report_format.h"
#include <cmath>
#include <cstdio>

namespace rayes {

std::string htmlEscape(const std::string& s) {
  std::string r;
  r.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&': r += "&amp;"; break;
      case '<': r += "&lt;"; break;
      case '>': r += "&gt;"; break;
      case '"': r += "&quot;"; break;
      case '\'': r += "&#39;"; break;
      default: r += c;
    }
  }
  return r;
}

std::string shortNumber(double v, int digits) {
  if (!std::isfinite(v)) return "–";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string shortCount(double v) {
  const double a = std::fabs(v);
  if (a >= 1e9) return shortNumber(v * 1e-9) + " G";
  if (a >= 1e6) return shortNumber(v * 1e-6) + " M";
  if (a >= 1e4) return shortNumber(v * 1e-3) + " k";
  return shortNumber(v, 6);
}

std::string shortBytes(double v) {
  const double a = std::fabs(v);
  if (a >= double(1ull << 30)) return shortNumber(v / double(1ull << 30)) + " GiB";
  if (a >= double(1ull << 20)) return shortNumber(v / double(1ull << 20)) + " MiB";
  if (a >= double(1ull << 10)) return shortNumber(v / double(1ull << 10)) + " KiB";
  return shortNumber(v, 6) + " B";
}

std::string ratioText(double a, double b) {
  if (!(a > 0) || !std::isfinite(b)) return "–";
  return shortNumber(b / a) + "&times;";
}

std::string base64(const std::string& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
    if (i + 1 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 1])) << 8;
    if (i + 2 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 2]));
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? table[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? table[v & 63] : '=';
  }
  return out;
}

}  // namespace rayes
