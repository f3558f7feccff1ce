#include "app/stats_json.h"
#include "core/error.h"
#include "core/memory.h"
#include "core/vector_isa.h"
#include "core/version.h"

namespace rayes {

nlohmann::json statsToJson(const Scene& scene, const RenderOptions& options, const RenderStats& s,
                           const RunInfo& run) {
  using json = nlohmann::json;
  json j;
  j["stats_version"] = kStatsVersion;
  j["scene"] = {{"file", run.scenePath}, {"leaves", scene.leaves.size()}, {"resolution", {run.width, run.height}},
                {"spp", run.spp}};
  json kinds = json::object();
  for (const auto& [k, n] : s.leafKinds) kinds[k] = n;
  j["scene"]["leaf_kinds"] = kinds;
  // Every position the render works with is relative to this world point (the camera's):
  // Scene::frame, docs/design.md "The render frame".
  j["scene"]["render_frame_origin"] = {scene.frame.origin.x, scene.frame.origin.y, scene.frame.origin.z};
  if (scene.compiled) {
    const MappedFileStats m = scene.compiled->stats();
    j["scene"]["compiled"] = {{"bytes_mapped", m.bytesMapped},     {"resident_peak_bytes", m.residentPeak},
                              {"bytes_read", m.bytesRead},         {"blocks_verified", m.blocksVerified},
                              {"blocks_released", m.blocksReleased}, {"scene_memory_bytes", m.budget},
                              {"resident_at_end_bytes", m.residentAtEnd},
                              {"top_level", scene.compiled->has(compiled::SectionKind::TopLevel) ? "stored" : "built"}};
  }
  j["settings"] = {{"threads", run.threads}, {"method", options.method.name}, {"max_lod", options.maxLod},
                   {"lod", options.lod == LodRule::PerRay ? "per-ray" : options.lod == LodRule::Density ? "density" : "fixed"},
                   {"trace_mode", options.sortByLeaf ? "sorted" : "alone"},
                   {"lod_bias", options.lodBias},
                   {"resident_lod", options.residentLod},
                   {"candidates_per_ray", options.candidatesPerRay},
                   {"dice_cache_entries", options.diceCacheEntries},
                   {"grid_cache_bytes", options.gridCacheBytes},
                   {"texture_memory_bytes", options.textureMemoryBytes},
                   {"progressive", s.progressive},
                   {"ray_memory_bytes", options.rayMemoryBytes},
                   {"vector_isa", vectorIsaName(vectorIsa())},
                   {"program_version", programVersion()}};

  json gens = json::array();
  uint64_t diced = 0, created = 0, rays = 0, shadow = 0;
  std::array<uint64_t, GenerationStats::kLevels> byLevel{};
  for (const auto& g : s.generations) {
    json its = json::array();
    for (const auto& it : g.stats.iterations)
      its.push_back({{"active_rays", it.activeRays}, {"candidates_per_ray", it.candidatesPerRay},
                     {"candidates", it.candidates}, {"dicings", it.dicings}, {"grid_cache_hits", it.cacheHits}});
    gens.push_back({{"pass", g.pass}, {"batch", g.batch}, {"depth", g.depth}, {"rays", g.stats.rays},
                    {"shadow_rays", g.stats.shadowRays}, {"iterations", its},
                    {"leaves_diced", g.stats.leavesDiced}, {"grid_cache_hits", g.stats.gridCacheHits},
                    {"origin_leaf_dicings", g.stats.originLeafDicings},
                    {"micropolygons_created", g.stats.micropolygonsCreated},
                    {"start_s", g.time.start},
                    {"time_s", {{"trace", g.time.trace}, {"toplevel", g.time.toplevel}, {"sort", g.time.sort},
                                {"shade", g.time.shade}, {"dice", g.time.dice}, {"bottom", g.time.bottom},
                                {"leaf_queries", g.time.leafQueries}}}});
    diced += g.stats.leavesDiced;
    created += g.stats.micropolygonsCreated;
    rays += g.stats.rays;
    shadow += g.stats.shadowRays;
    for (size_t m = 0; m < byLevel.size(); ++m) byLevel[m] += g.stats.dicingsByLevel[m];
  }
  // Keyed by level so that merged parts sum level by level (app/batch_job.cpp).
  json lodHistogram = json::object();
  for (size_t m = 0; m < byLevel.size(); ++m)
    if (byLevel[m]) lodHistogram[std::to_string(m)] = byLevel[m];
  j["generations"] = gens;

  j["totals"] = {
      {"rays", rays},
      {"shadow_rays", shadow},
      {"leaves_diced", diced},
      {"rays_per_dicing", diced ? double(rays) / double(diced) : 0.0},
      {"micropolygons_created", created},
      {"micropolygons_potential", s.micropolygonsPotential},
      {"dicings_by_level", lodHistogram},
      {"batches", s.batches},
      {"pixels_per_block", s.pixelsPerBlock},
      {"nonfinite_samples_dropped", s.shade.nonFinite.load()},
      {"splats", s.shade.splats.load()},
      {"splat_saturations", s.splatSaturations},
      {"photons_traced", s.shade.photonsTraced.load()},
      {"photons_stored", s.shade.photonsStored.load()},
      {"photon_map_bytes", s.shade.photonMapBytes.load()},
      {"caustic_gathers", s.shade.gathers.load()},
      {"caustic_gathers_skipped", s.shade.gathersSkipped.load()},
      {"peak_rss_bytes", peakRssBytes()},
      {"time_s",
       {{"load", run.loadSeconds},
        {"setup", s.timeSetup},
        {"toplevel", s.trace.toplevel.seconds()},
        {"sort", s.trace.sort.seconds()},
        {"dice", s.trace.dice.seconds()},
        {"bottom", s.trace.bottom.seconds()},
        {"leaf_queries", s.trace.leafQueries.seconds()},
        {"shade", s.shade.shade.seconds()},
        {"shade_sort", s.shade.sort.seconds()},
        {"film", s.timeFilm},
        {"total", s.timeTotal},
        {"wall", run.wallSeconds}}},
      {"mrays_per_s", s.timeTotal > 0 ? double(rays) / s.timeTotal * 1e-6 : 0.0},
  };
  j["memory"] = {{"limit_bytes", processMemoryLimit().bytes},
                 {"limit_source", processMemoryLimit().source},
                 {"ray_budget_bytes", options.rayMemoryBytes},
                 {"bytes_per_path", s.bytesPerPath},
                 {"bytes_per_ray", s.raysPerPath ? s.bytesPerPath / s.raysPerPath : 0},
                 {"paths_per_batch", s.pathsPerBatch},
                 {"candidate_capacity", s.candidateCapacity},
                 {"toplevel_bytes", s.topLevelBytes},
                 {"dice_buffer_bytes", s.diceBufferBytes}};
  const MemoryByOwner& m = s.memory;
  j["memory"]["by_owner"] = {
      {"ray_buffers", m.rayBuffers},
      {"candidates_and_sort", m.candidatesAndSort},
      {"top_level", m.topLevel},
      {"dice_buffers", m.diceBuffers},
      {"dice_cache", m.diceCache},
      {"border_bounds", m.borderBounds},
      {"film", m.film},
      {"scene_description", m.sceneDescription},
      {"uv_sets", m.uvSets},
      {"cost_layers", m.costLayers},
      // lbt: the --beam-memory account's peak (beams.peak_bytes), the grids kept while beams
      // are traced included; 0 for the other methods and when no beams were built.
      {"beams", s.method.section == "beams" ? uint64_t(s.method.number("peak_bytes")) : uint64_t(0)},
  };
  json overTime = json::array();
  for (const MemorySample& x : s.memoryOverTime)
    overTime.push_back({{"t_s", x.seconds},
                        {"ray_buffers", x.rayBuffers},
                        {"candidates_and_sort", x.candidatesAndSort},
                        {"dice_buffers", x.diceBuffers},
                        {"dice_cache", x.diceCache},
                        {"border_bounds", x.borderBounds},
                        {"film", x.film},
                        {"rss_bytes", x.rss}});
  j["memory_over_time"] = overTime;
  j["memory"]["scene_bytes_per_leaf"] = m.leaves ? double(m.sceneDescription) / double(m.leaves) : 0.0;
  j["memory"]["peak_rss_bytes"] = peakRssBytes();
  const EngineStats& e = s.engine;
  j["engine"] = {{"name", e.name}, {"fixed_bytes", e.fixedBytes}};
  if (options.diceCacheEntries > 0 && options.engine == EngineKind::Rayes) {
    j["engine"].update({{"cache_entries", e.cacheEntries},
                        {"cache_hits", e.cacheHits},
                        {"cache_misses", e.cacheMisses},
                        {"cache_peak_bytes", e.cachePeakBytes}});
  }
  if (options.engine == EngineKind::Embree) {
    j["engine"].update({{"lod", options.embreeAutoLod ? "auto" : "fixed"},
                        {"min_level", e.minLevel},
                        {"max_level", e.maxLevel},
                        {"micropolygons", e.micropolygons},
                        {"vertices", e.vertices},
                        {"vertex_bytes", e.vertexBytes},
                        {"embree_bytes", e.embreeBytes},
                        {"embree_peak_bytes", e.embreePeakBytes},
                        {"estimated_bytes", e.estimatedBytes},
                        {"memory_limit_bytes", options.memoryLimitBytes},
                        {"time_s", {{"tessellate", e.tessellateSeconds}, {"build", e.buildSeconds}}}});
  }
  // docs/design.md, invariant 4: what this scene used, and what it did not need and was not done.
  const SceneFeatures& f = s.features;
  uint64_t movingDicings = 0, borderHits = 0, originLeafDicings = 0, gridCacheHits = 0, splitRuns = 0, subLeafDicings = 0;
  uint64_t subLeafCacheHits = 0;
  for (const auto& g : s.generations) {
    splitRuns += g.stats.splitRuns;
    subLeafDicings += g.stats.subLeafDicings;
    subLeafCacheHits += g.stats.subLeafCacheHits;
    gridCacheHits += g.stats.gridCacheHits;
    movingDicings += g.stats.movingDicings;
    borderHits += g.stats.borderHits;
    originLeafDicings += g.stats.originLeafDicings;
  }
  j["totals"]["origin_leaf_dicings"] = originLeafDicings;
  j["totals"]["grid_cache_hits"] = gridCacheHits;
  j["totals"]["split_runs"] = splitRuns;
  j["totals"]["sub_leaf_dicings"] = subLeafDicings;
  j["totals"]["sub_leaf_cache_hits"] = subLeafCacheHits;
  j["features"] = {
      {"motion_blur", f.movingLeaves > 0 && f.shutterOpen},
      {"moving_leaves", f.movingLeaves},
      {"moving_dicings", movingDicings},
      {"displacement", f.displacedLeaves > 0},
      {"displaced_leaves", f.displacedLeaves},
      {"subdivision_leaves", f.subdivisionLeaves},
      {"border_closure_leaves", f.borderClosureLeaves},
      {"border_region_hits", borderHits},
      {"uv_leaves", f.uvLeaves},
      {"environment_light", f.environment},
      {"textured_materials", f.texturedMaterials},
      {"coarsest_relative_spacing", f.coarsestRelativeSpacing},
      {"low_precision_leaves", f.lowPrecisionLeaves},
  };
  json skipped = json::object();
  if (f.movingLeaves == 0) skipped["motion_blur"] = "no moving shapes: one time sample stored and diced, no time per ray";
  else if (!f.shutterOpen) skipped["motion_blur"] = "the shutter has no interval: moving shapes seen at the opening time";
  if (f.displacedLeaves == 0) skipped["displacement"] = "no displaced shapes: no interval evaluation";
  if (f.borderClosureLeaves == 0) skipped["border_closure"] = "every patch border is straight: no crack-closing regions";
  if (f.texturedMaterials == 0)
    skipped["texture_footprint"] = "no material reads a texture: no surface derivatives per ray, no footprint";
  if (!f.environment) skipped["environment"] = "no environment light: escaping rays gather nothing";
  if (f.uvSetsDropped) skipped["uv_sets"] = "no texture reads uv coordinates: the shapes' uv sets were left out at load";
  else if (f.uvLeaves == 0) skipped["uv_sets"] = "no shape has a uv set: textures read the patch parameters";
  // The method's own section (beams), or why it was not built; a method without beams says so.
  for (const auto& [section, why] : s.method.skipped) skipped[section] = why;
  if (!s.method.section.empty() && !s.method.wasSkipped(s.method.section)) {
    json section = json::object();
    for (const auto& [key, value] : s.method.values) {
      json* at = &section;
      std::string_view rest = key;
      for (size_t dot; (dot = rest.find('.')) != std::string_view::npos; rest = rest.substr(dot + 1))
        at = &(*at)[std::string(rest.substr(0, dot))];
      std::visit([&](const auto& v) { (*at)[std::string(rest)] = v; }, value);
    }
    j[s.method.section] = section;
  }
  if (s.method.section != "beams" && !skipped.contains("beams"))
    skipped["beams"] = "--method " + options.method.name + " traces no beams";
  if (f.volumes == 0) {
    skipped["volumes"] = "no volume in the scene: OpenVDB not loaded, no tracking";
  } else {
    j["volumes"] = {{"volumes", f.volumes},
                    {"bricks", f.volumeBricks},
                    {"voxels_read", f.volumeVoxels},
                    {"bytes", f.volumeBytes},
                    {"collisions", s.shade.mediumCollisions.load()},
                    {"transmittance_estimates", s.shade.transmittanceEstimates.load()},
                    {"density_lookups", s.shade.densityLookups.load()},
                    {"brick_cells_walked", s.shade.brickCellsWalked.load()},
                    {"emitting_volumes", f.emittingVolumes},
                    {"time_s", {{"load", f.volumeLoadSeconds}, {"tracking", s.shade.volume.seconds()}}}};
    if (f.emittingVolumes == 0) skipped["volume_emission"] = "no volume has an emission or temperature grid: no emission work";
    else j["volumes"]["emission_lookups"] = s.shade.emissionLookups.load();
    if (s.volumeCache) {
      const BrickCacheStats& c = *s.volumeCache;
      j["volumes"]["cache"] = {{"budget_bytes", c.budgetBytes},
                               {"slots", c.slots},
                               {"peak_bytes", c.slotsUsed * BrickCache::kSlotBytes},
                               {"bricks_loaded", c.loads},
                               {"hits", c.hits},
                               {"hit_rate", c.hitRate()},
                               {"evictions", c.evictions},
                               {"voxels_read", c.voxelsRead},
                               {"bytes_read", c.bytesRead}};
      j["volumes"]["time_s"]["brick_reads"] = c.loadSeconds;
    } else {
      skipped["volume_cache"] = "no volume reads bricks from a file";
    }
  }
  if (s.textures) {
    const TextureCacheStats& t = *s.textures;
    j["textures"] = {{"files", t.files},
                     {"conversions", t.conversions},
                     {"image_bytes", t.imageBytes},
                     {"tiles_read", t.tilesRead},
                     {"bytes_read", t.bytesRead},
                     {"tile_lookups", t.tileLookups},
                     {"hit_rate", t.hitRate},
                     {"peak_tiles", t.peakTiles},
                     {"cache_memory_bytes", t.memoryBytes},
                     {"texture_memory_bytes", t.memoryLimitBytes},
                     {"io_time_s", t.ioSeconds}};
  } else {
    skipped["textures"] = "no image texture, environment map or height map: no texture cache, OpenImageIO not loaded";
  }
  if (s.costLayers) {
    j["cost_layers"] = {{"image", ""},
                        {"layers", {"lod.Y", "dicings.Y", "time.Y"}},
                        {"dicings_charged", s.costLayers->dicingsCharged},
                        {"dicings_not_charged", std::max(0.0, double(diced) - s.costLayers->dicingsCharged)},
                        {"time_charged_s", s.costLayers->secondsCharged}};
  } else {
    skipped["cost_layers"] = "no --cost-layers: no dicings or time per pixel";
  }
  if (!options.firstHitAovs)
    skipped["first_hit_aovs"] = "no output reads the AOVs (a PNG preview alone): no first hit recorded or added to the film";
  j["skipped"] = skipped;
  if (!s.errorCurve.empty()) {
    json curve = json::array();
    for (const auto& e : s.errorCurve) curve.push_back({{"spp", e.spp}, {"time_s", e.seconds}, {"rmse", e.rmse}});
    j["error_vs_time"] = curve;
  }
  return j;
}

}  // namespace rayes
