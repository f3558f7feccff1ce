// Rewrites a scene document so the whole scene -- camera, shapes, lights, displacement, media --
// is scaled by s about the origin and then translated by (o, o, o). An exact similarity of
// the scene, so the image is unchanged up to float rounding: the stiff-case tests compare
// renders of the rewritten scene with the original.
#pragma once
#include <string>
#include <nlohmann/json.hpp>
#include "core/text_file.h"
#include "scene/scene_loader.h"

namespace rayes::testing {

struct Similarity {
  double scale = 1;
  double offset = 0;  // the same on x, y and z
};

inline nlohmann::json transformedScene(nlohmann::json doc, Similarity t) {
  using nlohmann::json;
  const auto point = [&](json& p) {
    for (auto& c : p) c = c.get<double>() * t.scale + t.offset;
  };
  const auto vector = [&](json& v) {
    for (auto& c : v) c = c.get<double>() * t.scale;
  };
  const auto length = [&](json& x) { x = x.get<double>() * t.scale; };
  json& cam = doc["camera"];
  point(cam["position"]);
  point(cam["look_at"]);
  if (cam.contains("focus_distance")) length(cam["focus_distance"]);
  if (cam.contains("aperture_radius")) length(cam["aperture_radius"]);
  const json steps = json::array({{{"scale", t.scale}}, {{"translate", {t.offset, t.offset, t.offset}}}});
  const auto append = [&](json& transform) {
    if (transform.is_null()) transform = json::array();
    for (const auto& s : steps) transform.push_back(s);
  };
  for (json& shape : doc["shapes"]) {
    // Motion keyframes apply after the shape's own transform: the similarity goes after them.
    if (shape.contains("motion")) {
      for (json& keyframe : shape["motion"]["transforms"]) append(keyframe);
    } else {
      append(shape["transform"]);
    }
    // A medium's coefficients are per unit length: they scale with 1/s, its optical depths not.
    if (shape.value("type", "") == "volume") {
      shape["sigma_a"] = shape.value("sigma_a", 0.0) / t.scale;
      shape["sigma_s"] = shape.value("sigma_s", 1.0) / t.scale;
    }
    // Noise is a function of the untransformed position; heights are in scene units.
    if (shape.contains("displacement")) {
      json& d = shape["displacement"];
      if (d.contains("offset")) length(d["offset"]);
      d["amplitude"] = d.value("amplitude", 1.0) * t.scale;
    }
  }
  if (doc.contains("lights")) {
    for (json& light : doc["lights"]) {
      const std::string type = light["type"];
      // Intensity over distance squared: intensities scale with s^2; radiance is unchanged.
      if (type == "point" || type == "spot") {
        point(light["position"]);
        if (light.contains("look_at")) point(light["look_at"]);
        for (auto& c : light["intensity"]) c = c.get<double>() * t.scale * t.scale;
      } else if (type == "rect") {
        point(light["corner"]);
        vector(light["edge_u"]);
        vector(light["edge_v"]);
      } else if (type == "disk") {
        point(light["center"]);
        length(light["radius"]);
      }
    }
  }
  return doc;
}

// The scene file at `path` under the similarity, parsed as if it were that file (relative
// file names still resolve next to it). Throws InputError where the loader refuses it.
inline Scene loadTransformedScene(const std::string& path, Similarity t) {
  const auto doc = transformedScene(nlohmann::json::parse(readTextFile(path, "scene file")), t);
  return parseScene(doc.dump(), path);
}

}  // namespace rayes::testing
