// The "displacement" modifier of a shape (docs/scene-format.md, "displacement"):
//   {"type": "noise", "amplitude": a, "frequency": f, "octaves": n, "gain": g, "lacunarity": l,
//    "seed": s, "ridged": b, "offset": o}
//   {"type": "image", "file": "h.exr", "amplitude": a, "offset": o, "channel": "Y"}
// A height map's header is checked here with OpenEXR (the channel named or found); its texels
// are read through the scene's texture cache (geometry/displacement.h, HeightMap). Every error
// names the scene file, line:column and JSON pointer; an unreadable image also names the image.
#include <filesystem>
#include <functional>
#include <ImfChannelList.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <cstring>
#include "core/error.h"
#include "geometry/displaced_patch.h"
#include "geometry/displacement.h"
#include "scene/exr_input.h"
#include "scene/shape_kinds.h"

namespace rayes {

std::shared_ptr<const HeightMap> openHeightMap(const std::filesystem::path& path, std::string& name, Scene& scene,
                                               const std::function<void(const char*, const std::string&)>& fail) {
  // The header is read with OpenEXR first: its checks (a truncated file, a lying size) and the
  // choice of channel come before the texture cache converts anything.
  std::string failure;
  std::unique_ptr<Imf::InputFile> in;
  try {
    in = openExrInput(path, "height map");
  } catch (const InputError& e) {
    fail("file", e.message());
  }
  const Imf::ChannelList& channels = in->header().channels();
  if (name.empty()) {
    for (const char* c : {"Y", "R"})
      if (channels.findChannel(c)) { name = c; break; }
    if (name.empty() && channels.begin() != channels.end() && ++channels.begin() == channels.end())
      name = channels.begin().name();
    if (name.empty()) fail("file", "height map '" + path.string() + "' has no channel Y or R (name one with 'channel')");
  } else if (!channels.findChannel(name.c_str())) {
    fail("channel", "height map '" + path.string() + "' has no channel '" + name + "'");
  }
  in.reset();
  // The texels are paged through the scene's texture cache (a plain EXR is converted once to a
  // tiled MIP-mapped file, keeping its float or half texels); EXR rows run top to bottom and
  // v = 0 is the first row (docs/scene-format.md), as in the cache's t.
  std::shared_ptr<const TextureImage> image;
  try {
    image = scene.textureCache().open(path);
  } catch (const ResourceError&) {
    throw;
  } catch (const InputError& e) {
    if (e.file().rfind("--", 0) == 0) throw;  // the conversion folder, an option's fault
    fail("file", "cannot read height map '" + path.string() + "': " + e.message());
  }
  const int channel = image->channelIndex(name);
  if (channel < 0) fail("channel", "height map '" + path.string() + "' has no channel '" + name + "'");
  try {
    return std::make_shared<HeightMap>(image, channel);
  } catch (const InputError& e) {
    failure = e.message();
  } catch (const std::invalid_argument& e) {
    failure = e.what();
  }
  fail("file", "cannot read height map '" + path.string() + "': " + failure);
  throw std::logic_error("openHeightMap: fail returned");
}

DisplacementPtr readDisplacement(const ShapeContext& ctx, Scene& scene) {
  const JsonReader& r = ctx.reader;
  const std::string p = ctx.ptr + "/displacement";
  const json& d = ctx.shape.at("displacement");
  if (!d.is_object()) r.fail(p, "expected an object, got " + JsonReader::typeName(d));
  const std::string type = r.string(r.member(d, p, "type"), p + "/type");
  auto num = [&](const char* key, double fallback) {
    return d.contains(key) ? r.number(d[key], p + "/" + key) : fallback;
  };
  const double amplitude = num("amplitude", 1.0);
  const double offset = num("offset", 0.0);
  if (std::fabs(amplitude) > 1e30) r.fail(p + "/amplitude", "must be at most 1e30 in magnitude");
  if (std::fabs(offset) > 1e30) r.fail(p + "/offset", "must be at most 1e30 in magnitude");
  if (type == "noise") {
    r.object(d, p, {"type", "amplitude", "frequency", "octaves", "gain", "lacunarity", "seed", "ridged", "offset"});
    NoiseParams np;
    np.amplitude = float(amplitude);
    np.offset = float(offset);
    np.frequency = float(num("frequency", 1.0));
    if (!(np.frequency > 0) || np.frequency > 1e30f) r.fail(p + "/frequency", "must be > 0 (lattice cells per unit length)");
    np.octaves = d.contains("octaves") ? r.integer(d["octaves"], p + "/octaves") : 4;
    if (np.octaves < 1 || np.octaves > 16) r.fail(p + "/octaves", "must be in 1..16");
    np.gain = float(num("gain", 0.5));
    if (!(np.gain > 0 && np.gain <= 1)) r.fail(p + "/gain", "must be in (0, 1]");
    np.lacunarity = float(num("lacunarity", 2.0));
    if (!(np.lacunarity >= 1 && np.lacunarity <= 4)) r.fail(p + "/lacunarity", "must be in [1, 4]");
    if (d.contains("seed")) {
      const int s = r.integer(d["seed"], p + "/seed");
      if (s < 0) r.fail(p + "/seed", "must be >= 0");
      np.seed = uint32_t(s);
    }
    np.ridged = d.contains("ridged") ? r.boolean(d["ridged"], p + "/ridged") : false;
    return std::make_shared<NoiseDisplacement>(np);
  }
  if (type == "image") {
    r.object(d, p, {"type", "file", "amplitude", "offset", "channel"});
    const std::string f = r.string(r.member(d, p, "file"), p + "/file");
    const std::filesystem::path fp = std::filesystem::path(f).is_absolute() ? std::filesystem::path(f) : ctx.sceneDir / f;
    if (!std::filesystem::exists(fp)) r.fail(p + "/file", "cannot open height map '" + fp.string() + "'");
    if (std::filesystem::is_directory(fp)) r.fail(p + "/file", "height map '" + fp.string() + "' is a directory");
    std::string channel = d.contains("channel") ? r.string(d["channel"], p + "/channel") : "";
    auto map = openHeightMap(fp, channel, scene, [&](const char* key, const std::string& why) { r.fail(p + "/" + key, why); });
    return std::make_shared<HeightMapDisplacement>(std::move(map), float(amplitude), float(offset), HeightMapOrigin{f, channel});
  }
  r.fail(p + "/type", "unknown displacement type '" + type + "' (expected image, noise)");
}

std::vector<PatchPtr> displacePatches(const DisplacementPtr& d, const ShapeSource& source, const TransformD& xf,
                                      std::vector<PatchPtr> patches) {
  if (!d) return patches;
  const bool transformed = !xf.isIdentity();
  const std::vector<PatchPtr> reference = transformed ? source.build(TransformD{}) : patches;
  for (size_t k = 0; k < patches.size(); ++k)
    patches[k] = std::make_shared<DisplacedPatch>(patches[k], d, transformed ? reference[k] : nullptr);
  return patches;
}

}  // namespace rayes
