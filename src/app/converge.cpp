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

std::vector<ConvergeRow> converge(const Scene& base, const RenderOptions& options, const std::vector<float>& reference,
                                  const PixelRegion& errorPixels, const PixelRegion& region, double budgetSeconds,
                                  const ConvergeSchedule& schedule,
                                  const std::function<void(const ConvergeRow&)>& report) {
  std::vector<ConvergeRow> rows;
  double spent = 0;
  RenderOptions o = options;
  o.reference.clear();
  for (int step = 0, spp = 1; spp <= (1 << 20); ++step, spp *= 2) {
    Scene scene = base;
    scene.samplesPerPixel = spp;
    // Beams grow with the samples (a method without beams ignores the option).
    o.method.beams.resolution = schedule.beamResolution(options.method.beams.resolution, step);
    const auto t0 = Clock::now();
    const std::clock_t c0 = std::clock();
    Renderer renderer(scene, o);
    const Film film = renderer.render();
    const double seconds = secondsSince(t0);
    const double cpuSeconds = double(std::clock() - c0) / CLOCKS_PER_SEC;
    const std::vector<float> rgba = film.beautyRgba();
    const ImageError error = errorAgainst(rgba, reference, errorPixels, scene.width, scene.height);
    const ConvergeRow row{seconds,
                          cpuSeconds,
                          spp,
                          renderer.stats().shade.photonsTraced.load(),
                          int(renderer.stats().method.number("resolution")),  // the glossy rule's, if coarser
                          uint64_t(renderer.stats().method.number("segments")),
                          error.rmse,
                          error.relMse,
                          regionBias(rgba, reference, region, errorPixels, scene.width, scene.height)};
    rows.push_back(row);
    if (report) report(row);
    spent += seconds;
    // The next render costs about twice this one (beams, where the method has them, double too).
    if (spent + 2 * seconds > budgetSeconds) break;
  }
  return rows;
}

std::string convergeCsv(const std::vector<ConvergeRow>& rows) {
  std::string out = "seconds,cpu_seconds,spp,photons,beam_resolution,beam_segments,rmse,rel_mse,region_bias\n";
  char line[256];
  for (const ConvergeRow& r : rows) {
    std::snprintf(line, sizeof line, "%.4f,%.4f,%d,%llu,%d,%llu,%.6g,%.6g,%.6g\n", r.seconds, r.cpuSeconds, r.spp,
                  static_cast<unsigned long long>(r.photons), r.beamResolution,
                  static_cast<unsigned long long>(r.beamSegments), r.rmse, r.relMse, r.regionBias);
    out += line;
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
