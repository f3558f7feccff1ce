#include "geometry/moving_patch.h"
#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace rayes {

MovingPatch::MovingPatch(std::vector<PatchPtr> samples, std::vector<float> times)
    : samples_(std::move(samples)), times_(std::move(times)) {
  if (samples_.size() < 2 || samples_.size() != times_.size())
    throw std::invalid_argument("MovingPatch: needs >= 2 samples and one time per sample");
  for (size_t s = 0; s < samples_.size(); ++s) {
    if (!samples_[s]) throw std::invalid_argument("MovingPatch: null sample");
    if (!std::isfinite(times_[s]) || (s > 0 && !(times_[s] > times_[s - 1])))
      throw std::invalid_argument("MovingPatch: sample times must be finite and strictly increasing");
    if (std::strcmp(samples_[s]->kind(), samples_[0]->kind()) != 0)
      throw std::invalid_argument("MovingPatch: samples of different kinds");
    bounds_.extend(samples_[s]->bounds());
    sizeBound_ = std::max(sizeBound_, samples_[s]->sizeBound());
    errorCoefficient_ = std::max(errorCoefficient_, samples_[s]->dicingErrorCoefficient());
    needsClosure_ = needsClosure_ || samples_[s]->needsBorderClosure();
  }
}

Box3 MovingPatch::boundsOver(float u0, float u1, float v0, float v1) const {
  Box3 b;
  for (const auto& s : samples_) b.extend(s->boundsOver(u0, u1, v0, v1));
  return b;
}

TimeInterval timeInterval(const Patch& patch, float t) {
  const int k = patch.timeSamples();
  if (k < 2) return {};
  if (!(t > patch.sampleTime(0))) return {0, 0.0f};  // also NaN
  if (!(t < patch.sampleTime(k - 1))) return {k - 2, 1.0f};
  int i = 0;
  while (i + 2 < k && !(t < patch.sampleTime(i + 1))) ++i;
  const float t0 = patch.sampleTime(i), t1 = patch.sampleTime(i + 1);
  return {i, std::clamp((t - t0) / (t1 - t0), 0.0f, 1.0f)};
}

}  // namespace rayes
