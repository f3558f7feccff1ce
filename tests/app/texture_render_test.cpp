// Image textures end to end (docs/scene-format.md, "Texture files"): a scene whose textures
// total 4x --texture-memory renders with the tile cache bounded (the process's measured peak
// resident set), gives the same pixels with any cache size and thread count, reports its
// cache in the stats, and refuses bad texture files and options with exit code 2 or 3 and
// nothing written.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "support/rayes_process.h"
#include "support/render_fixtures.h"
#include "support/temp_folder.h"
#include "support/texture_test_files.h"

namespace rayes {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr int kTextures = 4;
constexpr int kSide = 1024;  // float RGB: 12 MiB per image, 16 MiB with its MIP levels

// Four quads side by side, each with its own image, under a constant sky. Plain: the same scene
// with plain albedos; Tiny: each quad with an image of 2x2 texels (the baseline of the memory
// test: OpenImageIO is loaded as for the big images, the images take nothing).
enum class Albedo { Textured, Plain, Tiny };
std::string sceneText(Albedo albedo) {
  std::string materials, shapes;
  for (int k = 0; k < kTextures; ++k) {
    const std::string name = "m" + std::to_string(k);
    const std::string image = albedo == Albedo::Tiny ? "tiny" + std::to_string(k) : "t" + std::to_string(k);
    materials += (k ? ", " : "") + ("\"" + name + "\": {\"type\": \"diffuse\", \"albedo\": ") +
                 (albedo != Albedo::Plain ? "{\"type\": \"image\", \"file\": \"" + image + ".exr\", \"scale\": 3}" : "0.5") +
                 "}";
    const float x0 = -2.0f + float(k), x1 = x0 + 1;
    shapes += std::string(k ? ", " : "") + "{\"type\": \"bilinear\", \"material\": \"" + name + "\", \"quads\": [[[" +
              std::to_string(x0) + ",-1,0],[" + std::to_string(x1) + ",-1,0],[" + std::to_string(x0) + ",1,0],[" +
              std::to_string(x1) + ",1,0]]]}";
  }
  return R"({"camera": {"position": [0, -3, 2], "look_at": [0, 0, 0], "up": [0, 0, 1]},
  "film": {"resolution": [64, 32], "spp": 4},
  "materials": {)" + materials + R"(},
  "shapes": [)" + shapes + R"(],
  "lights": [{"type": "environment", "radiance": [1, 1, 1]}]})";
}

// The textures and both scenes in `dir`; the textures converted into dir/cache.
void writeScenes(const fs::path& dir) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int k = 0; k < kTextures; ++k) {
    std::vector<Rgb> t(size_t(kSide) * kSide);
    for (Rgb& c : t) c = {u(rng), u(rng), u(rng)};
    testing::writeRgbExr(dir / ("t" + std::to_string(k) + ".exr"), kSide, kSide, t);
    testing::writeRgbExr(dir / ("tiny" + std::to_string(k) + ".exr"), 2, 2, std::vector<Rgb>(4, Rgb{u(rng), u(rng), u(rng)}));
  }
  std::ofstream(dir / "textured.json") << sceneText(Albedo::Textured);
  std::ofstream(dir / "plain.json") << sceneText(Albedo::Plain);
  std::ofstream(dir / "tiny.json") << sceneText(Albedo::Tiny);
}

class TextureRender : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    temp_ = new testing::TempFolder();
    writeScenes(temp_->dir());
  }
  static void TearDownTestSuite() { delete temp_; }
  static fs::path dir() { return temp_->dir(); }
  static Scene load(const std::string& name) {
    TextureCacheOptions t;
    t.conversionDir = dir() / "cache";
    t.notice = [](const std::string&) {};
    return loadScene((dir() / name).string(), t);
  }
  static testing::TempFolder* temp_;
};
testing::TempFolder* TextureRender::temp_ = nullptr;

TEST_F(TextureRender, AnyCacheSizeAndThreadCountGiveTheSamePixels) {
  const Scene scene = load("textured.json");
  ASSERT_TRUE(scene.textures);
  RenderOptions big;
  big.textureMemoryBytes = uint64_t(256) << 20;
  const auto ref = testing::renderBeauty(scene, big, 2);
  const TextureCacheStats all = scene.textures->stats();
  EXPECT_EQ(all.files, uint64_t(kTextures));
  EXPECT_GE(all.imageBytes, uint64_t(kTextures) * kSide * kSide * 12) << "float RGB, every level";
  RenderOptions small;
  small.textureMemoryBytes = all.imageBytes / 16;
  for (int threads : {1, 2}) {
    const Scene again = load("textured.json");
    EXPECT_EQ(testing::renderBeauty(again, small, threads), ref) << threads << " threads, cache 1/16 of the textures";
    const TextureCacheStats s = again.textures->stats();
    EXPECT_LE(s.memoryBytes, small.textureMemoryBytes + uint64_t(threads) * 2 * 64 * 64 * 12)
        << "the bound, plus the tiles each thread may hold while the cache evicts";
  }
  // The textures make a difference: the plain scene renders another image.
  EXPECT_NE(testing::renderBeauty(load("plain.json"), big, 2), ref);
}

// Textures totalling 4x --texture-memory: the tile cache stays bounded, so the process's peak
// resident set grows by about the bound over the same scene with images of 2x2 texels (which
// loads OpenImageIO just as well), not by the textures. The assertion: the growth stays below the midpoint between the bound and the
// textures' whole size (what holding them all would add), a margin of (total - bound) / 2 =
// 1.5x the bound for what is not the cache (OIIO's per-file and per-thread state).
TEST_F(TextureRender, TexturesFourTimesTheCacheRenderWithinIt) {
  const uint64_t cap = uint64_t(kTextures) * kSide * kSide * 12 / 4;  // a quarter of the finest levels
  // Converted first (this first run), so that the measured runs read the converted files.
  const fs::path out = dir() / "out";
  fs::create_directories(out);
  auto run = [&](const std::string& scene, const std::string& stats) {
    const auto r = testing::runRayesProcess({"render", (dir() / scene).string(), "-o", (out / "o.exr").string(), "--stats",
                                             (out / stats).string(), "--texture-memory", std::to_string(cap),
                                             "--texture-cache-dir", (dir() / "cache").string(), "--threads", "2", "-q"});
    EXPECT_EQ(r.code, 0) << r.err;
    std::ifstream in(out / stats);
    return nlohmann::json::parse(in);
  };
  run("textured.json", "first.json");
  run("tiny.json", "first-tiny.json");
  const nlohmann::json textured = run("textured.json", "textured.json");
  const nlohmann::json plain = run("tiny.json", "tiny.json");
  const nlohmann::json& t = textured.at("textures");
  const uint64_t total = t.at("image_bytes").get<uint64_t>();
  ASSERT_GE(total, 4 * cap) << "the textures total at least 4x the cache";
  EXPECT_EQ(t.at("conversions").get<uint64_t>(), 0u) << "converted by the first run";
  EXPECT_GT(t.at("tiles_read").get<uint64_t>(), 0u);
  EXPECT_LE(t.at("cache_memory_bytes").get<uint64_t>(), cap + 2 * 2 * 64 * 64 * 12);
  const int64_t growth = textured.at("memory").at("peak_rss_bytes").get<int64_t>() -
                         plain.at("memory").at("peak_rss_bytes").get<int64_t>();
  EXPECT_LT(growth, int64_t(cap + (total - cap) / 2))
      << "peak RSS grew by " << growth << " bytes for a cache of " << cap << " and textures of " << total;
  std::cout << "peak RSS: textured " << textured.at("memory").at("peak_rss_bytes") << ", 2x2 texels "
            << plain.at("memory").at("peak_rss_bytes") << ", growth " << growth << ", cache " << cap << ", textures "
            << total << ", hit rate " << t.at("hit_rate") << "\n";
}

// OpenImageIO is a module the program loads when a scene names an image (texture/texture_cache.h
// says why): a scene without one never maps it -- by the dynamic loader's own record of what it
// loaded (LD_DEBUG=files) -- and its stats list the textures as skipped; a scene with images
// loads the module and OpenImageIO once, and renders.
TEST_F(TextureRender, OpenImageIOIsLoadedOnlyForASceneWithImages) {
  const fs::path out = dir() / "out-modules";
  fs::create_directories(out);
  auto run = [&](const std::string& scene) {
    const auto r = testing::runRayesProcess({"render", (dir() / scene).string(), "-o", (out / (scene + ".exr")).string(),
                                             "--stats", (out / (scene + ".stats.json")).string(), "--texture-cache-dir",
                                             (dir() / "cache").string(), "-q"},
                                            {.env = {"LD_DEBUG=files"}});
    EXPECT_EQ(r.code, 0) << r.err;
    return r.err;
  };
  const std::string plain = run("plain.json");
  EXPECT_THAT(plain, ::testing::Not(HasSubstr("libOpenImageIO")));
  EXPECT_THAT(plain, ::testing::Not(HasSubstr(kTextureModuleName)));
  EXPECT_THAT(plain, HasSubstr("libembree3")) << "LD_DEBUG=files lists the libraries loaded";
  std::ifstream in(out / "plain.json.stats.json");
  const nlohmann::json stats = nlohmann::json::parse(in);
  EXPECT_THAT(stats.at("skipped").at("textures").get<std::string>(), HasSubstr("OpenImageIO not loaded"));
  EXPECT_FALSE(stats.contains("textures"));
  const std::string textured = run("tiny.json");
  EXPECT_THAT(textured, HasSubstr(std::string("file=") + (fs::path(testing::rayesBinary()).parent_path() / kTextureModuleName).string()));
  EXPECT_THAT(textured, HasSubstr("file=libOpenImageIO"));
}

// Without its module (RAYES_MODULE_DIR names a folder without it, standing for a program copied
// without it), a scene with images is refused with one message naming the module and where it
// was looked for, exit code 2, and no image written; a scene without images renders.
TEST_F(TextureRender, AMissingOpenImageIOModuleIsRefusedNamingIt) {
  const testing::TempFolder empty;
  const fs::path image = empty.dir() / "o.exr";
  const testing::ChildSetup withoutModules{.env = {"RAYES_MODULE_DIR=" + empty.dir().string()}};
  const auto refused =
      testing::runRayesProcess({"render", (dir() / "tiny.json").string(), "-o", image.string(), "-q"}, withoutModules);
  const bool written = fs::exists(image);
  const auto plain =
      testing::runRayesProcess({"render", (dir() / "plain.json").string(), "-o", image.string(), "-q"}, withoutModules);
  EXPECT_EQ(refused.code, 2) << refused.err;
  EXPECT_FALSE(written);
  EXPECT_THAT(refused.err, HasSubstr(kTextureModuleName));
  EXPECT_THAT(refused.err, HasSubstr((empty.dir() / kTextureModuleName).string() + ": no such file"));
  EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1) << "one message";
  EXPECT_EQ(plain.code, 0) << plain.err;
  EXPECT_TRUE(fs::exists(image)) << "the scene without images rendered";
}

TEST_F(TextureRender, BadTextureFilesAndCacheSizesAreRefusedWithNothingWritten) {
  const testing::TempFolder temp;
  const fs::path& d = temp.dir();
  std::ofstream(d / "text.exr") << "this is not an image";
  const auto whole = fs::file_size(dir() / "t0.exr");
  fs::copy_file(dir() / "t0.exr", d / "cut.exr");
  fs::resize_file(d / "cut.exr", whole / 3);
  auto scene = [&](const std::string& file) {
    std::string s = sceneText(Albedo::Textured);
    s.replace(s.find("t0.exr"), 6, file);
    for (int k = 1; k < kTextures; ++k) {
      const std::string name = "t" + std::to_string(k) + ".exr";
      s.replace(s.find("\"" + name), name.size() + 1, "\"" + (dir() / name).string());
    }
    std::ofstream(d / "s.json") << s;
    return (d / "s.json").string();
  };
  const fs::path out = d / "o.exr";
  auto run = [&](const std::string& sceneFile, std::vector<std::string> more = {}) {
    std::vector<std::string> args = {"render", sceneFile, "-o", out.string(), "-q", "--texture-cache-dir",
                                     (d / "cache").string()};
    args.insert(args.end(), more.begin(), more.end());
    return testing::runRayes(args);
  };
  for (const auto& [file, message] : std::vector<std::pair<std::string, std::string>>{
           {"text.exr", "not an image"}, {"cut.exr", "cut.exr"}, {"missing.exr", "cannot open image"}}) {
    const auto r = run(scene(file));
    EXPECT_EQ(r.code, 2) << file << ": " << r.err;
    EXPECT_THAT(r.err, HasSubstr("s.json:")) << "names the scene file";
    EXPECT_THAT(r.err, HasSubstr("/materials/m0/albedo/file")) << "names the JSON pointer";
    EXPECT_THAT(r.err, HasSubstr(file)) << "names the texture file";
    EXPECT_THAT(r.err, HasSubstr(message));
    EXPECT_FALSE(fs::exists(out));
  }
  const auto zero = run(scene((dir() / "t0.exr").string()), {"--texture-memory", "0"});
  EXPECT_EQ(zero.code, 2) << zero.err;
  EXPECT_THAT(zero.err, HasSubstr("--texture-memory"));
  const auto huge = run(scene((dir() / "t0.exr").string()), {"--texture-memory", "900000G"});
  EXPECT_EQ(huge.code, 3) << huge.err;
  EXPECT_THAT(huge.err, HasSubstr("--texture-memory"));
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace rayes
