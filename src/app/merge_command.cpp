// `rayes merge PART.film... -o OUT.exr [-o OUT.png] [-o OUT.film] [--stats S.json]`: the parts of
// a farm split (rayes render --part I/N -o part-I.film) made into one image, the same bits as
// one render of the frame; or one complete .film resolved. Every part must be a finished part of
// the same render (fingerprint, version, size, crop, method, N), each I of 1..N exactly once;
// otherwise the message names the file (or the missing part) and the exit code is 2. Outputs
// are all or nothing (OutputSet).
#include <cstdio>
#include <filesystem>
#include <map>
#include "app/batch_job.h"
#include "app/commands.h"
#include "app/film_file.h"
#include "app/image_io.h"
#include "app/output_set.h"
#include "app/renderer.h"
#include "core/error.h"
#include "core/timer.h"

namespace rayes {
namespace {

std::string partName(int part, int parts) { return std::to_string(part) + "/" + std::to_string(parts); }

}  // namespace

int runMerge(const MergeArgs& a) {
  const auto wall0 = Clock::now();
  if (a.parts.empty()) throw InputError("merge", "", "no part given");
  if (a.outputs.empty()) throw InputError("-o", "", "give the image to write: -o OUT.exr (and/or OUT.png, OUT.film)");
  for (const std::string& o : a.outputs) checkOutputName(o);
  // Every part read and checked before anything is written.
  std::vector<FilmFile> parts;
  for (const std::string& path : a.parts) parts.push_back(readFilmFile(path));
  const FilmFileHeader& first = parts.front().header;
  std::map<int, size_t> byPart;
  for (size_t i = 0; i < parts.size(); ++i) {
    const FilmFileHeader& h = parts[i].header;
    const std::string& path = a.parts[i];
    if (!h.complete)
      throw InputError(path, "", "cannot merge it: an unfinished " + h.kind + " (resume its render with --resume first)");
    // What the part must be: the first part's render, its own part number, and the window
    // (a band of the crop, or for light path ids the crop) that number gives.
    FilmFileHeader expected = first;
    expected.part = h.part;
    expected.window = first.lightPathIds ? first.crop : partBand(first.crop, h.part, first.parts);
    checkSameRender(path, h, expected, "merge", a.parts[0]);
    if (h.parts != first.parts)
      throw InputError(path, "", "cannot merge it: part " + partName(h.part, h.parts) + " of another split than " +
                                     a.parts[0] + " (" + partName(first.part, first.parts) + ")");
    if (const auto [at, fresh] = byPart.emplace(h.part, i); !fresh)
      throw InputError(path, "", "cannot merge it: part " + partName(h.part, h.parts) + " is given twice (also " +
                                     a.parts[at->second] + ")");
  }
  for (int p = 1; p <= first.parts; ++p)
    if (!byPart.count(p)) {
      std::string given;
      for (const auto& [q, i] : byPart) given += (given.empty() ? "" : ", ") + a.parts[i] + " (" + partName(q, first.parts) + ")";
      throw InputError("merge", "", "part " + partName(p, first.parts) + " of " + first.scene + " is missing; given " + given);
    }

  Film merged(first.width, first.height, first.crop);
  std::vector<nlohmann::json> stats;
  for (const auto& [p, i] : byPart) {
    if (!merged.addFilm(parts[i].film))
      throw InputError(a.parts[i], "", "cannot merge it: its pixels overlap another part's");
    stats.push_back(parts[i].header.stats);
  }

  OutputSet outputs;
  for (const std::string& path : a.parts) outputs.addInput(path);
  // An EXR gets its preview beside it, as from rayes render, unless a PNG is named.
  bool pngNamed = false;
  for (const std::string& o : a.outputs) pngNamed = pngNamed || lowerExtension(o) == ".png";
  std::vector<std::pair<std::string, std::string>> writes;  // (path, extension)
  for (const std::string& o : a.outputs) {
    writes.push_back({o, lowerExtension(o)});
    if (lowerExtension(o) == ".exr" && !pngNamed)
      writes.push_back({std::filesystem::path(o).replace_extension(".png").string(), ".png"});
  }
  for (const auto& [path, ext] : writes) outputs.add(path, ext == ".exr" ? "image" : ext == ".png" ? "preview" : "film");
  if (!a.stats.empty()) outputs.add(a.stats, "stats");
  const nlohmann::json combined = combinedStats(stats);
  for (const auto& [path, ext] : writes) {
    if (ext == ".exr") outputs.write(path, [&](const std::string& tmp) { writeExr(tmp, merged); });
    else if (ext == ".png") outputs.write(path, [&](const std::string& tmp) { writePngPreview(tmp, merged); });
    else {
      FilmFileHeader h = first;
      h.kind = "film";
      h.part = h.parts = 1;
      h.window = first.crop;
      h.stats = combined;
      outputs.write(path, [&](const std::string& tmp) { writeFilmFile(tmp, h, merged); });
    }
  }
  if (!a.stats.empty()) outputs.writeText(a.stats, combined.dump(2) + "\n");
  outputs.commit();
  if (!a.quiet)
    std::fprintf(stderr, "rayes: merged %zu part%s into %s (%.2fs)\n", parts.size(), parts.size() == 1 ? "" : "s",
                 a.outputs.front().c_str(), secondsSince(wall0));
  return 0;
}

}  // namespace rayes
