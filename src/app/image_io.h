// Image files. Outputs are written to a temporary name beside the target and renamed into
// place only when complete, so a failed or interrupted run never leaves a half-written file.
#pragma once
#include <string>
#include <vector>
#include "shading/film.h"

namespace rayes {

// Multi-layer OpenEXR: beauty R,G,B,A; depth.Z; normal.X/Y/Z; lod.Y. All channels are 32-bit
// float so that the AOVs keep full precision.
void writeExr(const std::string& path, const Film& film);
// 8-bit sRGB preview of the beauty pass (clamped, no tone curve beyond the sRGB transfer).
void writePngPreview(const std::string& path, const Film& film);
// Reads the RGB of an EXR (a reference image). Throws InputError on failure.
std::vector<float> readExrRgb(const std::string& path, int& width, int& height);

}  // namespace rayes
