// Batch jobs at the Renderer (docs/batch-and-farm.md): a crop renders the same sums as the
// whole render in its window; the parts of a split, merged, are the whole render's sums bit for
// bit; a render stopped at any batch boundary, or inside a batch after its camera rays added
// their first-hit AOVs to the film, and resumed from its film and position (through a checkpoint
// file) is the uninterrupted render's. For every method (pt, lt, pm, ppm, lbt), on a small caustic scene
// (a rect light over a mirror lighting a ceiling), with row counts the parts do not divide.
#include <algorithm>
#include <cstring>
#include <gtest/gtest.h>
#include "app/film_file.h"
#include "app/renderer.h"
#include "scene/scene_loader.h"
#include "support/beam_scenes.h"
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes::testing {
namespace {

constexpr int kWidth = 13, kHeight = 10;

Scene caustic(int spp = 2) { return parseScene(rectLightOverMirrorJson(kWidth, kHeight, spp), "mirror.json"); }

RenderOptions optionsFor(const std::string& method) {
  RenderOptions o;
  o.method.name = method;
  o.method.photons.photonsPerSample = 500;
  o.method.beams.resolution = 16;
  return o;
}

// Bitwise equality of doubles (so -0 and NaN compare as bits, not values).
bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Every sum of `part`'s window equals `whole`'s in the same pixel, bit for bit (splats too).
void expectSameSums(const Film& whole, const Film& part, const std::string& what) {
  const PixelWindow& w = part.window();
  const Film::Sums &a = whole.sums(), &b = part.sums();
  int bad = 0;
  for (int y = w.y0; y < w.y1 && bad < 5; ++y)
    for (int x = w.x0; x < w.x1 && bad < 5; ++x) {
      const size_t p = size_t(y - whole.window().y0) * size_t(whole.width()) + size_t(x - whole.window().x0);
      const size_t q = size_t(y - w.y0) * size_t(w.width()) + size_t(x - w.x0);
      bool same = a.count[p] == b.count[q] && a.hits[p] == b.hits[q] && a.material[p] == b.material[q] &&
                  sameBits(a.alpha[p], b.alpha[q]) && sameBits(a.depth[p], b.depth[q]) && sameBits(a.lod[p], b.lod[q]);
      for (int c = 0; c < 3; ++c)
        same = same && sameBits(a.rgb[3 * p + c], b.rgb[3 * q + c]) && sameBits(a.normal[3 * p + c], b.normal[3 * q + c]) &&
               sameBits(a.albedo[3 * p + c], b.albedo[3 * q + c]) && a.splat[3 * p + c] == b.splat[3 * q + c];
      if (!same) {
        ++bad;
        ADD_FAILURE() << what << ": pixel (" << x << ", " << y << ") differs (red " << a.rgb[3 * p] << " vs "
                      << b.rgb[3 * q] << ", samples " << a.count[p] << " vs " << b.count[q] << ")";
      }
    }
}

Film renderWith(const Scene& scene, const RenderOptions& options) {
  ThreadLimit limit(2);
  Renderer r(scene, options);
  return r.render();
}

class EveryMethod : public ::testing::TestWithParam<std::string> {};
INSTANTIATE_TEST_SUITE_P(Batch, EveryMethod, ::testing::Values("pt", "lt", "pm", "ppm", "lbt"));

TEST_P(EveryMethod, ACropIsTheWholeRendersWindow) {
  const Scene scene = caustic();
  const Film whole = renderWith(scene, optionsFor(GetParam()));
  RenderOptions o = optionsFor(GetParam());
  o.crop = {3, 2, 11, 9};
  const Film crop = renderWith(scene, o);
  ASSERT_EQ(crop.window(), o.crop);
  EXPECT_EQ(crop.width(), 8);
  EXPECT_EQ(crop.beautyRgba().size(), size_t(4 * 8 * 7));
  expectSameSums(whole, crop, GetParam() + " crop");
  if (GetParam() == "lt") {
    EXPECT_EQ(crop.sums().splatPaths, whole.sums().splatPaths) << "lt traces every light path";
  }
}

// Parts 1..N merged (Film::addFilm) give the whole render's sums, for N that does and does not
// divide the rows, with and without a crop.
TEST_P(EveryMethod, MergedPartsAreTheWholeRender) {
  const Scene scene = caustic();
  const Film whole = renderWith(scene, optionsFor(GetParam()));
  for (const PixelWindow crop : {PixelWindow{}, PixelWindow{1, 1, 12, 8}})
    for (int parts : {3, 4}) {
      const PixelWindow frame = crop.empty() ? PixelWindow::whole(kWidth, kHeight) : crop;
      Film merged(kWidth, kHeight, frame);
      for (int part = 1; part <= parts; ++part) {
        RenderOptions o = optionsFor(GetParam());
        o.crop = crop;
        o.part = part;
        o.parts = parts;
        const Film f = renderWith(scene, o);
        if (GetParam() != "lt") {
          EXPECT_EQ(f.window(), partBand(frame, part, parts));
        }
        ASSERT_TRUE(merged.addFilm(f)) << "part " << part << "/" << parts;
      }
      expectSameSums(whole, merged, GetParam() + " " + std::to_string(parts) + " parts");
      EXPECT_EQ(merged.beautyRgba().size(), size_t(4) * frame.pixels());
    }
}

// Stopped after k batches (k = 0, 1, 2, ...), then resumed from the film and the position in a
// new Renderer (as from a checkpoint): the whole render's sums, whichever batch it stopped at.
TEST_P(EveryMethod, ResumedAtAnyBatchIsTheUninterruptedRender) {
  const Scene scene = caustic(4);
  RenderOptions o = optionsFor(GetParam());
  o.frequentBatches = true;  // as with --checkpoint: at least 16 batches a pass
  o.progressive = GetParam() == "pm";  // pm in passes: its one map comes from the first pass
  const Film whole = renderWith(scene, o);
  ThreadLimit limit(2);
  int stoppedAt = 0;
  for (int k = 0;; k += 7) {
    Renderer first(scene, o);
    int batches = 0;
    Renderer::Control stopAfterK;
    stopAfterK.stop = [&] { return batches >= k; };
    stopAfterK.batchDone = [&](const Film&, const Renderer::Position&) { ++batches; };
    Film part = first.render({}, stopAfterK);
    if (!first.interrupted()) break;  // k is past the last batch
    stoppedAt = first.position().pass;
    Renderer second(scene, o);
    second.resume(std::move(part), first.position());
    const Film resumed = second.render();
    ASSERT_FALSE(second.interrupted());
    expectSameSums(whole, resumed, GetParam() + " resumed after " + std::to_string(k) + " batches");
  }
  if (GetParam() == "ppm" || GetParam() == "pm") {
    EXPECT_GT(stoppedAt, 0) << "a stop in a later pass was tried";
  }
}

// Stopped at the c-th stop check (c = 1, 4, 7, ...: before a batch, and between the generations
// of one, after its camera generation added the batch's first-hit AOVs to the film too), the
// checkpoint written and read back as --checkpoint / --resume do, and resumed: the whole
// render's sums, AOVs included (a batch's AOVs are not added twice: Position::firstHitsEnd).
TEST_P(EveryMethod, ResumedAfterAStopInsideABatchIsTheUninterruptedRender) {
  const Scene scene = caustic(4);
  RenderOptions o = optionsFor(GetParam());
  o.frequentBatches = true;
  const Film whole = renderWith(scene, o);
  ThreadLimit limit(2);
  TempFolder temp;
  int insideABatch = 0;
  for (int c = 1;; c += 3) {
    Renderer first(scene, o);
    int checks = 0;
    Renderer::Control stopAtC;
    stopAtC.stop = [&] { return ++checks >= c; };
    const Film part = first.render({}, stopAtC);
    if (!first.interrupted()) break;  // c is past the last check
    const Renderer::Position& at = first.position();
    if (at.firstHitsEnd > at.next) ++insideABatch;
    FilmFileHeader h;
    h.kind = "checkpoint";
    h.width = kWidth;
    h.height = kHeight;
    h.crop = h.window = part.window();
    h.method = GetParam();
    h.pass = at.pass;
    h.next = at.next;
    h.blockPixels = at.blockPixels;
    h.firstHitsEnd = at.firstHitsEnd;
    writeFilmFile(temp.path("cp.film"), h, part);
    FilmFile saved = readFilmFile(temp.path("cp.film"));
    EXPECT_EQ(saved.header.firstHitsEnd, at.firstHitsEnd);
    Renderer second(scene, o);
    second.resume(std::move(saved.film), {saved.header.pass, saved.header.next, saved.header.blockPixels,
                                          saved.header.firstHitsEnd});
    const Film resumed = second.render();
    ASSERT_FALSE(second.interrupted());
    expectSameSums(whole, resumed, GetParam() + " resumed after " + std::to_string(c) + " stop checks");
  }
  if (GetParam() != "lt") {  // (lt sees nothing from the camera: no AOVs)
    EXPECT_GT(insideABatch, 0) << "a stop after a camera generation was tried";
    EXPECT_GT(*std::max_element(whole.sums().hits.begin(), whole.sums().hits.end()), 0u) << "the AOVs are compared";
  }
}

}  // namespace
}  // namespace rayes::testing
