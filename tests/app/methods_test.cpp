// The methods' factory (app/methods.h): every name on the command line makes an Integrator that
// reports its own traits and statistics; a wrong name or a combination a method cannot render
// is refused naming the option; the Renderer schedules what the traits say.
#include <gtest/gtest.h>
#include <memory>
#include "app/methods.h"
#include "app/render_data.h"
#include "core/error.h"
#include "lbt/beam_integrator.h"
#include "support/mirror_caustic_scene.h"
#include "support/render_fixtures.h"

namespace rayes::testing {
namespace {

TEST(Methods, EveryNameMakesAnIntegratorWithTwoRaySlotsPerPath) {
  const Scene scene = mirrorCausticScene(8, 6, 1);
  const RenderData data(scene);
  ASSERT_EQ(methodNames().size(), 5u);
  for (const std::string& name : methodNames()) {
    MethodOptions o;
    o.name = name;
    const std::unique_ptr<Integrator> integrator = makeMethod(o, scene, data);
    ASSERT_NE(integrator, nullptr) << name;
    EXPECT_EQ(integrator->raysPerPath(), kRaysPerPath) << name;
    EXPECT_GT(integrator->bytesPerPath(), 0u) << name;
    // Only progressive photon mapping is defined by its passes.
    EXPECT_EQ(integrator->traits().progressive, name == "ppm") << name;
    // The photon methods trace their photons in light passes before the camera paths.
    EXPECT_EQ(integrator->traits().lightPasses, name == "pm" || name == "ppm") << name;
    // Before prepare() nothing is traced: one round per camera batch.
    EXPECT_EQ(integrator->roundsPerBatch(), 1u) << name;
  }
}

TEST(Methods, AnUnknownNameIsRefusedNamingTheOption) {
  MethodOptions o;
  o.name = "bdpt";
  try {
    checkMethodOptions(o);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(e.message().find("--method"), std::string::npos) << e.message();
    EXPECT_NE(e.message().find("bdpt"), std::string::npos) << e.message();
  }
}

TEST(Methods, CausticMethodsRefuseRenderingWithoutTheirCausticPaths) {
  for (const char* name : {"pm", "ppm", "lbt"}) {
    MethodOptions o;
    o.name = name;
    o.causticPaths = CausticPaths::Without;
    EXPECT_THROW(checkMethodOptions(o), InputError) << name;
    o.causticPaths = CausticPaths::Only;
    EXPECT_NO_THROW(checkMethodOptions(o)) << name;
  }
  for (const char* name : {"pt", "lt"}) {
    MethodOptions o;
    o.name = name;
    o.causticPaths = CausticPaths::Without;
    EXPECT_NO_THROW(checkMethodOptions(o)) << name;
  }
}

TEST(Methods, TheRendererTakesPassesFromTheTraitsAndTheSectionFromTheMethod) {
  const Scene scene = mirrorCausticScene(8, 6, 2);
  RenderOptions o;
  o.method.name = "ppm";
  o.method.photons.photonsPerSample = 100;
  EXPECT_TRUE(Renderer(scene, o).stats().progressive);
  o.method.name = "pm";
  EXPECT_FALSE(Renderer(scene, o).stats().progressive);
  EXPECT_TRUE(Renderer(scene, o).stats().method.section.empty());  // pm keeps its figures in totals
  o.method.name = "lbt";
  o.method.beams.resolution = 8;
  const Renderer lbt(scene, o);
  EXPECT_EQ(lbt.stats().method.section, "beams");
  EXPECT_FALSE(lbt.stats().method.wasSkipped("beams"));
  EXPECT_GT(lbt.stats().method.number("segments"), 0);
  EXPECT_NE(dynamic_cast<const BeamIntegrator*>(&lbt.integrator()), nullptr);
}

}  // namespace
}  // namespace rayes::testing
