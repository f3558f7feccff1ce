// `rayes compile` and the render of a compiled scene (docs/scene-format.md, "Compiled scenes"):
// the same image bits as the JSON render for every kind of leaf a .rayes holds; a scene several
// times --scene-memory renders within it; bad input, found at opening or mid-render, is one
// message naming the file and place, exit code 2 (3 for a resource limit), nothing written.
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "app/command_line.h"
#include "core/memory.h"
#include "geometry/compiled_file.h"
#include "support/exr_test_file.h"
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {
namespace fs = std::filesystem;
using testing::RunResult;

RunResult run(std::vector<std::string> args) { return testing::runRayes(std::move(args)); }
std::string sceneFile(const std::string& name) { return std::string(RAYES_SOURCE_DIR) + "/scenes/" + name; }

class CompiledScene : public ::testing::Test {
 protected:
  // Compiles `json` into the temp folder; returns the .rayes path.
  std::string compile(const std::string& json, const std::string& name) {
    const std::string out = temp_.path(name + ".rayes");
    const RunResult r = run({"compile", json, "-o", out, "-q"});
    EXPECT_EQ(r.code, 0) << r.err;
    return out;
  }
  // Renders `scene` to NAME.exr with `extra` options; returns the EXR's bytes.
  std::string render(const std::string& scene, const std::string& name, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"render", scene, "-o", temp_.path(name + ".exr"), "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = run(args);
    EXPECT_EQ(r.code, 0) << r.err;
    return temp_.read(name + ".exr");
  }
  testing::TempFolder temp_;
};

// The offset of `kind`'s section in a compiled file (0: none).
uint64_t sectionOffset(const std::string& path, compiled::SectionKind kind) {
  MappedFile probe(path, 0);
  for (uint32_t k = 0; k < probe.header().sectionCount; ++k)
    if (probe.header().sections[k].kind == uint32_t(kind)) return probe.header().sections[k].offset;
  return 0;
}

// `in` written again to `out` section by section, each section's bytes passed through `edit`
// first: a file whose checksums are right, with contents no compile writes.
void rewrite(const std::string& in, const std::string& out,
             const std::function<void(compiled::SectionKind, std::string&)>& edit) {
  std::string bytes;
  {
    std::ifstream f(in, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(f), {});
  }
  MappedFile probe(in, 0);
  CompiledFileWriter w(out, "test");
  for (uint32_t k = 0; k + 1 < probe.header().sectionCount; ++k) {
    const compiled::SectionEntry& e = probe.header().sections[k];
    std::string section = bytes.substr(e.offset, e.bytes);
    edit(compiled::SectionKind(e.kind), section);
    w.beginSection(compiled::SectionKind(e.kind));
    w.write(section.data(), section.size());
  }
  w.finish();
}

// Bézier (teapot), noise-displaced Bézier (displaced teapot), a forest (displaced Bézier bark,
// displaced bilinear terrain, bilinear foliage), moving bilinear patches, a bilinear box with a
// rectangle light (a light leaf after the compiled ones), depth of field over Bézier patches,
// a Catmull-Clark mesh with creases (subdiv creature) and with its uv set read by a texture
// (uv checker).
TEST_F(CompiledScene, RendersTheSameBitsAsTheJson) {
  for (const char* name : {"teapot", "displaced-teapot", "forest-1", "motion-cubes", "cornell-box", "dof",
                           "subdiv-creature", "uv-checker"}) {
    SCOPED_TRACE(name);
    const std::string json = sceneFile(std::string(name) + ".json");
    const std::string compiled = compile(json, name);
    const std::vector<std::string> opts = {"--res", "40x30", "--spp", "2"};
    const std::string a = render(json, std::string(name) + "-json", opts);
    const std::string b = render(compiled, std::string(name) + "-rayes", opts);
    ASSERT_FALSE(a.empty());
    EXPECT_TRUE(a == b) << "the compiled render differs from the JSON render";
  }
}

// Forests are stored as their generator tables (the forests section: parameters, branches,
// foliage) and a 13-byte record per leaf naming its forest and piece, not as expanded patches:
// two forests (one placed by a rotation, a uniform scale and a translation, with several
// terrain tiles) with a stored bilinear quad between them render to the JSON's bits, at one
// thread and two.
TEST_F(CompiledScene, ForestsAreStoredAsTheirGeneratorTablesAndRenderTheSameBits) {
  const std::string json = temp_.write("forests.json", R"({
    "camera": {"position": [0, 5, 26], "look_at": [0, 3, 0], "fov": 50},
    "film": {"resolution": [48, 32], "spp": 2},
    "integrator": {"max_depth": 2},
    "materials": {"bark": {"type": "diffuse", "albedo": [0.3, 0.2, 0.15]},
                  "leaf": {"type": "diffuse", "albedo": [0.2, 0.45, 0.1]},
                  "ground": {"type": "diffuse", "albedo": [0.35, 0.3, 0.2]}},
    "shapes": [
      {"type": "forest", "trees": 12, "seed": 4, "detail": 2, "area": 16, "terrain_tiles": 5, "terrain_amplitude": 0.8,
       "materials": {"terrain": "ground", "bark": "bark", "foliage": "leaf"}},
      {"type": "bilinear", "material": "ground", "quads": [[[-9, 0, -9], [9, 0, -9], [-9, 8, -9], [9, 8, -9]]]},
      {"type": "forest", "trees": 5, "seed": 11, "detail": 2, "area": 6, "terrain_tiles": 3, "leaves_per_twig": 5,
       "materials": {"terrain": "ground", "bark": "bark", "foliage": "leaf"},
       "transform": [{"rotate": {"axis": [0, 1, 0], "degrees": 30}}, {"scale": 1.5}, {"translate": [6, -0.5, 4]}]}
    ],
    "lights": [{"type": "distant", "direction": [0.4, 0.8, 0.45], "irradiance": [3, 3, 3]}]})");
  const std::string compiled = compile(json, "forests");
  {
    MappedFile probe(compiled, 0);
    ASSERT_TRUE(probe.has(compiled::SectionKind::Forests));
    const uint64_t leaves = probe.sectionBytes(compiled::SectionKind::Leaves) / sizeof(compiled::LeafEntry);
    // Every forest leaf a 13-byte record, the quad a bilinear record (a tag and four corners).
    EXPECT_EQ(probe.sectionBytes(compiled::SectionKind::Records), (leaves - 1) * 13 + 1 + 4 * 12);
  }
  const std::string reference = render(json, "json");
  ASSERT_FALSE(reference.empty());
  for (const char* threads : {"1", "2"}) {
    SCOPED_TRACE(threads);
    EXPECT_TRUE(render(compiled, std::string("rayes") + threads, {"--threads", threads}) == reference)
        << "the compiled render differs from the JSON render";
  }
}

// A forest's tables that do not match what its header says, parameters its generator refuses,
// or a leaf record outside the tables (files with right checksums and wrong contents): refused
// naming the file and the section, exit code 2, nothing written.
TEST_F(CompiledScene, BadForestTablesAreRefusedNamingTheSection) {
  const std::string json = temp_.write("forest.json", R"({
    "camera": {"position": [0, 4, 12], "look_at": [0, 2, 0], "fov": 50},
    "film": {"resolution": [16, 12], "spp": 1},
    "materials": {"m": {"type": "diffuse", "albedo": [0.5, 0.4, 0.3]}},
    "shapes": [{"type": "forest", "trees": 3, "seed": 2, "detail": 2, "area": 6, "terrain_tiles": 2,
                "materials": {"terrain": "m", "bark": "m", "foliage": "m"}}],
    "lights": [{"type": "distant", "direction": [0.4, 0.8, 0.45], "irradiance": [3, 3, 3]}]})");
  const std::string good = compile(json, "good");
  using Kind = compiled::SectionKind;
  struct Case {
    const char* name;
    std::function<void(Kind, std::string&)> edit;
    std::string place;
  };
  const auto header = [](std::string& s) { return reinterpret_cast<compiled::ForestHeader*>(s.data()); };
  const std::vector<Case> cases = {
      {"truncated", [](Kind k, std::string& s) { if (k == Kind::Forests) s.resize(s.size() - 100); },
       "section forests (forest 0): "},
      {"count", [&](Kind k, std::string& s) { if (k == Kind::Forests) header(s)->branchCount += 1; },
       "section forests (forest 0): "},
      {"params", [&](Kind k, std::string& s) { if (k == Kind::Forests) header(s)->detail = 99; },
       "section forests (forest 0): its parameters are refused: detail must be in [0, 8]"},
      // Every leaf's piece beyond its table: the first leaf diced says which it is.
      {"record", [](Kind k, std::string& s) {
         if (k != Kind::Records) return;
         for (size_t at = 0; at + 13 <= s.size(); at += 13) std::memset(s.data() + at + 9, 0xff, 4);
       },
       "the patch record does not decode: "},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    testing::TempFolder t;
    const std::string scene = t.path(std::string(c.name) + ".rayes");
    rewrite(good, scene, c.edit);
    const RunResult r = run({"render", scene, "-o", t.path("out/x.exr"), "--stats", t.path("out/s.json"), "-q"});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(scene + ":"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.place), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
    EXPECT_EQ(t.entries(), std::vector<std::string>{std::string(c.name) + ".rayes"}) << "something was written";
  }
}

// Format version 2's other kinds, in one scene: height-map displacement (the map named relative
// to the scene, which lies in another folder than the .rayes) on a bilinear quad with uv
// corners a texture reads, a moving displaced subdivision mesh whose uv set the texture reads
// (its topology stored once for both time samples), and a Bézier teapot without a uv set
// among leaves with one.
TEST_F(CompiledScene, HeightMapsUvSetsAndMovingMeshesRenderTheSameBitsAsTheJson) {
  fs::create_directories(temp_.path("src"));
  std::vector<float> h(16 * 16);
  for (int k = 0; k < 256; ++k) h[size_t(k)] = float((k * 37) % 17) / 17.0f;
  testing::writeOneChannelExr(temp_.path("src/h.exr"), 16, 16, "Y", h);
  const std::string json = temp_.write("src/scene.json", R"({
    "camera": {"position": [0, -6, 4], "look_at": [0, 0, 0.3], "up": [0, 0, 1], "fov": 40, "shutter": [0, 1]},
    "film": {"resolution": [40, 30], "spp": 2},
    "integrator": {"max_depth": 2},
    "materials": {
      "uv": {"type": "diffuse", "albedo": {"type": "checker", "colors": [[0.8, 0.7, 0.6], [0.1, 0.2, 0.4]], "scale": 6,
                                          "coordinates": "uv"}},
      "plain": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
    "shapes": [
      {"type": "bilinear", "material": "uv", "quads": [[[-3, -3, 0], [3, -3, 0], [-3, 3, 0], [3, 3, 0]]],
       "uvs": [[[0, 0], [2, 0], [0, 2], [2, 2]]],
       "displacement": {"type": "image", "file": "h.exr", "amplitude": 0.3}},
      {"type": "subdiv", "material": "uv",
       "vertices": [[-1, -1, 0.5], [1, -1, 0.5], [1, 1, 0.5], [-1, 1, 0.5], [-1, -1, 1.5], [1, -1, 1.5], [1, 1, 1.5], [-1, 1, 1.5]],
       "faces": [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]],
       "creases": [[4, 5, 2.5]], "corners": [[6, 3]],
       "uvs": [[0, 0], [1, 0], [1, 1], [0, 1]], "uv_faces": [[0, 3, 2, 1], [0, 1, 2, 3], [0, 1, 2, 3], [0, 1, 2, 3], [0, 1, 2, 3], [0, 1, 2, 3]],
       "displacement": {"type": "noise", "amplitude": 0.05, "frequency": 3},
       "motion": {"times": [0, 1], "transforms": [[{"translate": [0, 0, 0]}], [{"translate": [0.3, 0, 0]}]]}},
      {"type": "bezier", "file": ")" + sceneFile("teapot.bpt") + R"(", "material": "plain",
       "transform": [{"scale": [0.2, 0.2, 0.2]}, {"translate": [2, 1, 0.5]}]}
    ],
    "lights": [{"type": "point", "position": [2, -4, 6], "intensity": [40, 40, 40]}]})");
  fs::create_directories(temp_.path("out"));
  const std::string compiled = compile(json, "out/scene");
  EXPECT_NE(sectionOffset(compiled, compiled::SectionKind::Meshes), 0u);
  EXPECT_NE(sectionOffset(compiled, compiled::SectionKind::UvSets), 0u);
  const std::string a = render(json, "json");
  const std::string b = render(compiled, "rayes");
  ASSERT_FALSE(a.empty());
  EXPECT_TRUE(a == b) << "the compiled render differs from the JSON render";
  // The map is opened again at every render: gone, it is named with the compiled file.
  fs::remove(temp_.path("src/h.exr"));
  const RunResult r = run({"render", compiled, "-o", temp_.path("gone.exr"), "-q"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find(compiled + ":section scene (height map 0): cannot open height map"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(temp_.path("gone.exr")));
}

// A forest of 48 trees: a .rayes of several MiB rendered under --scene-memory 1M, with the
// stats' estimate and the kernel's count of the mapping's pages within it, and the image of
// the JSON route at any thread count.
TEST_F(CompiledScene, RendersWithinSceneMemoryAndEqualsTheJson) {
  const std::string json = temp_.write("forest.json", R"({
    "camera": {"position": [0, 6, 30], "look_at": [0, 3, 0], "fov": 50},
    "film": {"resolution": [48, 36], "spp": 1},
    "integrator": {"max_depth": 2},
    "materials": {"m": {"type": "diffuse", "albedo": [0.5, 0.4, 0.3]}},
    "shapes": [{"type": "forest", "trees": 48, "seed": 5, "detail": 3, "area": 24, "terrain_tiles": 8,
                "materials": {"terrain": "m", "bark": "m", "foliage": "m"}}],
    "lights": [{"type": "distant", "direction": [0.4, 0.8, 0.45], "irradiance": [3, 3, 3]}]})");
  const std::string compiled = compile(json, "forest");
  const uint64_t budget = uint64_t(1) << 20;
  ASSERT_GE(fs::file_size(compiled), 4 * budget) << "the scene must be several times the budget";
  const std::string reference = render(json, "json");
  for (const char* threads : {"1", "2"}) {
    SCOPED_TRACE(threads);
    const std::string stats = temp_.path(std::string("s") + threads + ".json");
    EXPECT_TRUE(render(compiled, std::string("c") + threads, {"--scene-memory", "1M", "--threads", threads, "--stats", stats}) ==
                reference);
    std::ifstream in(stats);
    const auto c = nlohmann::json::parse(in)["scene"]["compiled"];
    EXPECT_EQ(c["scene_memory_bytes"].get<uint64_t>(), budget);
    EXPECT_EQ(c["bytes_mapped"].get<uint64_t>(), fs::file_size(compiled));
    EXPECT_LE(c["resident_peak_bytes"].get<uint64_t>(), budget);
    EXPECT_GT(c["blocks_released"].get<uint64_t>(), 0u);
    // Everything touched is read at least once; released blocks are read again.
    EXPECT_GT(c["bytes_read"].get<uint64_t>(), c["resident_peak_bytes"].get<uint64_t>());
    // The kernel's count when the stats were taken: the budget (blocks being read by other
    // threads are not in flight then).
    EXPECT_LE(c["resident_at_end_bytes"].get<uint64_t>(), budget);
  }
}

// The top level is built by `rayes compile` and read in place by the render: no top level in
// the render's own memory, its nodes paged under --scene-memory like the records (a budget
// smaller than the nodes alone), every node read at least once (adoption checks them all), and
// the image of the JSON route, whose render builds its own tree.
TEST_F(CompiledScene, TheStoredTopLevelIsReadInPlaceUnderSceneMemory) {
  const std::string json = temp_.write("forest.json", R"({
    "camera": {"position": [0, 6, 30], "look_at": [0, 3, 0], "fov": 50},
    "film": {"resolution": [40, 30], "spp": 1},
    "integrator": {"max_depth": 2},
    "materials": {"m": {"type": "diffuse", "albedo": [0.5, 0.4, 0.3]}},
    "shapes": [{"type": "forest", "trees": 64, "seed": 9, "detail": 3, "area": 24, "terrain_tiles": 8,
                "materials": {"terrain": "m", "bark": "m", "foliage": "m"}}],
    "lights": [{"type": "distant", "direction": [0.4, 0.8, 0.45], "irradiance": [3, 3, 3]}]})");
  const std::string compiled = compile(json, "forest");
  uint64_t topBytes = 0;
  {
    MappedFile probe(compiled, 0);
    topBytes = probe.sectionBytes(compiled::SectionKind::TopLevel);
  }
  const uint64_t budget = uint64_t(1) << 20;
  ASSERT_GE(topBytes, 2 * budget) << "the nodes alone must exceed the budget";
  const std::string reference = render(json, "json", {"--stats", temp_.path("sj.json")});
  EXPECT_TRUE(render(compiled, "c", {"--scene-memory", "1M", "--stats", temp_.path("sc.json")}) == reference);
  std::ifstream inJson(temp_.path("sj.json")), inCompiled(temp_.path("sc.json"));
  const auto sj = nlohmann::json::parse(inJson), sc = nlohmann::json::parse(inCompiled);
  EXPECT_GT(sj["memory"]["by_owner"]["top_level"].get<uint64_t>(), topBytes / 2) << "the JSON route builds its own";
  EXPECT_EQ(sc["memory"]["by_owner"]["top_level"].get<uint64_t>(), 0u);
  const auto c = sc["scene"]["compiled"];
  EXPECT_EQ(c["top_level"], "stored");
  EXPECT_GE(c["bytes_read"].get<uint64_t>(), topBytes);
  EXPECT_LE(c["resident_peak_bytes"].get<uint64_t>(), budget);
}

// Batch jobs take a compiled scene too: its films' fingerprint names it by its header block
// (whose CRC covers every block's), so parts merge to the whole render's bits.
TEST_F(CompiledScene, PartsOfACompiledRenderMergeToTheWholeRender) {
  const std::string compiled = compile(sceneFile("teapot.json"), "teapot");
  const std::vector<std::string> opts = {"--res", "24x18", "--spp", "1"};
  const std::string whole = render(compiled, "whole", opts);
  for (const char* part : {"1/2", "2/2"}) {
    std::vector<std::string> args = {"render", compiled, "--part", part, "-o", temp_.path(std::string("p") + part[0] + ".film"), "-q"};
    args.insert(args.end(), opts.begin(), opts.end());
    const RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << r.err;
  }
  const RunResult m = run({"merge", temp_.path("p1.film"), temp_.path("p2.film"), "-o", temp_.path("merged.exr"), "-q"});
  ASSERT_EQ(m.code, 0) << m.err;
  EXPECT_TRUE(temp_.read("merged.exr") == whole);
}

TEST_F(CompiledScene, BadFilesAreRefusedNamingThePlaceAndWriteNothing) {
  const std::string good = compile(sceneFile("cornell-box.json"), "good");
  const std::string bytes = temp_.read("good.rayes");
  const uint64_t records = sectionOffset(good, compiled::SectionKind::Records);
  // A mesh with a uv set: its topology is built at load, its uv records read as hits are shaded.
  const std::string uvScene = compile(sceneFile("uv-checker.json"), "uv");
  const std::string uvBytes = temp_.read("uv.rayes");
  const uint64_t meshes = sectionOffset(uvScene, compiled::SectionKind::Meshes);
  const uint64_t uvSets = sectionOffset(uvScene, compiled::SectionKind::UvSets);
  // A forest: its tables' first block is read at load (the forest's header).
  const std::string forestScene = compile(sceneFile("forest-1.json"), "forest");
  const std::string forestBytes = temp_.read("forest.rayes");
  const uint64_t forests = sectionOffset(forestScene, compiled::SectionKind::Forests);
  ASSERT_NE(forests, 0u);
  ASSERT_NE(meshes, 0u);
  ASSERT_NE(uvSets, 0u);
  struct Case {
    const char* name;
    std::string content;
    std::string place;  // what the message must hold
  };
  std::vector<Case> cases = {
      {"truncated", bytes.substr(0, bytes.size() / 2), "header: truncated"},
      {"not-one", "{\"camera\": {}}", "not a compiled Rayes scene"},
      {"version", bytes, "header: format version 7"},
      {"header", bytes, "header: checksum mismatch"},
      // A record block: the bilinear leaves are read first when diced, mid-render.
      {"block", bytes, "section records, block 0 (leaf "},
      // A file of format version 1 (no uv sets, meshes or height maps): refused, both versions named.
      {"version-1", bytes, "header: format version 1, written by rayes"},
      // Version 2 had no stored top level, and its leaves were in world coordinates (not in the
      // camera's render frame).
      {"version-2", bytes, "header: format version 2, written by rayes"},
      // The stored top level: every node is checked at load.
      {"top-level-block", bytes, "section top_level, block 0"},
      // Shading's per-leaf rows: every row is checked at load.
      {"shading-block", bytes, "section leaf_shading, block 0"},
      {"mesh-block", uvBytes, "section meshes, block 0 (topology 0)"},
      {"uv-block", uvBytes, "section uv_sets, block 0 (leaf "},
      {"uv-truncated", uvBytes.substr(0, uvSets + 100), "header: truncated or extended"},
      // Version 3 stored a forest's leaves as expanded patch records.
      {"version-3", bytes, "header: format version 3, written by rayes"},
      {"forest-block", forestBytes, "section forests, block 0 (forest 0)"},
      {"forest-truncated", forestBytes.substr(0, forests + 100), "header: truncated or extended"},
  };
  cases[2].content[8] = 7;
  cases[3].content[90] ^= 1;
  cases[4].content[records + 3] ^= 1;
  cases[5].content[8] = 1;
  cases[6].content[8] = 2;
  cases[7].content[sectionOffset(good, compiled::SectionKind::TopLevel) + 200] ^= 1;
  cases[8].content[sectionOffset(good, compiled::SectionKind::LeafShading) + 5] ^= 1;
  cases[9].content[meshes + 5] ^= 1;
  cases[10].content[uvSets + 3] ^= 1;
  cases[12].content[8] = 3;
  cases[13].content[forests + 5] ^= 1;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    testing::TempFolder t;
    const std::string scene = t.write(std::string(c.name) + ".rayes", c.content);
    const RunResult r = run({"render", scene, "--res", "16x12", "--spp", "1", "-o", t.path("out/x.exr"), "--stats",
                             t.path("out/s.json"), "-q"});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(scene + ":"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.place), std::string::npos) << r.err;
    if (std::string(c.name).rfind("version-", 0) == 0) {
      EXPECT_NE(r.err.find("this program reads version 4"), std::string::npos) << r.err;
    }
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
    EXPECT_EQ(t.entries(), std::vector<std::string>{std::string(c.name) + ".rayes"}) << "something was written";
  }
}

TEST_F(CompiledScene, SceneMemoryOptionIsChecked) {
  const std::string compiled = compile(sceneFile("teapot.json"), "teapot");
  const auto code = [&](std::vector<std::string> extra, const std::string& scene) {
    std::vector<std::string> args = {"render", scene, "--res", "8x6", "--spp", "1", "-o", temp_.path("x.exr"), "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = run(args);
    EXPECT_NE(r.err.find("--scene-memory"), std::string::npos) << r.err;
    return r.code;
  };
  EXPECT_EQ(code({"--scene-memory", "0"}, compiled), 2);
  EXPECT_EQ(code({"--scene-memory", "64K"}, compiled), 2);                   // below 16 blocks
  EXPECT_EQ(code({"--scene-memory", "1G"}, sceneFile("teapot.json")), 2);    // a JSON scene maps nothing
  if (processMemoryLimit().bytes > 0 && processMemoryLimit().bytes < (uint64_t(1) << 50)) {
    EXPECT_EQ(code({"--scene-memory", "900000G"}, compiled), 3);  // beyond memory: a resource limit
  }
  EXPECT_FALSE(fs::exists(temp_.path("x.exr")));
}

TEST_F(CompiledScene, CompileFailsLikeRenderAndWritesNothing) {
  const std::string bad = temp_.write("bad.json", "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},\n \"shapes\": [}");
  RunResult r = run({"compile", bad, "-o", temp_.path("bad.rayes"), "-q"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find(bad + ":2:"), std::string::npos) << r.err;
  r = run({"compile", sceneFile("teapot.json"), "-o", temp_.path("t.exr"), "-q"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("ends in .rayes"), std::string::npos) << r.err;
  EXPECT_EQ(temp_.entries(), std::vector<std::string>{"bad.json"});
}

}  // namespace
}  // namespace rayes
