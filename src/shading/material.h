// Materials of the v1 scene format: a Lambertian reflectance and an emitted radiance (either
// may be zero). Emission leaves the side the surface normal dP/du x dP/dv points to, or both
// sides when twoSided is set.
#pragma once
#include <string>
#include "core/vec.h"

namespace rayes {

struct Material {
  std::string name;
  Rgb albedo{0, 0, 0};
  Rgb emission{0, 0, 0};  // radiance, W / (m^2 sr) per channel
  bool twoSided = false;
  bool emits() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
};

}  // namespace rayes
