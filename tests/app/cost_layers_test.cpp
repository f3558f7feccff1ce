// The per-pixel cost layers (`rayes render --cost-layers`, app/pixel_cost.h): dicings.Y holds
// every dicing of the camera paths, shared among the rays that caused it, so its total is the
// stats' dicings; it and lod.Y are the same bits at any thread count; time.Y shares the
// measured batch times among the pixels. Without the option the EXR has no such layers and the
// render keeps no per-ray shares.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "support/exr_image.h"
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {
using json = nlohmann::json;

const std::string kScene = std::string(RAYES_SOURCE_DIR) + "/scenes/teapot.json";

class CostLayers : public ::testing::Test {
 protected:
  // Renders the teapot into NAME.exr and NAME.json with `more` options; returns the stats.
  json render(const std::string& name, const std::vector<std::string>& more) {
    std::vector<std::string> args = {"render", kScene, "--res", "32x24", "--spp", "2", "-o", temp_.path(name + ".exr"),
                                     "--stats", temp_.path(name + ".json"), "-q"};
    args.insert(args.end(), more.begin(), more.end());
    const auto r = testing::runRayes(args);
    EXPECT_EQ(r.code, 0) << r.err;
    return json::parse(temp_.read(name + ".json"));
  }
  testing::ExrImage image(const std::string& name) { return testing::readExrImage(temp_.path(name + ".exr")); }
  testing::TempFolder temp_;
};

double sum(const std::vector<float>& v) {
  double s = 0;
  for (float x : v) s += double(x);
  return s;
}

// The layer's pixels are the exact fixed-point sums rounded once to float (relative error at
// most 2^-24 each), so their total is within D · 2^-24 of the exact total D, plus the double
// summation's n · 2^-53 · D.
double floatSumBound(double total, size_t n) { return total * (std::ldexp(1.0, -24) + double(n) * std::ldexp(1.0, -53)); }

TEST_F(CostLayers, DicingsLayerHoldsEveryDicingOfTheCameraPaths) {
  const json s = render("one", {"--cost-layers", "--threads", "2"});
  const double dicings = s["totals"]["leaves_diced"].get<double>();
  ASSERT_GT(dicings, 0);
  // pt: every dicing is a camera path's, charged exactly (shares sum to one dicing each).
  EXPECT_EQ(s["cost_layers"]["dicings_charged"].get<double>(), dicings);
  EXPECT_EQ(s["cost_layers"]["dicings_not_charged"].get<double>(), 0.0);
  const testing::ExrImage im = image("one");
  const std::vector<float>& d = im.channels.at("dicings.Y");
  EXPECT_NEAR(sum(d), dicings, floatSumBound(dicings, d.size()));
  for (float v : d) EXPECT_TRUE(std::isfinite(v) && v >= 0) << v;
  // The stats name the image relative to their own folder.
  EXPECT_EQ(s["cost_layers"]["image"], "one.exr");
}

TEST_F(CostLayers, TimeLayerSharesTheMeasuredBatchTimes) {
  const json s = render("t", {"--cost-layers"});
  const testing::ExrImage im = image("t");
  const std::vector<float>& t = im.channels.at("time.Y");
  const double charged = s["cost_layers"]["time_charged_s"].get<double>();
  EXPECT_GT(charged, 0);
  EXPECT_LE(charged, s["totals"]["time_s"]["total"].get<double>());
  EXPECT_NEAR(sum(t), charged, floatSumBound(charged, t.size()));
  for (float v : t) EXPECT_TRUE(std::isfinite(v) && v >= 0) << v;
}

TEST_F(CostLayers, LodAndDicingsAreTheSameBitsAtAnyThreadCount) {
  render("t1", {"--cost-layers", "--threads", "1"});
  render("t2", {"--cost-layers", "--threads", "2"});
  const testing::ExrImage a = image("t1"), b = image("t2");
  for (const char* layer : {"lod.Y", "dicings.Y", "R", "G", "B"}) {
    const std::vector<float>&x = a.channels.at(layer), &y = b.channels.at(layer);
    ASSERT_EQ(x.size(), y.size());
    EXPECT_EQ(std::memcmp(x.data(), y.data(), x.size() * sizeof(float)), 0) << layer;
  }
}

// Several batches by pixel blocks, and the engines that dice per ray: still every dicing charged.
TEST_F(CostLayers, EveryEngineAndBatchingChargesEveryDicing) {
  for (const auto& [name, more] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"blocks", {"--ray-memory", "200K"}}, {"alone", {"--trace-mode", "alone"}}, {"cache", {"--dice-cache", "8"}}}) {
    std::vector<std::string> args = more;
    args.push_back("--cost-layers");
    const json s = render(name, args);
    const double dicings = s["totals"]["leaves_diced"].get<double>();
    EXPECT_GT(dicings, 0) << name;
    EXPECT_EQ(s["cost_layers"]["dicings_charged"].get<double>(), dicings) << name;
    const testing::ExrImage im = image(name);
    const std::vector<float>& d = im.channels.at("dicings.Y");
    EXPECT_NEAR(sum(d), dicings, floatSumBound(dicings, d.size())) << name;
  }
}

TEST_F(CostLayers, WithoutTheOptionThereAreNoLayersAndNoCost) {
  const json s = render("plain", {});
  const testing::ExrImage im = image("plain");
  EXPECT_EQ(im.channels.count("dicings.Y"), 0u);
  EXPECT_EQ(im.channels.count("time.Y"), 0u);
  EXPECT_EQ(im.channels.count("lod.Y"), 1u);  // always written
  EXPECT_FALSE(s.contains("cost_layers"));
  EXPECT_TRUE(s["skipped"].contains("cost_layers"));
  EXPECT_EQ(s["memory"]["by_owner"]["cost_layers"], 0);
  // And the ray budget's path is dearer with them (the shares and counts are in it).
  const json with = render("with", {"--cost-layers"});
  EXPECT_GT(with["memory"]["bytes_per_path"].get<double>(), s["memory"]["bytes_per_path"].get<double>());
  EXPECT_GT(with["memory"]["by_owner"]["cost_layers"].get<double>(), 0);
}

TEST_F(CostLayers, NeedAnExrAndAWholeRender) {
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"render", kScene, "--res", "8x6", "--cost-layers", "-o", temp_.path("p.png")},
           {"render", kScene, "--res", "8x6", "--cost-layers", "--resume", "-o", temp_.path("r.exr")}}) {
    const auto r = testing::runRayes(args);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("--cost-layers"), std::string::npos) << r.err;
  }
  EXPECT_TRUE(temp_.entries().empty());
}

TEST_F(CostLayers, TheReportFindsTheLayersThroughTheStats) {
  render("r", {"--cost-layers"});
  ASSERT_EQ(testing::runRayes({"report", temp_.path("r.json"), "-o", temp_.path("page.html"), "-q"}).code, 0);
  const std::string page = temp_.read("page.html");
  for (const char* layer : {"data-layer=beauty", "data-layer=lod", "data-layer=dicings", "data-layer=time"})
    EXPECT_NE(page.find(layer), std::string::npos) << layer;
  // Moved away from its image, the page is still made, and says the image is missing.
  std::filesystem::rename(temp_.path("r.exr"), temp_.path("gone.exr"));
  ASSERT_EQ(testing::runRayes({"report", temp_.path("r.json"), "-o", temp_.path("page2.html"), "-q"}).code, 0);
  const std::string page2 = temp_.read("page2.html");
  EXPECT_EQ(page2.find("data-layer=dicings"), std::string::npos);
  EXPECT_NE(page2.find("it is not there"), std::string::npos);
}

}  // namespace
}  // namespace rayes
