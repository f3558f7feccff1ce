// Typed, checked access to a parsed scene document. Every failure throws InputError with the
// file, the line:column of the value and its JSON pointer. Shared by the readers of each
// section of the scene file (materials, shapes, lights, ...).
#pragma once
#include <cmath>
#include <initializer_list>
#include <set>
#include <string>
#include <nlohmann/json.hpp>
#include "core/error.h"
#include "core/vec.h"
#include "scene/json_positions.h"

namespace rayes {

using json = nlohmann::json;

// Typed, checked access to the parsed document; every failure names file, line:column and
// the JSON pointer of the offending value.
class JsonReader {
 public:
  JsonReader(std::string file, std::string_view text) : file_(std::move(file)), pos_(text) {}

  [[noreturn]] void fail(const std::string& ptr, const std::string& msg) const {
    throw InputError(file_, pos_.place(ptr), (ptr.empty() ? "/" : ptr) + ": " + msg);
  }
  // "line:column" of the value at `ptr`, for messages that are not errors (warnings).
  std::string place(const std::string& ptr) const { return pos_.place(ptr); }
  // A resource limit met at this place (exit code 3): "file:line:column: ptr: msg".
  [[noreturn]] void failResource(const std::string& ptr, const std::string& msg) const {
    throw ResourceError(file_ + ":" + pos_.place(ptr), (ptr.empty() ? "/" : ptr) + ": " + msg);
  }
  static std::string typeName(const json& j) { return j.type_name(); }

  void object(const json& j, const std::string& ptr, std::initializer_list<const char*> allowed) const {
    objectKeys(j, ptr, std::set<std::string>(allowed.begin(), allowed.end()));
  }
  void objectKeys(const json& j, const std::string& ptr, const std::set<std::string>& ok) const {
    if (!j.is_object()) fail(ptr, "expected an object, got " + typeName(j));
    for (auto it = j.begin(); it != j.end(); ++it)
      if (!ok.count(it.key())) {
        std::string list;
        for (const auto& k : ok) list += (list.empty() ? "" : ", ") + k;
        fail(ptr + "/" + it.key(), "unknown key '" + it.key() + "' (expected one of: " + list + ")");
      }
  }
  const json& member(const json& j, const std::string& ptr, const char* key) const {
    if (!j.contains(key)) fail(ptr, std::string("missing required key '") + key + "'");
    return j.at(key);
  }
  double number(const json& j, const std::string& ptr) const {
    if (!j.is_number()) fail(ptr, "expected a number, got " + typeName(j));
    const double v = j.get<double>();
    if (!std::isfinite(v) || std::fabs(v) > 3.0e38) fail(ptr, "number out of range");
    return v;
  }
  int integer(const json& j, const std::string& ptr) const {
    if (!j.is_number_integer()) fail(ptr, "expected an integer, got " + typeName(j));
    const auto v = j.get<int64_t>();
    if (v < -(int64_t(1) << 30) || v > (int64_t(1) << 30)) fail(ptr, "integer out of range");
    return static_cast<int>(v);
  }
  bool boolean(const json& j, const std::string& ptr) const {
    if (!j.is_boolean()) fail(ptr, "expected true or false, got " + typeName(j));
    return j.get<bool>();
  }
  std::string string(const json& j, const std::string& ptr) const {
    if (!j.is_string()) fail(ptr, "expected a string, got " + typeName(j));
    return j.get<std::string>();
  }
  Vec3 vec3(const json& j, const std::string& ptr) const {
    if (!j.is_array() || j.size() != 3) fail(ptr, "expected an array of 3 numbers");
    return {float(number(j[0], ptr + "/0")), float(number(j[1], ptr + "/1")), float(number(j[2], ptr + "/2"))};
  }
  // A position, kept in double until the render frame (scene/scene.h, RenderFrame) is applied.
  Vec3d vec3d(const json& j, const std::string& ptr) const {
    if (!j.is_array() || j.size() != 3) fail(ptr, "expected an array of 3 numbers");
    return {number(j[0], ptr + "/0"), number(j[1], ptr + "/1"), number(j[2], ptr + "/2")};
  }
  Rgb color(const json& j, const std::string& ptr, bool atMostOne) const {
    const Rgb c = j.is_number() ? Rgb{float(number(j, ptr)), float(number(j, ptr)), float(number(j, ptr))}
                                : vec3(j, ptr);
    if (c.x < 0 || c.y < 0 || c.z < 0) fail(ptr, "must not be negative");
    if (atMostOne && (c.x > 1 || c.y > 1 || c.z > 1))
      fail(ptr, "a reflectance above 1 would create energy");
    return c;
  }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
  JsonPositions pos_;
};

}  // namespace rayes
