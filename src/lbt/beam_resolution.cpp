#include "lbt/beam_resolution.h"
#include <algorithm>
#include <cmath>
#include <vector>

namespace rayes {

double footprintAngle(const BeamSegment& s, float far) {
  double mean = 0, side = 0;
  Vec3 end[3];
  for (int i = 0; i < 3; ++i) {
    if (!(s.t[i] < far)) return 0;
    end[i] = s.o[i] + s.d[i] * s.t[i];
    mean += s.t[i] / 3.0;
  }
  for (int i = 0; i < 3; ++i) side = std::max(side, double(length(end[(i + 1) % 3] - end[i])));
  const double angle = side / mean;
  return mean > 0 && std::isfinite(angle) ? angle : 0;
}

void addProbeWidths(std::span<const BeamSegment> probe, float far, std::vector<double>& widths, size_t& specular) {
  for (const BeamSegment& s : probe) {
    if (s.scatterings != 1) continue;
    if (!(s.sigma > 0)) {
      ++specular;
      continue;
    }
    const double w = footprintAngle(s, far);
    if (w > 0) widths.push_back(w / s.sigma);
  }
}

int lobeResolution(std::vector<double>& widths, size_t specular, int probeResolution, double cellsPerSigma) {
  if (widths.empty() || widths.size() < specular || !(cellsPerSigma > 0)) return 0;
  const auto mid = widths.begin() + int64_t(widths.size() / 2);
  std::nth_element(widths.begin(), mid, widths.end());
  const double n = std::ceil(probeResolution * *mid / cellsPerSigma);
  return int(std::clamp(n, 1.0, 4096.0));
}

int lobeResolution(std::span<const BeamSegment> probe, int probeResolution, double cellsPerSigma, float far) {
  std::vector<double> widths;  // in units of σ
  size_t specular = 0;
  addProbeWidths(probe, far, widths, specular);
  return lobeResolution(widths, specular, probeResolution, cellsPerSigma);
}

}  // namespace rayes
