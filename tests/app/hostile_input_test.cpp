// The hostile-input catalogue: every row is a set of files, a command line and the message it
// must give. Each must end with exit code 2, one message naming the file (or option) and the
// place, never an internal error or a library's stray line, and nothing left in the folder
// but the inputs: no output, no temporary, no folder created for outputs.
//
// "$D" in arguments and expected text stands for the row's temporary folder.
#include <sys/stat.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include "app/image_io.h"
#include "support/render_fixtures.h"
#include "support/exr_test_file.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {

// A file to create: `content` as bytes, or a folder when `folder` is set, or a FIFO (a named
// pipe nobody writes to: opening it to read would block forever) when `fifo` is set.
struct InputFile {
  std::string name, content;
  bool folder = false, fifo = false;
};

struct HostileCase {
  const char* name;
  std::vector<InputFile> files;
  std::vector<std::string> args;  // after "rayes"; empty: render $D/s.json -o $D/out/o.exr -q
  std::string place;              // e.g. "s.json:2:13": the file and the place
  std::string message;            // a fragment of what is wrong
};

std::ostream& operator<<(std::ostream& os, const HostileCase& c) { return os << c.name; }

// The scene of the catalogue, one section per line so that rows can name the line: camera on
// line 2, film 3, integrator 4, materials 5, shapes 6, lights 7. A section given as "" is left out.
struct SceneParts {
  std::string camera = R"({"position": [0, -3, 1], "look_at": [0, 0, 0], "up": [0, 0, 1], "fov": 40})";
  std::string film = R"({"resolution": [8, 6], "spp": 1})";
  std::string integrator = R"({"max_depth": 2})";
  std::string materials = R"({"m": {"type": "diffuse", "albedo": 0.5}})";
  std::string shapes = R"([{"type": "bilinear", "material": "m", "quads": [[[-1,-1,0],[1,-1,0],[-1,1,0],[1,1,0]]]}])";
  std::string lights = R"([{"type": "point", "position": [0, -2, 3], "intensity": [5, 5, 5]}])";
  std::string text() const {
    std::string s = "{\n";
    const std::pair<const char*, const std::string*> sections[] = {
        {"camera", &camera}, {"film", &film}, {"integrator", &integrator},
        {"materials", &materials}, {"shapes", &shapes}, {"lights", &lights}};
    bool first = true;
    for (const auto& [key, value] : sections) {
      s += first ? "" : ",\n";
      first = false;
      s += std::string("  \"") + key + "\": " + *value;
    }
    return s + "\n}\n";
  }
};

// The column where each section's value starts on its line.
constexpr int kCameraCol = 13, kFilmCol = 11, kIntegratorCol = 17, kMaterialsCol = 16, kShapesCol = 13;

InputFile scene(SceneParts p) { return {"s.json", p.text()}; }
InputFile withCamera(const std::string& v) { SceneParts p; p.camera = v; return scene(p); }
InputFile withFilm(const std::string& v) { SceneParts p; p.film = v; return scene(p); }
InputFile withIntegrator(const std::string& v) { SceneParts p; p.integrator = v; return scene(p); }
InputFile withMaterials(const std::string& v) { SceneParts p; p.materials = v; return scene(p); }
InputFile withShapes(const std::string& v) { SceneParts p; p.shapes = v; return scene(p); }
InputFile withLights(const std::string& v) { SceneParts p; p.lights = v; return scene(p); }
InputFile validScene() { return scene(SceneParts{}); }
InputFile folder(const std::string& name) { return {name, "", true}; }
InputFile fifo(const std::string& name) { return {name, "", false, true}; }

template <size_t N>
std::string bytes(const char (&a)[N]) { return std::string(a, N - 1); }
// A valid 1x1 RGBA PNG, and the same with its header (correct CRC) claiming 16384x16384.
const std::string kPng1x1 = bytes(
    "\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x00\x01\x00\x00\x00\x01\x08\x06\x00"
    "\x00\x00\x1f\x15\xc4\x89\x00\x00\x00\x0d\x49\x44\x41\x54\x78\xda\x63\x64\x60\xf8\x5f\x0f\x00\x02\x87\x01\x80"
    "\xeb\x47\xba\x92\x00\x00\x00\x00\x49\x45\x4e\x44\xae\x42\x60\x82");
const std::string kPngHuge = bytes(
    "\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x40\x00\x00\x00\x40\x00\x08\x06\x00"
    "\x00\x00\xa9\xc8\x10\x84\x00\x00\x00\x0d\x49\x44\x41\x54\x78\xda\x63\x64\x60\xf8\x5f\x0f\x00\x02\x87\x01\x80"
    "\xeb\x47\xba\x92\x00\x00\x00\x00\x49\x45\x4e\x44\xae\x42\x60\x82");

// A valid 16x16 single-channel EXR (channel `channel`), written through OpenEXR.
std::string writeExrBytes(const char* channel) {
  const testing::TempFolder scratch;
  const std::string path = scratch.path("x.exr");
  testing::writeOneChannelExr(path, 16, 16, channel, std::vector<float>(16 * 16, 0.25f));
  return scratch.read("x.exr");
}
std::string exrBytes(const char* channel) {
  static std::map<std::string, std::string> made;
  auto it = made.find(channel);
  if (it == made.end()) it = made.emplace(channel, writeExrBytes(channel)).first;
  return it->second;
}
std::string halfOf(const std::string& file) { return file.substr(0, file.size() / 2); }
// A black 8x6 render as the program writes it: a valid reference for the catalogue's scene.
std::string referenceBytes() {
  const testing::TempFolder scratch;
  writeExr(scratch.path("ref.exr"), Film(8, 6));
  return scratch.read("ref.exr");
}
// An RGB EXR of w x h pixels, every value `v`.
std::string rgbExrBytes(int w, int h, float v) {
  const testing::TempFolder scratch;
  testing::writeRgbExr(scratch.path("x.exr"), w, h, std::vector<float>(size_t(w) * size_t(h) * 3, v));
  return scratch.read("x.exr");
}
std::vector<std::string> convergeWith(std::vector<std::string> extra) {
  std::vector<std::string> args = {"converge", "$D/s.json", "--reference", "$D/ref.exr", "--budget", "1",
                                   "-o", "$D/out/c.csv", "-q"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}
// The same EXR with its data window widened to 60000x60000 (the file still holds 16x16).
std::string exrLyingAboutItsSize(std::string exr) {
  const std::string key = bytes("dataWindow\0box2i\0");
  const size_t at = exr.find(key);
  if (at == std::string::npos) return "";
  const int32_t box[4] = {0, 0, 59999, 59999};
  exr.replace(at + key.size() + 4, 16, std::string(reinterpret_cast<const char*>(box), 16));
  return exr;
}

const std::string kBptOne =
    "1\n1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16\n16\n"
    "0,0,0\n1,0,0\n2,0,0\n3,0,0\n0,1,0\n1,1,0\n2,1,0\n3,1,0\n0,2,0\n1,2,0\n2,2,0\n3,2,0\n0,3,0\n1,3,0\n2,3,0\n3,3,0\n";
InputFile bptShapeScene() { return withShapes(R"([{"type": "bezier", "material": "m", "file": "p.bpt"}])"); }
InputFile objShapeScene() { return withShapes(R"([{"type": "subdiv", "material": "m", "file": "m.obj"}])"); }
const std::string kCubeObj =
    "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
InputFile textureScene(const std::string& file) {
  return withMaterials(R"({"m": {"type": "diffuse", "albedo": {"type": "image", "file": ")" + file + R"("}}})");
}
InputFile heightMapScene(const std::string& file) {
  return withShapes(R"([{"type": "bilinear", "material": "m", "quads": [[[-1,-1,0],[1,-1,0],[-1,1,0],[1,1,0]]], )"
                    R"("displacement": {"type": "image", "file": ")" + file + R"("}}])");
}

// A forest shape of one small tree with `extra` keys.
std::string forestShape(const std::string& extra) {
  return R"([{"type": "forest", "materials": {"terrain": "m", "bark": "m", "foliage": "m"}, )" + extra +
         "}]";
}

std::vector<std::string> renderWith(std::vector<std::string> extra) {
  std::vector<std::string> args = {"render", "$D/s.json", "-o", "$D/out/o.exr", "-q"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

std::string nested(const std::string& open, const std::string& close, int depth) {
  std::string s;
  s.reserve(size_t(depth) * (open.size() + close.size()));
  for (int k = 0; k < depth; ++k) s += open;
  for (int k = 0; k < depth; ++k) s += close;
  return s;
}

std::string col(int line, int column) { return "s.json:" + std::to_string(line) + ":" + std::to_string(column); }

std::vector<HostileCase> catalogue() {
  const std::string pos = R"("position": [0, -3, 1], "look_at": [0, 0, 0])";
  std::vector<HostileCase> c = {
      // --- the scene file itself: missing, a folder, empty, encodings
      {"SceneMissing", {}, {}, "$D/s.json", "cannot open scene file: No such file or directory"},
      {"SceneIsAFolder", {folder("s.json")}, {}, "$D/s.json", "scene file is a directory"},
      {"SceneEmpty", {{"s.json", ""}}, {}, "s.json:1:1", "JSON syntax error"},
      // Inputs must be regular files: a FIFO blocks the reader forever, /dev/zero never ends.
      {"SceneIsAFifo", {fifo("s.json")}, {}, "$D/s.json", "scene file is not a regular file"},
      {"SceneIsDevZero", {}, {"render", "/dev/zero", "-o", "$D/out/o.exr", "-q"}, "/dev/zero",
       "scene file is not a regular file"},
      {"SceneBlank", {{"s.json", "  \n\n"}}, {}, "s.json:3:1", "JSON syntax error"},
      {"SceneTruncated", {{"s.json", "{\n  \"camera\": {\"position\": [0, "}}, {}, "s.json:2:", "JSON syntax error"},
      {"SceneTrailingComma", {{"s.json", "{\n  \"camera\": {},\n}"}}, {}, "s.json:3:1", "JSON syntax error"},
      {"SceneComment", {{"s.json", "{\n  // a comment\n}"}}, {}, "s.json:2:3", "JSON syntax error"},
      {"SceneSingleQuotes", {{"s.json", "{\n  'camera': {}\n}"}}, {}, "s.json:2:3", "JSON syntax error"},
      {"SceneNaNLiteral", {withCamera("{\"fov\": NaN}")}, {}, "s.json:2:", "JSON syntax error"},
      {"SceneInfinityLiteral", {withCamera("{\"fov\": Infinity}")}, {}, "s.json:2:", "JSON syntax error"},
      {"SceneGarbageAfterDocument", {{"s.json", validScene().content + "x"}}, {}, "s.json:9:1", "JSON syntax error"},
      {"SceneBinaryZeros", {{"s.json", std::string(64, '\0')}}, {}, "s.json:1:1", "JSON syntax error"},
      {"SceneUtf16Bom", {{"s.json", bytes("\xff\xfe{\0}\0")}}, {}, "s.json:1:1", "JSON syntax error"},
      {"SceneBomThenWrongType", {{"s.json", "\xEF\xBB\xBF" + withCamera("[]").content}}, {}, col(2, kCameraCol),
       "/camera: expected an object, got array"},
      {"SceneBomThenSyntaxError", {{"s.json", "\xEF\xBB\xBF{\n  \"camera\" {}\n}"}}, {}, "s.json:2:12", "JSON syntax error"},
      {"SceneInvalidUtf8InString", {withMaterials("{\"m\xff\": {\"type\": \"diffuse\"}}")}, {}, "s.json:5:", "JSON syntax error"},
      {"SceneControlCharInString", {withMaterials("{\"m\x01\": {\"type\": \"diffuse\"}}")}, {}, "s.json:5:", "JSON syntax error"},
      {"SceneTopLevelArray", {{"s.json", "[1, 2]"}}, {}, "s.json:1:1", "/: expected an object, got array"},
      {"SceneTopLevelString", {{"s.json", "\"scene\""}}, {}, "s.json:1:1", "/: expected an object, got string"},
      {"SceneUnknownSection", {{"s.json", "{\n  \"cameras\": {}\n}"}}, {}, "s.json:2:14", "unknown key 'cameras'"},
      {"SceneMissingCamera", {{"s.json", "{\n  \"materials\": {}\n}"}}, {}, "s.json:1:1", "missing required key 'camera'"},
      // --- duplicate keys
      {"DuplicateTopLevelKey", {{"s.json", validScene().content.substr(0, validScene().content.size() - 3) +
                                              ",\n  \"film\": {}\n}\n"}}, {}, "s.json:8:3", "key 'film' appears twice"},
      {"DuplicateNestedKey", {withCamera(R"({"fov": 40, "fov": 50})")}, {}, col(2, kCameraCol + 12),
       "key 'fov' appears twice"},
      {"DuplicateKeySpelledWithEscape", {withCamera(R"({"fov": 40, "f\u006fv": 50})")}, {}, col(2, kCameraCol + 12),
       "key 'fov' appears twice"},
      {"DuplicateMaterialName", {withMaterials(R"({"m": {"type": "diffuse"}, "m": {"type": "diffuse"}})")}, {},
       col(5, kMaterialsCol + 27), "key 'm' appears twice"},
      // --- deep nesting and huge numbers
      {"CameraNested100kArrays", {withCamera(nested("[", "]", 100000))}, {}, col(2, kCameraCol),
       "/camera: expected an object, got array"},
      {"CameraNested100kObjects", {withCamera(nested("{\"a\":", "}", 100000).insert(500000, "1"))}, {},
       col(2, kCameraCol + 5), "/camera/a: unknown key 'a'"},
      {"ShapesNested100kArrays", {withShapes(nested("[", "]", 100000))}, {}, col(6, kShapesCol + 1),
       "/shapes/0: expected an object"},
      {"NumberOverflowsDouble", {withCamera(R"({"fov": 1e999})")}, {}, "s.json:2:", "number overflow parsing '1e999'"},
      {"NegativeNumberOverflowsDouble", {withFilm(R"({"spp": -1e999})")}, {}, "s.json:3:", "number overflow"},
      {"NumberBeyondFloat", {withCamera(R"({)" + pos + R"(, "fov": 1e300})")}, {}, "s.json:2:", "number out of range"},
      {"IntegerBeyondInt64", {withFilm(R"({"spp": 99999999999999999999999})")}, {}, col(3, kFilmCol + 8),
       "/film/spp: expected an integer"},
      {"IntegerBeyondRange", {withFilm(R"({"spp": 9999999999})")}, {}, col(3, kFilmCol + 8), "integer out of range"},
      {"CoordinateBeyondFloat", {withCamera(R"({"position": [0, -3e39, 1], "look_at": [0, 0, 0]})")}, {},
       col(2, kCameraCol + 17), "/camera/position/1: number out of range"},
      // --- wrong types and impossible values, section by section
      {"CameraIsArray", {withCamera("[1, 2, 3]")}, {}, col(2, kCameraCol), "/camera: expected an object, got array"},
      {"CameraIsNull", {withCamera("null")}, {}, col(2, kCameraCol), "/camera: expected an object, got null"},
      {"CameraIsString", {withCamera("\"front\"")}, {}, col(2, kCameraCol), "expected an object, got string"},
      {"CameraPositionIsString", {withCamera(R"({"position": "here", "look_at": [0, 0, 0]})")}, {},
       col(2, kCameraCol + 13), "/camera/position: expected an array of 3 numbers"},
      {"CameraPositionTwoNumbers", {withCamera(R"({"position": [1, 2], "look_at": [0, 0, 0]})")}, {},
       col(2, kCameraCol + 13), "/camera/position: expected an array of 3 numbers"},
      {"CameraPositionHasBoolean", {withCamera(R"({"position": [1, true, 2], "look_at": [0, 0, 0]})")}, {},
       col(2, kCameraCol + 17), "/camera/position/1: expected a number, got boolean"},
      {"CameraLookAtMissing", {withCamera(R"({"position": [0, 0, 1]})")}, {}, col(2, kCameraCol),
       "missing required key 'look_at'"},
      {"CameraLookAtEqualsPosition", {withCamera(R"({"position": [1, 1, 1], "look_at": [1, 1, 1]})")}, {},
       col(2, kCameraCol + 35), "/camera/look_at: look_at equals position"},
      {"CameraUpZero", {withCamera("{" + pos + R"(, "up": [0, 0, 0]})")}, {}, col(2, kCameraCol + 53),
       "/camera/up: the up vector must not be zero"},
      {"CameraUpAlongView", {withCamera("{" + pos + R"(, "up": [0, 3, -1]})")}, {}, col(2, kCameraCol + 53),
       "looks along its up vector"},
      {"CameraFovZero", {withCamera("{" + pos + R"(, "fov": 0})")}, {}, col(2, kCameraCol + 54), "/camera/fov"},
      {"CameraFov180", {withCamera("{" + pos + R"(, "fov": 180})")}, {}, col(2, kCameraCol + 54), "in (0, 180)"},
      {"CameraFovString", {withCamera("{" + pos + R"(, "fov": "wide"})")}, {}, col(2, kCameraCol + 54),
       "expected a number, got string"},
      {"CameraNegativeAperture", {withCamera("{" + pos + R"(, "aperture_radius": -1})")}, {}, col(2, kCameraCol + 66),
       "must not be negative"},
      {"CameraZeroFocusDistance", {withCamera("{" + pos + R"(, "focus_distance": 0})")}, {}, col(2, kCameraCol + 65),
       "the focus distance must be positive"},
      {"CameraShutterBackwards", {withCamera("{" + pos + R"(, "shutter": [1, 0]})")}, {}, col(2, kCameraCol + 58),
       "closes before it opens"},
      {"CameraShutterNotPair", {withCamera("{" + pos + R"(, "shutter": 1})")}, {}, col(2, kCameraCol + 58),
       "expected [open, close]"},
      {"CameraUnknownKey", {withCamera("{" + pos + R"(, "zoom": 2})")}, {}, col(2, kCameraCol + 55),
       "unknown key 'zoom'"},
      {"FilmIsArray", {withFilm("[8, 6]")}, {}, col(3, kFilmCol), "/film: expected an object, got array"},
      {"FilmResolutionZero", {withFilm(R"({"resolution": [0, 6]})")}, {}, col(3, kFilmCol + 15),
       "width and height must be positive"},
      {"FilmResolutionHuge", {withFilm(R"({"resolution": [70000, 70000]})")}, {}, col(3, kFilmCol + 15),
       "more than 2^28 pixels"},
      {"FilmResolutionFraction", {withFilm(R"({"resolution": [8.5, 6]})")}, {}, col(3, kFilmCol + 16),
       "/film/resolution/0: expected an integer"},
      {"FilmResolutionString", {withFilm(R"({"resolution": "8x6"})")}, {}, col(3, kFilmCol + 15),
       "expected [width, height]"},
      {"FilmSppZero", {withFilm(R"({"spp": 0})")}, {}, col(3, kFilmCol + 8), "samples per pixel must be positive"},
      {"FilmSppNegative", {withFilm(R"({"spp": -4})")}, {}, col(3, kFilmCol + 8), "must be positive"},
      {"FilmSppFraction", {withFilm(R"({"spp": 1.5})")}, {}, col(3, kFilmCol + 8), "expected an integer, got number"},
      {"IntegratorIsString", {withIntegrator("\"path\"")}, {}, col(4, kIntegratorCol), "expected an object"},
      {"IntegratorDepthNegative", {withIntegrator(R"({"max_depth": -1})")}, {}, col(4, kIntegratorCol + 14),
       "must be in [0, 1000]"},
      {"IntegratorDepthHuge", {withIntegrator(R"({"max_depth": 5000})")}, {}, col(4, kIntegratorCol + 14),
       "must be in [0, 1000]"},
      {"IntegratorSeedNegative", {withIntegrator(R"({"seed": -5})")}, {}, col(4, kIntegratorCol + 9),
       "/integrator/seed: must not be negative"},
      {"IntegratorRouletteNegative", {withIntegrator(R"({"roulette_depth": -1})")}, {},
       col(4, kIntegratorCol + 19), "must not be negative"},
      {"IntegratorUnknownKey", {withIntegrator(R"({"bounces": 3})")}, {}, col(4, kIntegratorCol + 12),
       "unknown key 'bounces'"},
      {"MaterialsIsArray", {withMaterials("[]")}, {}, col(5, kMaterialsCol), "/materials: expected an object"},
      {"MaterialIsNumber", {withMaterials(R"({"m": 1})")}, {}, col(5, kMaterialsCol + 6), "/materials/m"},
      {"MaterialUnknownType", {withMaterials(R"({"m": {"type": "velvet"}})")}, {}, col(5, kMaterialsCol + 15),
       "velvet"},
      {"MaterialAlbedoAboveOne", {withMaterials(R"({"m": {"type": "diffuse", "albedo": 2}})")}, {},
       col(5, kMaterialsCol + 36), "a reflectance above 1 would create energy"},
      {"MaterialAlbedoNegative", {withMaterials(R"({"m": {"type": "diffuse", "albedo": [0.5, -1, 0]}})")}, {},
       col(5, kMaterialsCol + 36), "must not be negative"},
      {"MaterialAlbedoNull", {withMaterials(R"({"m": {"type": "diffuse", "albedo": null}})")}, {},
       col(5, kMaterialsCol + 36), "/materials/m/albedo"},
      {"MaterialUnknownKey", {withMaterials(R"({"m": {"type": "diffuse", "colour": 1}})")}, {},
       col(5, kMaterialsCol + 36), "unknown key 'colour'"},
      {"MaterialNegativeRoughness", {withMaterials(R"({"m": {"type": "conductor", "metal": "gold", "roughness": -1}})")},
       {}, col(5, kMaterialsCol + 58), "/materials/m/roughness"},
      {"MaterialIorZero", {withMaterials(R"({"m": {"type": "dielectric", "ior": 0}})")}, {},
       col(5, kMaterialsCol + 36), "/materials/m/ior"},
      {"TextureUnknownType", {withMaterials(R"({"m": {"type": "diffuse", "albedo": {"type": "marble"}}})")}, {},
       col(5, kMaterialsCol + 45), "unknown texture type 'marble'"},
      {"TextureOctavesZero", {withMaterials(R"({"m": {"type": "diffuse", "albedo": {"type": "noise", )"
                                            R"("colors": [0, 1], "octaves": 0}}})")},
       {}, "s.json:5:", "/materials/m/albedo/octaves: must be in [1, 16]"},
      {"ShapesIsObject", {withShapes("{}")}, {}, col(6, kShapesCol), "/shapes"},
      {"ShapesEmpty", {withShapes("[]")}, {}, col(6, kShapesCol), "/shapes"},
      {"ShapeIsNumber", {withShapes("[1]")}, {}, col(6, kShapesCol + 1), "/shapes/0"},
      {"ShapeUnknownType", {withShapes(R"([{"type": "nurbs", "material": "m"}])")}, {}, col(6, kShapesCol + 10),
       "nurbs"},
      {"ShapeMissingMaterial", {withShapes(R"([{"type": "bilinear", "quads": []}])")}, {}, "s.json:6:",
       "/shapes/0"},
      {"ShapeUnknownMaterial", {withShapes(R"([{"type": "bilinear", "material": "x", "quads": [[[-1,-1,0],[1,-1,0],[-1,1,0],[1,1,0]]]}])")}, {},
       col(6, kShapesCol + 34), "no material named 'x'"},
      {"BilinearQuadThreeCorners", {withShapes(R"([{"type": "bilinear", "material": "m", "quads": [[[0,0,0],[1,0,0],[0,1,0]]]}])")},
       {}, "s.json:6:", "/shapes/0/quads/0"},
      {"BilinearCornerNaNString", {withShapes(R"([{"type": "bilinear", "material": "m", "quads": [[[0,0,"nan"],[1,0,0],[0,1,0],[1,1,0]]]}])")},
       {}, "s.json:6:", "/shapes/0/quads/0/0/2: expected a number, got string"},
      {"BilinearCornerBeyondFloat", {withShapes(R"([{"type": "bilinear", "material": "m", "quads": [[[0,0,1e39],[1,0,0],[0,1,0],[1,1,0]]]}])")},
       {}, "s.json:6:", "/shapes/0/quads/0/0/2: number out of range"},
      {"BezierBothFileAndPatches", {withShapes(R"([{"type": "bezier", "material": "m", "file": "p.bpt", "patches": []}])")},
       {}, col(6, kShapesCol + 1), "exactly one of 'file' and 'patches'"},
      {"BezierPatchFifteenPoints", {withShapes(R"([{"type": "bezier", "material": "m", "patches": [[[0,0,0]]]}])")},
       {}, "s.json:6:", "/shapes/0/patches/0: expected 16 control points"},
      {"SubdivFaceOutOfRange", {withShapes(R"([{"type": "subdiv", "material": "m", "vertices": [[0,0,0],[1,0,0],[0,1,0]], "faces": [[0,1,7]]}])")},
       {}, "s.json:6:", "/shapes/0"},
      {"TransformUnknownStep", {withShapes(R"([{"type": "bilinear", "material": "m", "quads": [[[-1,-1,0],[1,-1,0],[-1,1,0],[1,1,0]]], "transform": [{"shear": 1}]}])")},
       {}, "s.json:6:", "/shapes/0/transform/0"},
      {"TransformZeroScale", {withShapes(R"([{"type": "bilinear", "material": "m", "quads": [[[-1,-1,0],[1,-1,0],[-1,1,0],[1,1,0]]], "transform": [{"scale": 0}]}])")},
       {}, "s.json:6:", "/shapes/0/transform/0"},
      {"TransformSingularMatrix", {withShapes(R"([{"type": "bilinear", "material": "m", "quads": [[[-1,-1,0],[1,-1,0],[-1,1,0],[1,1,0]]], "transform": [{"matrix": [0,0,0,0, 0,0,0,0, 0,0,0,0]}]}])")},
       {}, "s.json:6:", "/shapes/0/transform/0"},
      {"MotionIsNumber", {withShapes(R"([{"type": "bilinear", "material": "m", "quads": [[[-1,-1,0],[1,-1,0],[-1,1,0],[1,1,0]]], "motion": 3}])")},
       {}, "s.json:6:", "/shapes/0/motion"},
      // The forest: refused before anything is grown (a leaf count beyond what memory could describe
      // is found by Forest::leafCount, without growing a tree).
      {"ForestNegativeTreeCount", {withShapes(forestShape(R"("trees": -1)"))}, {}, "s.json:6:",
       "/shapes/0/trees: must be in [0, 16777216]"},
      {"ForestTreesNotANumber", {withShapes(forestShape(R"("trees": "many")"))}, {}, "s.json:6:",
       "/shapes/0/trees: expected an integer, got string"},
      {"ForestAbsurdDetail", {withShapes(forestShape(R"("trees": 16777216, "detail": 8, "branching": 6)"))}, {},
       "s.json:6:", "a scene holds at most 2^32 leaves"},
      {"ForestDetailOutOfRange", {withShapes(forestShape(R"("detail": 9)"))}, {}, "s.json:6:",
       "/shapes/0/detail: must be in [0, 8]"},
      {"ForestFractionalSeed", {withShapes(forestShape(R"("seed": 1.5)"))}, {}, "s.json:6:",
       "/shapes/0/seed: expected a non-negative integer"},
      {"ForestUnknownPartMaterial", {withShapes(R"([{"type": "forest", "materials": {"terrain": "m", "bark": "x", "foliage": "m"}}])")},
       {}, "s.json:6:", "/shapes/0/materials/bark: no material named 'x'"},
      {"ForestShearedTransform", {withShapes(forestShape(R"("transform": [{"matrix": [1,0.5,0,0, 0,1,0,0, 0,0,1,0]}])"))},
       {}, "s.json:6:", "/shapes/0/transform: a forest takes only rotations, uniform scales and translations"},
      {"ForestUnequalScale", {withShapes(forestShape(R"("transform": [{"scale": [1, 2, 1]}])"))}, {}, "s.json:6:",
       "/shapes/0/transform: a forest takes only rotations, uniform scales and translations"},
      {"ForestMirrored", {withShapes(forestShape(R"("transform": [{"scale": [-1, 1, 1]}])"))}, {}, "s.json:6:",
       "/shapes/0/transform: the placement must keep orientation"},
      {"DisplacementUnknownType", {withShapes(R"([{"type": "bilinear", "material": "m", "quads": [[[-1,-1,0],[1,-1,0],[-1,1,0],[1,1,0]]], "displacement": {"type": "wave"}}])")},
       {}, "s.json:6:", "/shapes/0/displacement/type"},
      {"DisplacementNaNFrequency", {withShapes(R"([{"type": "bilinear", "material": "m", "quads": [[[-1,-1,0],[1,-1,0],[-1,1,0],[1,1,0]]], "displacement": {"type": "noise", "frequency": 0}}])")},
       {}, "s.json:6:", "/shapes/0/displacement/frequency"},
      {"LightsIsObject", {withLights("{}")}, {}, "s.json:7:", "/lights"},
      {"LightUnknownType", {withLights(R"([{"type": "laser"}])")}, {}, "s.json:7:", "laser"},
      {"LightNegativeIntensity", {withLights(R"([{"type": "point", "position": [0, 0, 1], "intensity": [-1, 0, 0]}])")},
       {}, "s.json:7:", "/lights/0/intensity"},
      // --- files the scene names: .bpt, .obj, textures, height maps
      {"BptMissing", {bptShapeScene()}, {}, col(6, kShapesCol + 45), "cannot open file"},
      {"BptIsAFolder", {bptShapeScene(), folder("p.bpt")}, {}, col(6, kShapesCol + 45), "is a directory"},
      {"BptIsAFifo", {bptShapeScene(), fifo("p.bpt")}, {}, "$D/p.bpt", "Bézier patch file is not a regular file"},
      {"BptClaims1e8Patches", {bptShapeScene(), {"p.bpt", "100000000\n1,1,1\n2\n"}}, {}, "p.bpt:line 1",
       "claims 100000000 patches"},
      {"BptClaimsTooManyPoints", {bptShapeScene(), {"p.bpt", "1\n1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16\n99999\n0,0,0\n"}},
       {}, "p.bpt:line 3", "claims 99999 points"},
      {"BptTruncated", {bptShapeScene(), {"p.bpt", kBptOne.substr(0, kBptOne.size() - 20)}}, {}, "p.bpt:line 16",
       "malformed number"},
      {"BptIndexOutOfRange", {bptShapeScene(), {"p.bpt", "1\n1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,99\n" +
                                                          kBptOne.substr(kBptOne.find("\n16\n") + 1)}},
       {}, "p.bpt:line 2", "control-point index 99 out of range"},
      {"BptNaNCoordinate", {bptShapeScene(), {"p.bpt", kBptOne.substr(0, kBptOne.size() - 6) + "3,nan,0\n"}}, {},
       "p.bpt:line 19", "non-finite coordinate"},
      {"BptHugeCoordinate", {bptShapeScene(), {"p.bpt", kBptOne.substr(0, kBptOne.size() - 6) + "3,1e39,0\n"}}, {},
       "p.bpt:line 19", "number '1e39' is out of range"},
      {"BptBinaryGarbage", {bptShapeScene(), {"p.bpt", kPng1x1}}, {}, "p.bpt:line 1", "malformed number"},
      {"ObjMissing", {objShapeScene()}, {}, col(6, kShapesCol + 45), "cannot open file"},
      {"ObjIsAFolder", {objShapeScene(), folder("m.obj")}, {}, col(6, kShapesCol + 45), "is a directory"},
      {"ObjIsAFifo", {objShapeScene(), fifo("m.obj")}, {}, "$D/m.obj", "OBJ file is not a regular file"},
      {"ObjFaceIndexOutOfRange", {objShapeScene(), {"m.obj", kCubeObj + "f 1 2 99\n"}}, {}, "m.obj:line 15",
       "vertex index 99 out of range"},
      {"ObjTagLiesAboutItsCounts", {objShapeScene(), {"m.obj", kCubeObj + "t crease 1000000/1/0 0 1 2\n"}}, {},
       "m.obj:line 15", "declares 1000001 arguments but has 3"},
      {"ObjHugeCoordinate", {objShapeScene(), {"m.obj", "v 1e39 0 0\n" + kCubeObj}}, {}, "m.obj:line 1",
       "number '1e39' is out of range for a float"},
      {"ObjMalformedNumber", {objShapeScene(), {"m.obj", "v 1 2 x\n" + kCubeObj}}, {}, "m.obj:line 1",
       "malformed number 'x'"},
      {"ObjNaNCoordinate", {objShapeScene(), {"m.obj", "v nan 0 0\n" + kCubeObj}}, {}, "m.obj:line 1",
       "number 'nan' is not finite"},
      {"ObjInfiniteCoordinate", {objShapeScene(), {"m.obj", "v 0 -inf 0\n" + kCubeObj}}, {}, "m.obj:line 1",
       "number '-inf' is not finite"},
      {"ObjZeroWeight", {objShapeScene(), {"m.obj", "v 1 1 1 0\n" + kCubeObj}}, {}, "m.obj:line 1",
       "vertex weight w must not be zero"},
      {"ObjUnknownStatement", {objShapeScene(), {"m.obj", kCubeObj + "curv 1 2\n"}}, {}, "m.obj:line 15",
       "unsupported OBJ statement 'curv'"},
      {"ObjIndexBeyondInt", {objShapeScene(), {"m.obj", kCubeObj + "f 1 2 99999999999999\n"}}, {}, "m.obj:line 15",
       "out of range"},
      // --- uv sets (OBJ vt, inline uvs, patch corners) and a texture's coordinates
      {"ObjVtIndexOutOfRange", {objShapeScene(), {"m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/7\n"}}, {},
       "m.obj:line 5", "texture coordinate index 7 out of range"},
      {"ObjVtNaN", {objShapeScene(), {"m.obj", "vt nan 0\n" + kCubeObj}}, {}, "m.obj:line 1", "number 'nan' is not finite"},
      {"ObjVtOnSomeCorners", {objShapeScene(), {"m.obj", "vt 0 0\n" + kCubeObj + "f 1/1 2 3/1\n"}}, {}, "m.obj:line 16",
       "some corners of this face have a texture coordinate"},
      {"InlineUvCountWrong",
       {withShapes(R"([{"type": "subdiv", "material": "m", "vertices": [[0,0,0],[1,0,0],[1,1,0]], "faces": [[0,1,2]], "uvs": [[0,0]]}])")},
       {}, "s.json:6:", "/shapes/0/uvs: without 'uv_faces', one uv per vertex"},
      {"InlineUvIndexOutOfRange",
       {withShapes(R"([{"type": "subdiv", "material": "m", "vertices": [[0,0,0],[1,0,0],[1,1,0]], "faces": [[0,1,2]], "uvs": [[0,0]], "uv_faces": [[0,0,1]]}])")},
       {}, "s.json:6:", "/shapes/0/uv_faces/0: uv index 1 out of range (0..0)"},
      {"InlineUvNotANumber",
       {withShapes(R"([{"type": "subdiv", "material": "m", "vertices": [[0,0,0],[1,0,0],[1,1,0]], "faces": [[0,1,2]], "uvs": [[0,0],[1,0],[0,"nan"]]}])")},
       {}, "s.json:6:", "/shapes/0/uvs/2/1: expected a number, got string"},
      {"InlineUvHuge",
       {withShapes(R"([{"type": "subdiv", "material": "m", "vertices": [[0,0,0],[1,0,0],[1,1,0]], "faces": [[0,1,2]], "uvs": [[0,0],[1,0],[0,1e39]]}])")},
       {}, "s.json:6:", "/shapes/0/uvs/2/1: number out of range"},
      {"PatchUvsCountWrong",
       {withShapes(R"([{"type": "bilinear", "material": "m", "quads": [[[-1,-1,0],[1,-1,0],[-1,1,0],[1,1,0]]], "uvs": []}])")},
       {}, "s.json:6:", "/shapes/0/uvs: expected one uv entry per patch: 1 patches, 0 entries"},
      {"UvInterpolationUnknown",
       {withShapes(R"([{"type": "subdiv", "material": "m", "file": "m.obj", "uv_interpolation": "smooth"}])"), {"m.obj", kCubeObj}},
       {}, "s.json:6:", "unknown uv interpolation 'smooth'"},
      {"TextureCoordinatesUnknown",
       {withMaterials(R"({"m": {"type": "diffuse", "albedo": {"type": "checker", "colors": [0, 1], "coordinates": "st"}}})")}, {},
       "s.json:5:", "/materials/m/albedo/coordinates: unknown coordinates 'st' (expected patch or uv)"},
      {"TextureMissing", {textureScene("t.png")}, {}, "s.json:5:", "cannot open image: No such file"},
      {"TextureIsAFolder", {textureScene("t.png"), folder("t.png")}, {}, "s.json:5:", "image is a directory"},
      {"TextureIsAFifo", {textureScene("t.png"), fifo("t.png")}, {}, "s.json:5:", "image is not a regular file"},
      {"TextureIsDevZero", {textureScene("/dev/zero")}, {}, "s.json:5:", "image is not a regular file"},
      {"TextureNotAPng", {textureScene("t.png"), {"t.png", "GIF89a not a png at all"}}, {}, "s.json:5:",
       "t.png: not an image OpenImageIO can read"},
      {"TextureTruncatedPng", {textureScene("t.png"), {"t.png", kPng1x1.substr(0, 45)}}, {}, "s.json:5:",
       "t.png: cannot convert the image"},
      {"TexturePngClaimsHugeSize", {textureScene("t.png"), {"t.png", kPngHuge}}, {}, "s.json:5:",
       "claims 16384x16384 pixels"},
      {"TextureEmptyPng", {textureScene("t.png"), {"t.png", ""}}, {}, "s.json:5:", "t.png: not an image"},
      {"TextureNotAnExr", {textureScene("t.exr"), {"t.exr", "not an exr"}}, {}, "s.json:5:", "t.exr: not an image"},
      {"TextureTruncatedExr", {textureScene("t.exr"), {"t.exr", halfOf(exrBytes("R"))}}, {}, "s.json:5:",
       "t.exr"},
      {"TextureExrClaimsHugeSize", {textureScene("t.exr"), {"t.exr", exrLyingAboutItsSize(exrBytes("R"))}}, {},
       "s.json:5:", "t.exr"},
      {"TextureUnknownFormat", {textureScene("t.gif"), {"t.gif", "GIF89a"}}, {}, "s.json:5:", "t.gif: not an image"},
      {"HeightMapMissing", {heightMapScene("h.exr")}, {}, "s.json:6:", "cannot open height map"},
      {"HeightMapIsAFolder", {heightMapScene("h.exr"), folder("h.exr")}, {}, "s.json:6:", "is a directory"},
      {"HeightMapIsAFifo", {heightMapScene("h.exr"), fifo("h.exr")}, {}, "s.json:6:", "is not a regular file"},
      {"HeightMapNotAnExr", {heightMapScene("h.exr"), {"h.exr", "P5 2 2 255"}}, {}, "s.json:6:",
       "cannot read height map"},
      {"HeightMapTruncated", {heightMapScene("h.exr"), {"h.exr", halfOf(exrBytes("Y"))}}, {}, "s.json:6:",
       "h.exr"},
      {"HeightMapClaimsHugeSize", {heightMapScene("h.exr"), {"h.exr", exrLyingAboutItsSize(exrBytes("Y"))}}, {},
       "s.json:6:", "h.exr"},
      // --- options
      {"SppZero", {validScene()}, renderWith({"--spp", "0"}), "--spp", "must be in [1, 2^20]"},
      {"SppNegative", {validScene()}, renderWith({"--spp", "-3"}), "--spp", "must be in [1, 2^20]"},
      {"SppHuge", {validScene()}, renderWith({"--spp", "2000000"}), "--spp", "must be in [1, 2^20]"},
      {"SppNotANumber", {validScene()}, renderWith({"--spp", "many"}), "--spp", ""},
      {"SppBeyondInt", {validScene()}, renderWith({"--spp", "99999999999"}), "--spp", ""},
      {"ThreadsNegative", {validScene()}, renderWith({"--threads", "-3"}), "--threads", "must be in [0, 4096]"},
      {"ThreadsHuge", {validScene()}, renderWith({"--threads", "100000"}), "--threads", "must be in [0, 4096]"},
      {"ThreadsMissingValue", {validScene()}, renderWith({"--threads"}), "--threads", ""},
      {"SeedNegative", {validScene()}, renderWith({"--seed", "-5"}), "--seed", "must be in [0, 2^62]"},
      {"SeedNotANumber", {validScene()}, renderWith({"--seed", "0x"}), "--seed", ""},
      {"Res100000Squared", {validScene()}, renderWith({"--res", "100000x100000"}), "--res", "more than 2^28 pixels"},
      {"Res65536SquaredWouldWrap", {validScene()}, renderWith({"--res", "65536x65536"}), "--res", "more than 2^28 pixels"},
      {"ResBeyondInt64", {validScene()}, renderWith({"--res", "99999999999999999999x2"}), "--res", "at most 2^28"},
      {"ResZeroWidth", {validScene()}, renderWith({"--res", "0x5"}), "--res", "must be positive"},
      {"ResNegative", {validScene()}, renderWith({"--res", "-4x4"}), "--res", "must be positive"},
      {"ResNoHeight", {validScene()}, renderWith({"--res", "5x"}), "--res", "expected WIDTHxHEIGHT with whole numbers, got '5x'"},
      {"ResNoSeparator", {validScene()}, renderWith({"--res", "640"}), "--res", "expected WIDTHxHEIGHT"},
      {"ResThreeParts", {validScene()}, renderWith({"--res", "4x4x4"}), "--res", "whole numbers"},
      {"ResFraction", {validScene()}, renderWith({"--res", "4.5x4"}), "--res", "whole numbers"},
      {"RayMemoryUnknownUnit", {validScene()}, renderWith({"--ray-memory", "12Q"}), "--ray-memory", "unknown unit"},
      {"RayMemoryZero", {validScene()}, renderWith({"--ray-memory", "0"}), "--ray-memory", "positive"},
      {"RayMemoryNegative", {validScene()}, renderWith({"--ray-memory", "-1G"}), "--ray-memory", "positive"},
      {"RayMemoryNaN", {validScene()}, renderWith({"--ray-memory", "nan"}), "--ray-memory", "positive"},
      {"RayMemoryInfinite", {validScene()}, renderWith({"--ray-memory", "inf"}), "--ray-memory", "positive"},
      {"RayMemoryText", {validScene()}, renderWith({"--ray-memory", "lots"}), "--ray-memory", "expected a byte count"},
      {"GridCacheText", {validScene()}, renderWith({"--grid-cache", "lots"}), "--grid-cache", "expected a byte count"},
      {"GridCacheNegative", {validScene()}, renderWith({"--grid-cache", "-1G"}), "--grid-cache", "positive"},
      {"CandidatesPerRayZero", {validScene()}, renderWith({"--candidates-per-ray", "0"}), "--candidates-per-ray", "[1, 1000]"},
      {"CandidatesPerRayHuge", {validScene()}, renderWith({"--candidates-per-ray", "1001"}), "--candidates-per-ray", "[1, 1000]"},
      {"CandidatesPerRayText", {validScene()}, renderWith({"--candidates-per-ray", "many"}), "--candidates-per-ray", ""},
      {"MaxLodNegative", {validScene()}, renderWith({"--max-lod", "-1"}), "--max-lod", "must be in [0, 12]"},
      {"MaxLod13", {validScene()}, renderWith({"--max-lod", "13"}), "--max-lod", "must be in [0, 12]"},
      {"ResidentLodNegative", {validScene()}, renderWith({"--resident-lod", "-1"}), "--resident-lod", "must be in [0, 12]"},
      {"ResidentLod13", {validScene()}, renderWith({"--resident-lod", "13"}), "--resident-lod", "must be in [0, 12]"},
      {"LodUnknownRule", {validScene()}, renderWith({"--lod", "random"}), "--lod", ""},
      {"TraceModeUnknown", {validScene()}, renderWith({"--trace-mode", "fast"}), "--trace-mode", ""},
      {"UnknownOption", {validScene()}, renderWith({"--fast"}), "--fast", ""},
      {"ReferenceMissing", {validScene()}, renderWith({"--reference", "$D/ref.exr"}), "$D/ref.exr",
       "cannot open reference image"},
      {"ReferenceIsAFolder", {validScene(), folder("ref.exr")}, renderWith({"--reference", "$D/ref.exr"}),
       "$D/ref.exr", "reference image is a directory"},
      {"ReferenceIsAFifo", {validScene(), fifo("ref.exr")}, renderWith({"--reference", "$D/ref.exr"}), "$D/ref.exr",
       "reference image is not a regular file"},
      {"ReferenceIsDevZero", {validScene()}, renderWith({"--reference", "/dev/zero"}), "/dev/zero",
       "reference image is not a regular file"},
      {"ReferenceNotAnExr", {validScene(), {"ref.exr", kPng1x1}}, renderWith({"--reference", "$D/ref.exr"}),
       "$D/ref.exr", "cannot read reference image"},
      {"ReferenceWithoutGreen", {validScene(), {"ref.exr", exrBytes("R")}}, renderWith({"--reference", "$D/ref.exr"}),
       "$D/ref.exr", "reference image has no channel G"},
      {"ReferenceTruncated", {validScene(), {"ref.exr", halfOf(exrBytes("R"))}},
       renderWith({"--reference", "$D/ref.exr"}), "$D/ref.exr", "reference image"},
      {"ReferenceOfAnotherSize", {validScene(), {"ref.exr", rgbExrBytes(16, 16, 0)}},
       renderWith({"--reference", "$D/ref.exr"}), "$D/ref.exr", "reference image is 16x16, the render 8x6"},
      {"ReferenceAllNaN", {validScene(), {"ref.exr", rgbExrBytes(8, 6, NAN)}}, renderWith({"--reference", "$D/ref.exr"}),
       "$D/ref.exr", "reference image has 144 values that are NaN or infinite, the first at pixel (0, 0) channel R (NaN)"},
      {"ReferenceInfinite", {validScene(), {"ref.exr", rgbExrBytes(8, 6, INFINITY)}},
       convergeWith({}), "$D/ref.exr", "the first at pixel (0, 0) channel R (infinite)"},
      {"ConvergeErrorMaskAllZero", {validScene(), {"ref.exr", referenceBytes()}, {"m.exr", rgbExrBytes(8, 6, 0)}},
       convergeWith({"--error-mask", "$D/m.exr"}), "$D/m.exr", "error mask has no pixel with non-zero red"},
      {"ConvergeMaskAllZero", {validScene(), {"ref.exr", referenceBytes()}, {"m.exr", rgbExrBytes(8, 6, 0)}},
       convergeWith({"--mask", "$D/m.exr"}), "$D/m.exr", "mask has no pixel with non-zero red"},
      {"ConvergeErrorMaskNaN", {validScene(), {"ref.exr", referenceBytes()}, {"m.exr", rgbExrBytes(8, 6, NAN)}},
       convergeWith({"--error-mask", "$D/m.exr"}), "$D/m.exr", "error mask has 144 values that are NaN or infinite"},
      {"ConvergeErrorMaskOfAnotherSize", {validScene(), {"ref.exr", referenceBytes()}, {"m.exr", rgbExrBytes(9, 6, 1)}},
       convergeWith({"--error-mask", "$D/m.exr"}), "$D/m.exr", "error mask is 9x6, the render 8x6"},
      {"ConvergeClampedRmseOne", {validScene(), {"ref.exr", referenceBytes()}}, convergeWith({"--clamped-rmse", "1"}),
       "--clamped-rmse", "must lie in (0, 1)"},
      {"ConvergeClampedRmseText", {validScene(), {"ref.exr", referenceBytes()}}, convergeWith({"--clamped-rmse", "most"}),
       "--clamped-rmse", ""},
      // --- outputs that cannot be written: nothing at all is left
      {"OutputIsAFolder", {validScene(), folder("out/o.exr")}, {}, "$D/out/o.exr", "is a directory"},
      {"PreviewPathIsAFolder", {validScene(), folder("out/o.png")}, {}, "$D/out/o.png", "is a directory"},
      {"StatsPathIsAFolder", {validScene(), folder("st")}, renderWith({"--stats", "$D/st"}), "$D/st",
       "cannot write the stats: is a directory"},
      {"ReportPathIsAFolder", {validScene(), folder("r.html")}, renderWith({"--report", "$D/r.html"}),
       "$D/r.html", "cannot write the report: is a directory"},
      {"OutputUnderAFile", {validScene(), {"f", "x"}}, {"render", "$D/s.json", "-o", "$D/f/o.exr", "-q"}, "$D/f/o.exr",
       "cannot create the folder"},
      {"StatsUnderAFile", {validScene(), {"f", "x"}}, renderWith({"--stats", "$D/f/s.json"}), "$D/f/s.json",
       "cannot create the folder"},
      {"ReportUnderAFileAfterOthers", {validScene(), {"f", "x"}},
       renderWith({"--stats", "$D/out/s.json", "--report", "$D/f/r.html"}), "$D/f/r.html", "cannot create the folder"},
      {"StatsAndReportSameFile", {validScene()}, renderWith({"--stats", "$D/out/x", "--report", "$D/out/x"}),
       "$D/out/x", "given as the stats and as the report"},
      {"StatsIsThePreview", {validScene()}, renderWith({"--stats", "$D/out/o.png"}), "$D/out/o.png",
       "given as the preview and as the stats"},
      {"PngOutputIsAlsoTheReport", {validScene()}, {"render", "$D/s.json", "-o", "$D/out/p.png", "--report",
                                                    "$D/out/p.png", "-q"},
       "$D/out/p.png", "given as the preview and as the report"},
      {"OutputIsAFifo", {validScene(), fifo("out/o.exr")}, {}, "$D/out/o.exr", "cannot write the image: not a regular file"},
      // -o takes .exr, .png and .film only (any other name would have been written as an EXR).
      {"OutputIsADevice", {validScene()}, {"render", "$D/s.json", "-o", "/dev/null", "-q"}, "-o: '/dev/null'",
       "no extension"},
      {"OutputIsTheScene", {validScene()}, {"render", "$D/s.json", "-o", "$D/s.json", "-q"}, "-o: '$D/s.json'",
       "unknown extension '.json'"},
      {"StatsIsTheScene", {validScene()}, renderWith({"--stats", "$D/s.json"}), "$D/s.json",
       "the stats would overwrite an input of this run"},
      {"OutputIsTheReference", {validScene(), {"ref.exr", referenceBytes()}},
       {"render", "$D/s.json", "-o", "$D/ref.exr", "--reference", "$D/ref.exr", "-q"}, "$D/ref.exr",
       "the image would overwrite an input of this run"},
  };
  return c;
}

std::string substitute(std::string s, const std::string& dir) {
  for (size_t at = s.find("$D"); at != std::string::npos; at = s.find("$D", at + dir.size())) s.replace(at, 2, dir);
  return s;
}

class HostileInput : public ::testing::TestWithParam<HostileCase> {};

TEST_P(HostileInput, IsExit2WithFileAndPlaceAndNothingWritten) {
  const HostileCase& c = GetParam();
  const testing::TempFolder temp;
  const std::string dir = temp.dir().string();
  for (const InputFile& f : c.files) {
    if (f.folder) std::filesystem::create_directories(temp.path(f.name));
    else if (f.fifo) {
      std::filesystem::create_directories(std::filesystem::path(temp.path(f.name)).parent_path());
      ASSERT_EQ(::mkfifo(temp.path(f.name).c_str(), 0644), 0) << f.name;
    }
    else temp.write(f.name, f.content);
  }
  const std::vector<std::string> before = temp.entries();
  std::vector<std::string> args = c.args.empty() ? renderWith({}) : c.args;
  for (auto& a : args) a = substitute(a, dir);

  const testing::RunResult r = testing::runRayes(args);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_THAT(r.err, ::testing::HasSubstr(substitute(c.place, dir)));
  EXPECT_THAT(r.err, ::testing::HasSubstr(c.message));
  EXPECT_THAT(r.err, ::testing::Not(::testing::HasSubstr("internal error")));
  // One message (a command-line parse error adds one line pointing at the help of the
  // subcommand it was parsing: 'rayes render --help', 'rayes converge --help' or 'rayes --help').
  std::string message = r.err;
  for (const char* which : {"render ", "converge ", ""}) {
    const std::string hint = std::string("(run 'rayes ") + which + "--help' for the options)\n";
    if (message.size() > hint.size() && message.ends_with(hint)) {
      message.resize(message.size() - hint.size());
      break;
    }
  }
  EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 1) << r.err;
  EXPECT_TRUE(message.starts_with("rayes: ")) << r.err;
  EXPECT_EQ(temp.entries(), before) << "the run left files behind";
}

INSTANTIATE_TEST_SUITE_P(Catalogue, HostileInput, ::testing::ValuesIn(catalogue()),
                         [](const ::testing::TestParamInfo<HostileCase>& info) { return std::string(info.param.name); });

TEST(HostileCatalogue, HasAtLeastAHundredRows) { EXPECT_GE(catalogue().size(), 100u); }

}  // namespace
}  // namespace rayes
