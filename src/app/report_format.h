// Text formatting shared by the report's page parts: HTML escaping and short human numbers.
#pragma once
#include <cstdint>
#include <string>

namespace rayes {

std::string htmlEscape(const std::string& s);
std::string shortNumber(double v, int digits = 3);  // "%.3g"
std::string shortCount(double v);                   // 12345678 -> "12.3 M"
std::string shortBytes(double v);                   // 36280320 -> "34.6 MiB"
// Bytes as base64 (data: URIs and the heat maps' values inside a page).
std::string base64(const std::string& bytes);
// A ratio b / a for a comparison ("1.25×"; "–" when a is 0).
std::string ratioText(double a, double b);

}  // namespace rayes
