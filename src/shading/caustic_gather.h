// What the path tracer asks of a caustic estimator at a receiving (non-delta, non-caustic-
// scatterer) vertex: the irradiance arriving there along light paths that left a light and
// were only reflected or refracted by specular and glossy surfaces since (docs/design.md,
// "Light beam tracing"). Implemented by src/lbt (light beams); shading sees only this seam.
//
// Contract: gather() calls add(psi, E) once per contributing beam segment, in an order that is
// a pure function of (leaf, x) -- the image stays bit-identical for any thread count -- with
// psi the unit direction the light travels at x and E its irradiance on the receiver (cosine
// included). Thread-safe (const), allocation free.
#pragma once
#include <cstdint>
#include "core/vec.h"

namespace rayes {

class CausticGather {
 public:
  virtual ~CausticGather() = default;
  struct Sink {
    virtual void add(Vec3 psi, Rgb irradiance) = 0;
  };
  virtual void gather(uint32_t leaf, Vec3 x, Vec3 normal, Sink& sink) const = 0;
};

}  // namespace rayes
