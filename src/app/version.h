// The program's version: what `rayes --version` prints and what a .film file (a part, a
// checkpoint) records; a film of another version is refused (its pixels may differ). Raise it
// with any change that can change an image's bits.
#pragma once

namespace rayes {

inline constexpr const char* kRayesVersion = "0.31.0";

}  // namespace rayes
