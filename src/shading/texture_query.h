// Where a texture is read at a surface point (issue 32): the point in the leaf's patch
// parameters (u, v) and, when the leaf carries one, in its uv set (s, t), each with the two
// axes of the ray's footprint there (the derivatives a filtered lookup takes; all zero: a point
// sample at the finest level). A Texture reads the coordinates its `coordinates` names.
//
// TexCoordSource is how shading learns a leaf's uv set without knowing what the leaf is (a
// Bézier or bilinear patch's uv corners, a subdivision face's face-varying data through
// OpenSubdiv Bfr, a compiled scene's mapped table): implemented above shading (scene, app),
// immutable after construction, at() const and thread-safe.
#pragma once
#include <cstdint>

namespace rayes {

// A point and the footprint's two axes A and B in one coordinate pair (x, y).
struct TexturePoint {
  float x = 0, y = 0;
  float dxA = 0, dyA = 0;  // axis A of the footprint
  float dxB = 0, dyB = 0;  // axis B
};

struct TextureQuery {
  TexturePoint patch;  // the patch parameters (u, v)
  TexturePoint uv;     // the leaf's uv set; meaningful only when hasUv
  bool hasUv = false;
  // A point sample at patch parameters (u, v), no uv set.
  static TextureQuery at(float u, float v) {
    TextureQuery q;
    q.patch.x = u; q.patch.y = v;
    return q;
  }
};

// (s, t) at patch parameters (u, v) and the Jacobian d(s, t) / d(u, v) there.
struct TexCoordSample {
  float s = 0, t = 0;
  float dsdu = 0, dtdu = 0, dsdv = 0, dtdv = 0;
};

class TexCoordSource {
 public:
  virtual ~TexCoordSource() = default;
  // Whether leaf carries a uv set.
  virtual bool has(uint32_t leaf) const = 0;
  // The uv set at (u, v) on leaf (only called when has(leaf)). Finite for finite input.
  virtual TexCoordSample at(uint32_t leaf, float u, float v) const = 0;
};

}  // namespace rayes
