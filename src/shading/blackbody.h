// The colour of a blackbody at a temperature, for volume emission from a temperature grid
// (shading/medium.h): Planck's spectral radiance normalised to 1 at its peak wavelength (as
// pbrt-v4's BlackbodySpectrum, so a temperature scale changes the hue and the brightness
// follows only the spectrum's shape; the scene's blackbody scale sets the radiance), projected to
// linear Rec. 709 RGB through the CIE 1931 matching functions (the multi-lobe Gaussian fit of
// Wyman, Sloan and Shirley 2013), so a flat spectrum of 1 has luminance 1.
// A table of 20 K steps up to 40 000 K built at the first call (thread-safe, a few ms, only in a
// scene with a temperature grid); O(1) per lookup, linear between entries; 0 at or below 0 K.
#pragma once
#include "core/vec.h"

namespace rayes {

Rgb blackbodyRgb(float kelvin);

}  // namespace rayes
