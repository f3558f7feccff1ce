// Image files. The writers write straight to `path` (the command line gives them an
// OutputSet's temporaries, which makes them all-or-nothing) and throw std::exception with the
// system's or the library's reason on failure.
#pragma once
#include <string>
#include <vector>
#include "app/pixel_cost.h"
#include "shading/film.h"

namespace rayes {

// Multi-layer OpenEXR: beauty R,G,B,A; depth.Z; normal.X/Y/Z (shading normal, facing the
// camera); lod.Y; albedo.R/G/B (the first hit's BSDF reflectance); materialId.Y (index of the
// first hit's material in the scene, of the first sample that hit; -1: none); samples.Y
// (samples taken in the pixel). All channels are 32-bit float so that the AOVs keep full
// precision (ids and counts are exact below 2^24).
// With `cost` (--cost-layers, app/pixel_cost.h) also dicings.Y (dicings charged to the pixel's
// camera paths) and time.Y (seconds of render time apportioned to it).
void writeExr(const std::string& path, const Film& film, const PixelCost* cost = nullptr);
// 8-bit sRGB preview of the beauty pass (clamped, no tone curve beyond the sRGB transfer).
void writePngPreview(const std::string& path, const Film& film);
// Reads the RGB of an EXR of any size (the bench tools' images). Throws InputError on failure.
std::vector<float> readExrRgb(const std::string& path, int& width, int& height);
// Reads the RGB of an EXR to measure against, `what` in messages ("reference", "error mask"):
// its data window must be width x height and it must have R, G and B, both checked from the
// header before a pixel is read or its memory allocated; and every value must be finite.
// Throws InputError naming the file: both sizes; the missing channel; or the first value that
// is NaN or infinite in scan order (pixel x, y from the data window's top left, and channel)
// and how many there are.
// The named channels of an EXR (its data window, row order), each as floats; a channel the file
// lacks is left empty. Throws InputError naming the file when it cannot be read.
struct ExrChannels {
  int width = 0, height = 0;
  std::vector<std::vector<float>> channels;  // in the order of the names asked for
};
ExrChannels readExrChannels(const std::string& path, const std::vector<std::string>& names, const std::string& what);
std::vector<float> readExrRgbOfSize(const std::string& path, const std::string& what, int width, int height);

}  // namespace rayes
