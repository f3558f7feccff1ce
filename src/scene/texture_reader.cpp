#include "scene/texture_reader.h"

namespace rayes {

ColorParam readColorParam(const JsonReader& r, const json& j, const std::string& ptr,
                          const std::filesystem::path& sceneDir, bool reflectance, Scene& scene) {
  if (!j.is_object()) return ColorParam(r.color(j, ptr, reflectance));
  const std::string type = r.string(r.member(j, ptr, "type"), ptr + "/type");
  auto tex = std::make_shared<Texture>();
  ColorParam c(Rgb{1, 1, 1});
  if (j.contains("scale")) {
    tex->scale = float(r.number(j["scale"], ptr + "/scale"));
    if (!(tex->scale > 0)) r.fail(ptr + "/scale", "the texture scale must be positive");
  }
  if (j.contains("coordinates")) {  // "patch" (the default) or "uv"
    const std::string coords = r.string(j["coordinates"], ptr + "/coordinates");
    if (coords == "uv") tex->coordinates = Texture::Coordinates::Uv;
    else if (coords != "patch") r.fail(ptr + "/coordinates", "unknown coordinates '" + coords + "' (expected patch or uv)");
  }
  if (type == "image") {
    r.object(j, ptr, {"type", "file", "scale", "tint", "coordinates"});
    const std::string f = r.string(r.member(j, ptr, "file"), ptr + "/file");
    const std::filesystem::path fp = std::filesystem::path(f).is_absolute() ? std::filesystem::path(f) : sceneDir / f;
    tex->kind = Texture::Kind::Image;
    try {
      tex->image = scene.textureCache().open(fp);
    } catch (const ResourceError&) {
      throw;
    } catch (const InputError& e) {
      r.fail(ptr + "/file", e.message());
    }
    if (reflectance) tex->maxValue = 1;
    if (j.contains("tint")) c.value = r.color(j["tint"], ptr + "/tint", reflectance);
  } else if (type == "checker" || type == "noise") {
    if (type == "checker") r.object(j, ptr, {"type", "colors", "scale", "coordinates"});
    else r.object(j, ptr, {"type", "colors", "scale", "octaves", "coordinates"});
    tex->kind = type == "checker" ? Texture::Kind::Checker : Texture::Kind::Noise;
    const json& cs = r.member(j, ptr, "colors");
    if (!cs.is_array() || cs.size() != 2) r.fail(ptr + "/colors", "expected two colours");
    tex->color0 = r.color(cs[0], ptr + "/colors/0", reflectance);
    tex->color1 = r.color(cs[1], ptr + "/colors/1", reflectance);
    if (j.contains("octaves")) {
      tex->octaves = r.integer(j["octaves"], ptr + "/octaves");
      if (tex->octaves < 1 || tex->octaves > 16) r.fail(ptr + "/octaves", "must be in [1, 16]");
    }
  } else {
    r.fail(ptr + "/type", "unknown texture type '" + type + "' (expected image, checker or noise)");
  }
  c.texture = tex;
  return c;
}

}  // namespace rayes
