// The batch-job command line (docs/batch-and-farm.md), run in process: --crop writes the whole
// render's pixels in an EXR whose data window is the crop; parts rendered to .film files and
// merged give the single render's EXR bit for bit, with the parts' stats combined; a complete
// .film resolves to the same image; --time-limit stops with exit code 4 and a checkpoint that
// resumes to the same image. Bad input (exit code 2, the file named, nothing written):
// truncated, corrupt, other-scene, other-settings and other-version films, parts missing,
// duplicated, mismatched or unfinished, an unwritable checkpoint path.
#include <filesystem>
#include <fstream>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "app/film_file.h"
#include "support/beam_scenes.h"
#include "support/exr_image.h"
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes::testing {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

class Farm : public ::testing::Test {
 protected:
  Farm() { scene_ = temp_.write("mirror.json", rectLightOverMirrorJson(13, 10, 2)); }
  std::string path(const std::string& name) const { return temp_.path(name); }
  // `rayes render` of the scene with `more` options.
  RunResult render(std::vector<std::string> more, const std::string& method = "pt") const {
    std::vector<std::string> args = {"render", scene_, "-q", "--method", method, "--photons", "500",
                                     "--beam-resolution", "16"};
    args.insert(args.end(), more.begin(), more.end());
    return runRayes(args);
  }
  // Parts 1..n of `method` into part-<i>.film; returns their paths.
  std::vector<std::string> parts(int n, const std::string& method = "pt", std::vector<std::string> more = {}) const {
    std::vector<std::string> files;
    for (int i = 1; i <= n; ++i) {
      files.push_back(path(method + "-part-" + std::to_string(i) + ".film"));
      std::vector<std::string> args = {"--part", std::to_string(i) + "/" + std::to_string(n), "-o", files.back()};
      args.insert(args.end(), more.begin(), more.end());
      const RunResult r = render(args, method);
      EXPECT_EQ(r.code, 0) << r.err;
    }
    return files;
  }
  RunResult merge(std::vector<std::string> files, std::vector<std::string> more) const {
    std::vector<std::string> args = {"merge", "-q"};
    args.insert(args.end(), files.begin(), files.end());
    args.insert(args.end(), more.begin(), more.end());
    return runRayes(args);
  }
  TempFolder temp_;
  std::string scene_;
};

TEST_F(Farm, CropIsAnExrOfTheWindowWithTheFullDisplayWindow) {
  ASSERT_EQ(render({"-o", path("whole.exr")}).code, 0);
  const RunResult r = render({"--crop", "2,3,9,8", "-o", path("crop.exr")});
  ASSERT_EQ(r.code, 0) << r.err;
  const ExrImage whole = readExrImage(path("whole.exr")), crop = readExrImage(path("crop.exr"));
  EXPECT_EQ(crop.dataX0, 2);
  EXPECT_EQ(crop.dataY0, 3);
  EXPECT_EQ(crop.width, 7);
  EXPECT_EQ(crop.height, 5);
  EXPECT_EQ(crop.displayWidth, 13);
  EXPECT_EQ(crop.displayHeight, 10);
  for (const auto& [name, values] : crop.channels)
    for (int y = 3; y < 8; ++y)
      for (int x = 2; x < 9; ++x) ASSERT_EQ(crop.at(name, x, y), whole.at(name, x, y)) << name << " " << x << "," << y;
  // The preview is the window's size.
  std::ifstream png(path("crop.png"), std::ios::binary);
  std::string head(24, '\0');
  png.read(head.data(), 24);
  EXPECT_EQ((uint8_t(head[16]) << 24 | uint8_t(head[17]) << 16 | uint8_t(head[18]) << 8 | uint8_t(head[19])), 7);
  EXPECT_EQ((uint8_t(head[20]) << 24 | uint8_t(head[21]) << 16 | uint8_t(head[22]) << 8 | uint8_t(head[23])), 5);
}

TEST_F(Farm, MergedPartsAreTheSingleRenderBitForBit) {
  for (const std::string method : {"pt", "lt", "ppm"}) {
    ASSERT_EQ(render({"-o", path(method + ".exr")}, method).code, 0);
    const std::vector<std::string> files = parts(3, method);
    const RunResult r = merge(files, {"-o", path(method + "-merged.exr"), "--stats", path(method + "-stats.json")});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(readExrImage(path(method + ".exr")).sameBits(readExrImage(path(method + "-merged.exr")))) << method;
    EXPECT_TRUE(fs::exists(path(method + "-merged.png")));
    std::ifstream in(path(method + "-stats.json"));
    const auto stats = nlohmann::json::parse(in);
    EXPECT_EQ(stats["parts"], 3);
    uint64_t rays = 0;
    for (const std::string& f : files) rays += readFilmFile(f).header.stats["totals"]["rays"].get<uint64_t>();
    EXPECT_EQ(stats["totals"]["rays"].get<uint64_t>(), rays) << "counters are summed over the parts";
  }
}

TEST_F(Farm, AFilmOutputResolvesToTheSameImage) {
  ASSERT_EQ(render({"-o", path("t.exr")}).code, 0);
  ASSERT_EQ(render({"-o", path("f.film")}).code, 0);
  EXPECT_FALSE(fs::exists(path("f.png"))) << "a .film output is the film alone";
  ASSERT_EQ(merge({path("f.film")}, {"-o", path("again.exr"), "-o", path("again.png")}).code, 0);
  EXPECT_TRUE(readExrImage(path("t.exr")).sameBits(readExrImage(path("again.exr"))));
  // -o takes one name each time, so the parts may come after it.
  ASSERT_EQ(runRayes({"merge", "-q", "-o", path("first.exr"), path("f.film")}).code, 0);
  EXPECT_TRUE(readExrImage(path("t.exr")).sameBits(readExrImage(path("first.exr"))));
}

TEST_F(Farm, TimeLimitStopsWithACheckpointThatResumesToTheSameImage) {
  ASSERT_EQ(render({"-o", path("t.exr")}, "ppm").code, 0);
  // A limit that has passed before the first batch: the stop is taken at once.
  RunResult r = render({"-o", path("out/x.exr"), "--time-limit", "1e-9"}, "ppm");
  ASSERT_EQ(r.code, 4) << r.err;
  EXPECT_THAT(r.err, HasSubstr("time limit"));
  EXPECT_THAT(r.err, HasSubstr("--resume"));
  EXPECT_EQ(temp_.entries(), (std::vector<std::string>{"mirror.json", "out", "out/x.checkpoint.film", "t.exr", "t.png"}));
  r = render({"-o", path("out/x.exr"), "--time-limit", "1000", "--resume"}, "ppm");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(readExrImage(path("t.exr")).sameBits(readExrImage(path("out/x.exr"))));
  EXPECT_FALSE(fs::exists(path("out/x.checkpoint.film"))) << "removed once the render is done";
}

// Writes `film`'s file again with its header changed by `edit` (a film of another version, ...).
void rewrite(const std::string& from, const std::string& to, const std::function<void(FilmFileHeader&)>& edit) {
  FilmFile f = readFilmFile(from);
  edit(f.header);
  writeFilmFile(to, f.header, f.film);
}

TEST_F(Farm, BadCheckpointsAreRefusedNamingThem) {
  const std::string cp = path("c.film");
  ASSERT_EQ(render({"-o", path("x.exr"), "--checkpoint", cp, "--time-limit", "1e-9"}).code, 4);
  const std::string bytes = temp_.read("c.film");
  auto resumeFrom = [&](const std::string& file, std::vector<std::string> more = {}) {
    std::vector<std::string> args = {"-o", path("y.exr"), "--checkpoint", file, "--resume"};
    args.insert(args.end(), more.begin(), more.end());
    return render(args);
  };
  auto expectRefused = [&](const RunResult& r, const std::string& file, const std::string& why) {
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_THAT(r.err, HasSubstr(file));
    EXPECT_THAT(r.err, HasSubstr(why));
    EXPECT_FALSE(fs::exists(path("y.exr")));
  };
  temp_.write("truncated.film", bytes.substr(0, bytes.size() / 2));
  expectRefused(resumeFrom(path("truncated.film")), "truncated.film", "truncated");
  std::string flipped = bytes;
  flipped[bytes.size() - 100] ^= 0x10;
  temp_.write("corrupt.film", flipped);
  expectRefused(resumeFrom(path("corrupt.film")), "corrupt.film", "checksum");
  temp_.write("junk.film", "not a film at all, just text");
  expectRefused(resumeFrom(path("junk.film")), "junk.film", "not a .film file");
  rewrite(cp, path("old.film"), [](FilmFileHeader& h) { h.programVersion = "0.0.1"; });
  expectRefused(resumeFrom(path("old.film")), "old.film", "written by rayes 0.0.1");
  expectRefused(resumeFrom(cp, {"--spp", "3"}), "c.film", "other settings: spp 2 in it, 3 in this render");
  expectRefused(resumeFrom(cp, {"--crop", "0,0,4,4"}), "c.film", "another crop");
  // Another scene file: the same settings, other bytes.
  const std::string other = temp_.write("other.json", rectLightOverMirrorJson(13, 10, 2) + "\n");
  const RunResult r = runRayes({"render", other, "-q", "--photons", "500", "--beam-resolution", "16", "-o",
                                path("y.exr"), "--checkpoint", cp, "--resume"});
  expectRefused(r, "c.film", "another scene file");
  EXPECT_EQ(temp_.read("c.film"), bytes) << "a refused checkpoint is left as it was";
}

TEST_F(Farm, BadPartsAreRefusedNamingThem) {
  const std::vector<std::string> files = parts(3);
  auto expectRefused = [&](const RunResult& r, const std::string& named, const std::string& why) {
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_THAT(r.err, HasSubstr(named));
    EXPECT_THAT(r.err, HasSubstr(why));
    EXPECT_FALSE(fs::exists(path("m.exr")));
    EXPECT_FALSE(fs::exists(path("m.png")));
  };
  expectRefused(merge({files[0], files[2]}, {"-o", path("m.exr")}), "part 2/3", "missing");
  expectRefused(merge({files[0], files[1], files[1], files[2]}, {"-o", path("m.exr")}), "pt-part-2.film", "given twice");
  // A part of another render: other samples per pixel.
  const RunResult r = render({"--part", "2/3", "--spp", "3", "-o", path("spp3.film")});
  ASSERT_EQ(r.code, 0) << r.err;
  expectRefused(merge({files[0], path("spp3.film"), files[2]}, {"-o", path("m.exr")}), "spp3.film", "spp 3 in it, 2 in " + files[0]);
  // A part of another split.
  ASSERT_EQ(render({"--part", "2/4", "-o", path("of4.film")}).code, 0);
  expectRefused(merge({files[0], path("of4.film"), files[2]}, {"-o", path("m.exr")}), "of4.film", "part 2/4");
  const std::string bytes = temp_.read("pt-part-3.film");
  temp_.write("cut.film", bytes.substr(0, bytes.size() - 7));
  expectRefused(merge({files[0], files[1], path("cut.film")}, {"-o", path("m.exr")}), "cut.film", "truncated");
  // An unfinished checkpoint is not a part.
  ASSERT_EQ(render({"-o", path("x.exr"), "--checkpoint", path("c.film"), "--time-limit", "1e-9"}).code, 4);
  expectRefused(merge({path("c.film")}, {"-o", path("m.exr")}), "c.film", "unfinished checkpoint");
  EXPECT_EQ(render({"--part", "1/3", "-o", path("p.exr")}).code, 2) << "a part is a .film";
  EXPECT_EQ(render({"--part", "4/3", "-o", path("p.film")}).code, 2);
  EXPECT_EQ(render({"--crop", "5,5,5,9", "-o", path("p.exr")}).code, 2) << "an empty crop";
  EXPECT_EQ(render({"--crop", "0,0,14,10", "-o", path("p.exr")}).code, 2) << "outside the image";
}

TEST_F(Farm, AnUnwritableCheckpointIsRefusedBeforeRendering) {
  temp_.write("file", "x");
  const RunResult r = render({"-o", path("x.exr"), "--checkpoint", path("file/c.film")});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("file/c.film: cannot create the folder for the checkpoint"));
  fs::create_directories(path("dir"));
  EXPECT_EQ(render({"-o", path("x.exr"), "--checkpoint", path("dir")}).code, 2);
  EXPECT_EQ(render({"-o", path("x.exr"), "--checkpoint", path("x.exr")}).code, 2) << "the output itself";
  EXPECT_FALSE(fs::exists(path("x.exr")));
}

}  // namespace
}  // namespace rayes::testing
