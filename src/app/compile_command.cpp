// `rayes compile SCENE.json -o SCENE.rayes`: the scene loaded as `render` loads it (bad input
// fails the same way, exit code 2), its leaves written to a compiled scene (scene/
// compiled_scene.h) through an OutputSet: the file appears whole or not at all. The top level
// is built here, as a render builds it (toplevel/, Embree's builder), and stored with them: the
// render of the .rayes adopts it instead of building it.
#include <cstdio>
#include <filesystem>
#include "app/commands.h"
#include "app/output_set.h"
#include "core/error.h"
#include "core/text_file.h"
#include "core/timer.h"
#include "toplevel/toplevel_bvh.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include "scene/compiled_scene.h"
#include "scene/scene_loader.h"

namespace rayes {

int runCompile(const CompileArgs& a) {
  const auto wall0 = Clock::now();
  if (a.scene == "-") throw InputError("-", "", "rayes compile reads a scene file, not standard input (its relative file names need a folder)");
  if (isCompiledSceneName(a.scene)) throw InputError(a.scene, "", "already a compiled scene");
  const std::string out = a.out.empty() ? std::filesystem::path(a.scene).replace_extension(".rayes").string() : a.out;
  if (!isCompiledSceneName(out))
    throw InputError("-o", "", "'" + out + "': a compiled scene's name ends in .rayes (rayes render recognises it by that)");
  const std::string text = readTextFile(a.scene, "scene file");
  const Scene scene = parseScene(text, a.scene);
  for (const std::string& w : scene.warnings) std::fprintf(stderr, "rayes: warning: %s\n", w.c_str());
  // Over every leaf of the render (the shapes' and the lights'), by leaf id, as RenderData
  // builds it for the JSON route.
  TopLevelBvh top;
  {
    std::vector<Box3> boxes(scene.leaves.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, boxes.size(), 1024), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) boxes[i] = scene.leaves.bounds(i);
    });
    top.build(std::move(boxes));
  }
  const TopLevelBvh::Stored tree = top.stored();
  compiled::StoredTopLevel stored;
  stored.nodes = tree.nodes;
  stored.nodeCount = tree.nodeCount;
  stored.nodeBytes = uint32_t(TopLevelBvh::kNodeBytes);
  stored.root = tree.root;
  stored.leafBoxes = top.leafBoxes().data();
  stored.leafCount = top.leafBoxes().size();
  OutputSet outputs;
  outputs.addInput(a.scene);
  outputs.add(out, "compiled scene");
  outputs.write(out, [&](const std::string& tmp) {
    try {
      writeCompiledScene(scene, text, a.scene, tmp, stored);
    } catch (const ResourceError&) {
      throw;
    } catch (const InputError& e) {
      if (e.file() == tmp) throw InputError(out, e.place(), e.what());  // name the target, not its temporary
      throw;
    }
  });
  outputs.commit();
  if (!a.quiet) {
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(out, ec);
    std::fprintf(stderr, "rayes: wrote %s (%zu leaves, %.1f MiB, %.2fs)\n", out.c_str(), scene.shapeLeaves,
                 ec ? 0.0 : double(bytes) / (1 << 20), secondsSince(wall0));
  }
  return 0;
}

}  // namespace rayes
