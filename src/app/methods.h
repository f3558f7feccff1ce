// START HERE for the methods. Every rendering method is an Integrator (shading/integrator.h),
// made here and only here from the options: the path tracer (pt), the light tracer (lt),
// photon mapping and its progressive form (pm, ppm; src/photons) and light beam tracing (lbt;
// src/lbt). Nothing else in the program names a method: the Renderer schedules whatever this
// returns through the Integrator interface and its traits, and the stats file gets a method's
// own section from Integrator::methodStats. A new method is one more name here and one
// Integrator.
#pragma once
#include <memory>
#include <string>
#include <vector>
#include "app/render_data.h"
#include "lbt/beam_integrator.h"
#include "photons/photon_mapper.h"
#include "scene/scene.h"
#include "shading/integrator.h"

namespace rayes {

// What the methods take besides the scene; each reads its own part.
struct MethodOptions {
  std::string name = "pt";                // one of methodNames()
  CausticPaths causticPaths = CausticPaths::All;
  // The probability a caustic estimate is taken at a diffuse vertex after the path's first
  // (--later-gathers; PathTracer::Options::laterGatherProbability), for the caustic methods.
  float laterGatherProbability = kLaterGatherProbability;
  // Photon mapping's counts, k, radius and alpha (its progressive flag, caustic paths and
  // later-gather probability are set from the fields above by makeMethod).
  PhotonOptions photons;
  BeamOptions beams;
};

// "pt", "lt", "pm", "ppm", "lbt": the names of the command line and the stats.
const std::vector<std::string>& methodNames();
// Checks the name and the options that depend on the method; throws InputError naming the
// option (--method, --caustic-paths).
void checkMethodOptions(const MethodOptions& options);
// The memory a method's own budget lets it take besides the ray budget (lbt: --beam-memory;
// 0 for the others), for the render's memory plan.
size_t methodBudgetBytes(const MethodOptions& options);
// The integrator for options.name over the render's data (which must outlive it). Fast: any
// work through the ray engine waits for Integrator::prepare.
std::unique_ptr<Integrator> makeMethod(const MethodOptions& options, const Scene& scene, const RenderData& data);

}  // namespace rayes
