// Photon counts checked against memory before any photon is traced (photon_mapper.h,
// checkPhotonMemory): the largest map's worst case (every light path stores a photon) must fit
// the budget (half of physical memory by default) and 2^32 - 1 photons, or the render is
// refused with ResourceError("--photons"), exit code 3 on the command line. The documented
// maximum, --photons 4294967296, used to run for minutes and die with bad_alloc at 3.7 GB.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include "core/error.h"
#include "core/memory.h"
#include "photons/photon_mapper.h"
#include "support/mirror_caustic_scene.h"
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {

RenderOptions photons(const std::string& method, uint64_t perSample, uint64_t budget = 0) {
  RenderOptions o;
  o.method.name = method;
  o.method.photons.photonsPerSample = perSample;
  o.method.photons.memoryBytes = budget;
  return o;
}

TEST(PhotonMemory, TheLargestMapIsPmsWholeMapAndPpmsLargestPass) {
  PhotonOptions o;
  o.photonsPerSample = 1000;
  EXPECT_EQ(largestPhotonMap(o, 5), 5000u);
  o.progressive = true;  // passes of 1, 1, 2, 1 samples at 5 spp; 1, 1, 2, 4, 8 at 16
  EXPECT_EQ(largestPhotonMap(o, 1), 1000u);
  EXPECT_EQ(largestPhotonMap(o, 5), 2000u);
  EXPECT_EQ(largestPhotonMap(o, 16), 8000u);
  EXPECT_EQ(largestPhotonMap(o, 17), 8000u);
}

TEST(PhotonMemory, TheBudgetIsTheWorstCaseExactly) {
  PhotonOptions o;
  o.photonsPerSample = 1000;
  o.memoryBytes = photonMapPeakBytes(4000) + 123;
  EXPECT_NO_THROW(checkPhotonMemory(o, 4, 123));
  EXPECT_THROW(checkPhotonMemory(o, 4, 124), ResourceError);
  EXPECT_THROW(checkPhotonMemory(o, 5, 0), ResourceError);
  // Past 2^32 - 1 photons in one map, whatever the memory.
  o.memoryBytes = ~uint64_t(0);
  o.photonsPerSample = uint64_t(1) << 31;
  EXPECT_NO_THROW(checkPhotonMemory(o, 1, 0));
  EXPECT_THROW(checkPhotonMemory(o, 2, 0), ResourceError);
}

// The refusal comes from the Renderer's set-up, before the first light pass: constructing it is
// enough (nothing is traced; the test takes milliseconds, where tracing 2^32 photons would take
// minutes).
TEST(PhotonMemory, TooManyPhotonsAreRefusedBeforeTracing) {
  const Scene scene = testing::mirrorCausticScene(8, 6, 1);
  for (const char* m : {"pm", "ppm"}) {
    EXPECT_THROW(Renderer(scene, photons(m, uint64_t(1) << 32)), ResourceError) << m;
    // Under a small budget: the message names the option, the bytes needed and the budget.
    try {
      Renderer r(scene, photons(m, 1000000, 1 << 20));
      ADD_FAILURE() << m << ": not refused";
    } catch (const ResourceError& e) {
      EXPECT_EQ(e.file(), "--photons");
      EXPECT_THAT(e.what(), ::testing::HasSubstr(readableBytes(photonMapPeakBytes(1000000))));
      EXPECT_THAT(e.what(), ::testing::HasSubstr("1 MiB"));
    }
    EXPECT_NO_THROW(Renderer(scene, photons(m, 1000)));
  }
}

TEST(PhotonMemory, TheCommandLineExitsWith3NamingTheOptionAndWritesNothing) {
  const testing::TempFolder tmp;
  for (const char* m : {"pm", "ppm"}) {
    const testing::RunResult r =
        testing::runRayes({"render", testing::sourcePath("scenes/caustic-closed-form.json"), "--method", m, "--photons",
                           "4294967296", "--res", "8x8", "--spp", "1", "-q", "-o", tmp.path("o.exr")});
    EXPECT_EQ(r.code, 3) << r.err;
    EXPECT_THAT(r.err, ::testing::HasSubstr("rayes: --photons: "));
    EXPECT_THAT(r.err, ::testing::Not(::testing::HasSubstr("internal error")));
  }
  EXPECT_TRUE(tmp.entries().empty());
}

}  // namespace
}  // namespace rayes
