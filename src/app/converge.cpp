#include "app/converge.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include "core/timer.h"

namespace rayes {

int ConvergeSchedule::beamResolution(int first, int step) const {
  const double r = std::round(double(first) * std::pow(beamGrowth, step));
  return int(std::clamp(r, 1.0, double(std::max(first, maxBeamResolution))));
}

namespace {
// Over the pixels in both `region` and `errorPixels` (where the reference is complete).
double regionBias(const std::vector<float>& rgba, const std::vector<float>& ref, const PixelRegion& region,
                  const PixelRegion& errorPixels, int width, int height) {
  double sum = 0;
  size_t count = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      if (!region.contains(x, y, width) || !errorPixels.contains(x, y, width)) continue;
      const size_t p = size_t(y) * size_t(width) + size_t(x);
      for (int c = 0; c < 3; ++c) sum += double(rgba[4 * p + c]) - double(ref[3 * p + c]);
      count += 3;
    }
  return count ? sum / double(count) : 0.0;
}
}  // namespace

double ConvergeBudget::predictedNext(const std::vector<double>& t) {
  if (t.empty()) return 0;
  const double last = t.back();
  const double growth = t.size() >= 2 && t[t.size() - 2] > 0 ? last / t[t.size() - 2] : 0;
  return last * std::max(2.0, growth);
}

bool heldByFewPixels(const LargestErrors& largest) {
  return largest.counted >= kOutlierMinPixels && largest.share > kOutlierShare;
}

ConvergeRun converge(const Scene& base, const RenderOptions& options, const ConvergeSettings& s,
                     const std::function<void(const ConvergeRow&)>& report) {
  ConvergeRun run;
  std::vector<double> renderSeconds;
  RenderOptions o = options;
  o.reference.clear();
  for (int step = 0, spp = 1; spp <= (1 << 20); ++step, spp *= 2) {
    const double start = s.now();
    if (!s.budget.mayStart(start, renderSeconds)) break;
    Scene scene = base;
    scene.samplesPerPixel = spp;
    // Beams grow with the samples (a method without beams ignores the option).
    o.method.beams.resolution = s.schedule.beamResolution(options.method.beams.resolution, step);
    const std::clock_t c0 = std::clock();
    Renderer renderer(scene, o);
    Renderer::Control control;
    if (!renderSeconds.empty()) control.stop = [&] { return s.budget.mustStop(s.now()); };
    const Film film = renderer.render({}, control);
    const double seconds = s.now() - start;
    const double cpuSeconds = double(std::clock() - c0) / CLOCKS_PER_SEC;
    if (renderer.interrupted()) {  // an image of part of the samples: no row
      run.stoppedSpp = spp;
      run.stoppedStart = start;
      run.stoppedSeconds = seconds;
      break;
    }
    const std::vector<float> rgba = film.beautyRgba();
    const ImageError error = errorAgainst(rgba, s.reference, s.errorPixels, scene.width, scene.height);
    ConvergeRow row{};
    row.seconds = seconds;
    row.cpuSeconds = cpuSeconds;
    row.spp = spp;
    row.photons = renderer.stats().shade.photonsTraced.load();
    row.beamResolution = int(renderer.stats().method.number("resolution"));  // the glossy rule's, if coarser
    row.beamSegments = uint64_t(renderer.stats().method.number("segments"));
    row.rmse = error.rmse;
    row.relMse = error.relMse;
    row.regionBias = regionBias(rgba, s.reference, s.region, s.errorPixels, scene.width, scene.height);
    if (s.clampQuantile > 0)
      row.clampedRmse = clampedRmse(rgba, s.reference, s.errorPixels, scene.width, scene.height, s.clampQuantile);
    row.largest = largestErrors(rgba, s.reference, s.errorPixels, scene.width, scene.height, kOutlierPixels);
    run.rows.push_back(row);
    renderSeconds.push_back(seconds);
    if (report) report(run.rows.back());
  }
  return run;
}

std::string convergeCsv(const std::vector<ConvergeRow>& rows, bool clampedColumn) {
  std::string out = "seconds,cpu_seconds,spp,photons,beam_resolution,beam_segments,rmse,rel_mse,region_bias";
  out += clampedColumn ? ",clamped_rmse\n" : "\n";
  char line[256];
  for (const ConvergeRow& r : rows) {
    std::snprintf(line, sizeof line, "%.4f,%.4f,%d,%llu,%d,%llu,%.6g,%.6g,%.6g", r.seconds, r.cpuSeconds, r.spp,
                  static_cast<unsigned long long>(r.photons), r.beamResolution,
                  static_cast<unsigned long long>(r.beamSegments), r.rmse, r.relMse, r.regionBias);
    out += line;
    if (clampedColumn) {
      std::snprintf(line, sizeof line, ",%.6g", r.clampedRmse);
      out += line;
    }
    out += "\n";
  }
  return out;
}

// Log-log axes over the rows' ranges (decades), one polyline with a dot per render.
std::string convergeSvg(const std::vector<ConvergeRow>& rows, const std::string& title) {
  constexpr double W = 640, H = 420, L = 70, R = 20, T = 40, B = 50;
  double t0 = 1e300, t1 = -1e300, e0 = 1e300, e1 = -1e300;
  for (const ConvergeRow& r : rows) {
    if (r.seconds > 0) t0 = std::min(t0, r.seconds), t1 = std::max(t1, r.seconds);
    if (r.rmse > 0) e0 = std::min(e0, r.rmse), e1 = std::max(e1, r.rmse);
  }
  if (!(t0 <= t1)) t0 = 0.1, t1 = 1;
  if (!(e0 <= e1)) e0 = 0.1, e1 = 1;
  const double lt0 = std::floor(std::log10(t0)), lt1 = std::max(lt0 + 1, std::ceil(std::log10(t1)));
  const double le0 = std::floor(std::log10(e0)), le1 = std::max(le0 + 1, std::ceil(std::log10(e1)));
  auto X = [&](double t) { return L + (std::log10(t) - lt0) / (lt1 - lt0) * (W - L - R); };
  auto Y = [&](double e) { return H - B - (std::log10(e) - le0) / (le1 - le0) * (H - T - B); };
  std::string s;
  char buf[256];
  std::snprintf(buf, sizeof buf, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" "
                "font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n", W, H);
  s += buf;
  std::string escaped;
  for (char c : title) escaped += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : std::string(1, c);
  std::snprintf(buf, sizeof buf, "<text x=\"%g\" y=\"24\" font-size=\"14\">", L);
  s += buf + escaped + "</text>\n";
  for (double d = lt0; d <= lt1; ++d) {
    std::snprintf(buf, sizeof buf, "<line x1=\"%.1f\" y1=\"%g\" x2=\"%.1f\" y2=\"%g\" stroke=\"#ddd\"/>"
                  "<text x=\"%.1f\" y=\"%g\" text-anchor=\"middle\">%g</text>\n", X(std::pow(10, d)), T,
                  X(std::pow(10, d)), H - B, X(std::pow(10, d)), H - B + 18, std::pow(10, d));
    s += buf;
  }
  for (double d = le0; d <= le1; ++d) {
    std::snprintf(buf, sizeof buf, "<line x1=\"%g\" y1=\"%.1f\" x2=\"%g\" y2=\"%.1f\" stroke=\"#ddd\"/>"
                  "<text x=\"%g\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n", L, Y(std::pow(10, d)), W - R,
                  Y(std::pow(10, d)), L - 6, Y(std::pow(10, d)) + 4, std::pow(10, d));
    s += buf;
  }
  std::snprintf(buf, sizeof buf, "<text x=\"%g\" y=\"%g\" text-anchor=\"middle\">seconds</text>\n"
                "<text x=\"16\" y=\"%g\" transform=\"rotate(-90 16 %g)\" text-anchor=\"middle\">RMSE</text>\n",
                (L + W - R) / 2, H - 12, (T + H - B) / 2, (T + H - B) / 2);
  s += buf;
  std::string points;
  for (const ConvergeRow& r : rows) {
    if (!(r.seconds > 0 && r.rmse > 0)) continue;
    std::snprintf(buf, sizeof buf, "%.1f,%.1f ", X(r.seconds), Y(r.rmse));
    points += buf;
    std::snprintf(buf, sizeof buf, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3\" fill=\"#c33\"/>\n", X(r.seconds), Y(r.rmse));
    s += buf;
  }
  s += "<polyline fill=\"none\" stroke=\"#c33\" stroke-width=\"1.5\" points=\"" + points + "\"/>\n</svg>\n";
  return s;
}

}  // namespace rayes
