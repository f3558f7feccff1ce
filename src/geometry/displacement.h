// Displacement functions: a scalar height h over a patch, with a conservative range over a box
// (thesis §6.1: "min-max MIP maps on textures and interval arithmetic on procedural noise").
// DisplacedPatch (geometry/displaced_patch.h) moves each point of its base surface by h along the
// base's unit normal and bounds the result with range().
//
// Two kinds:
//  - NoiseDisplacement: fractal value noise of the base surface's POSITION (3D, world space).
//    A function of position is continuous across patch borders even where (u, v) are not, so
//    neighbouring patches agree on h at their shared border vertices bit for bit.
//  - HeightMapDisplacement: a bilinearly filtered image indexed by the patch's (u, v), read
//    through the texture cache and bounded by a min-max pyramid built from one streaming pass
//    over the image. Each patch maps the whole image over its own unit square.
//
// Contract of range(): it contains sample(...).h as computed in float, for every float point p
// inside pBox and every (u, v) inside [u0,u1] x [v0,v1], whatever the other arguments. The
// exact-arithmetic range is computed with outward rounding and then widened by a bound on the
// float evaluation's own rounding; tests/geometry/displace_*_test.cpp check it by sampling.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>
#include "core/box.h"
#include "core/interval.h"
#include "core/vec.h"
#include "core/vector_isa.h"

namespace rayes {

class TextureImage;  // texture/texture_cache.h

// A height and its derivatives along the base surface's parameters.
struct HeightSample {
  float h = 0;
  float hu = 0, hv = 0;  // dh/du, dh/dv (chain rule through pu, pv for position-based heights)
};

class Displacement {
 public:
  virtual ~Displacement() = default;
  // The height at base point p with parameters (u, v); pu, pv are the base surface's dP/du,
  // dP/dv there (only used for hu, hv). Deterministic, finite for finite input.
  virtual HeightSample sample(Vec3 p, Vec3 pu, Vec3 pv, float u, float v) const = 0;
  // sample() at n points with one v (a grid row: DisplacedPatch::dice()): out[i] is
  // sample(p[i], pu[i], pv[i], u[i], v) bit for bit. The default calls sample(); kinds that
  // evaluate a row faster than its points one at a time override it.
  virtual void sampleRow(int n, const Vec3* p, const Vec3* pu, const Vec3* pv, const float* u, float v,
                         HeightSample* out) const;
  // Conservative range of sample().h, see the contract above.
  virtual Interval range(const Box3& pBox, float u0, float u1, float v0, float v1) const = 0;
  // A bound M on every result of range(), whatever its arguments: range() lies in [-M, M]. It
  // lets DisplacedPatch::coarseBoundsOverAt bound a box without calling range(). Infinite (the
  // default) where a kind gives none.
  virtual float magnitudeBound() const;
  // LOD estimates (not bounds): the mean |dh/ds| per unit length of base surface, and per unit
  // of (u, v) parameter. DisplacedPatch::sizeBound() lengthens the base's size by these.
  virtual float meanSlopePerLength() const = 0;
  virtual float meanSlopePerParameter() const = 0;
  virtual const char* kind() const = 0;  // "noise", "image"
};

using DisplacementPtr = std::shared_ptr<const Displacement>;

// h(p) = offset + amplitude * sum_k w_k n_k(p * f_k + o_k) / sum_k w_k, with w_k = gain^k,
// f_k = frequency * lacunarity^k, o_k a per-octave offset from the seed, and n_k value noise in
// [-1, 1] (or 1 - |n_k| in [0, 1] when ridged). So |h - offset| <= |amplitude|.
struct NoiseParams {
  float amplitude = 1;
  float frequency = 1;   // lattice cells per unit length of the first octave, > 0
  int octaves = 4;       // 1..16
  float gain = 0.5f;     // amplitude ratio of successive octaves, in (0, 1]
  float lacunarity = 2;  // frequency ratio of successive octaves, in [1, 4]
  uint32_t seed = 0;
  bool ridged = false;
  float offset = 0;
};

// Value noise on the integer lattice: trilinear interpolation of hashed lattice values in
// [-1, 1) with quintic fade weights. Its interval extension over a box is exact per lattice
// cell up to rounding: the fade is monotone, so each axis's weight over the box's slice of the
// cell is an interval [fade(t0), fade(t1)], and a lerp of intervals with an interval weight is
// bounded at the weight's endpoints. Boxes over more than kMaxCells cells get [-1, 1]: a box
// that large holds more than 32 lattice values, so its exact range usually reaches within 0.1
// of both ends anyway, while visiting its cells (up to 512 before) was most of the cost of
// the border bounds of displaced leaves (bench/RESULTS.md, "Interval noise capped at 32 cells";
// tests/geometry/displace_noise_test.cpp, BoxesOverTheCellCapAreCloseToEverything).
class ValueNoise {
 public:
  static constexpr int kMaxCells = 32;
  explicit ValueNoise(uint64_t seed) : seed_(seed) {}
  // Noise and its gradient at x (lattice units).
  float eval(float x, float y, float z, Vec3* gradient) const;
  // eval() at n points (lattice units): value[i] and the gradient (gx, gy, gz)[i]. Bit for bit
  // n eval() calls (eval() is its n = 1 case), at a fraction of the cost: the fade weights and
  // the blend are vectorised and a row's points share their cells.
  void evalRow(int n, const float* x, const float* y, const float* z, float* value, float* gx, float* gy,
               float* gz) const;
  // Conservative range of eval() over every float point of [lo, hi].
  Interval range(Vec3 lo, Vec3 hi) const;
  float lattice(int64_t ix, int64_t iy, int64_t iz) const;
  uint64_t seed() const { return seed_; }

 private:
  uint64_t seed_;
};

class NoiseDisplacement final : public Displacement {
 public:
  explicit NoiseDisplacement(const NoiseParams& params);  // std::invalid_argument if out of range
  HeightSample sample(Vec3 p, Vec3 pu, Vec3 pv, float u, float v) const override;  // sampleRow() for n = 1
  void sampleRow(int n, const Vec3* p, const Vec3* pu, const Vec3* pv, const float* u, float v,
                 HeightSample* out) const override;
  Interval range(const Box3& pBox, float u0, float u1, float v0, float v1) const override;
  // (|offset| + |amplitude|) (1 + 10^-3): range() is offset + amplitude x a weighted mean of
  // octave ranges within [-1, 1] widened by at most 2 10^-6, the mean widened by 10^-6 and the
  // result by 10^-6 (10^-5 for a box that is not finite) of |offset| + |amplitude|.
  float magnitudeBound() const override;
  float meanSlopePerLength() const override { return meanSlope_; }
  float meanSlopePerParameter() const override { return 0; }
  const char* kind() const override { return "noise"; }
  const NoiseParams& params() const { return params_; }
  // The noise coordinate of octave k for position p: the exact float operations that range()
  // repeats on a box's corners (monotone rounding makes the box image conservative).
  Vec3 octaveCoordinate(int k, Vec3 p) const;
  // Range of the normalised fractal sum (before amplitude and offset) over a position box.
  Interval fractalRange(const Box3& pBox) const;

 private:
  // sampleRow's body and its version per instruction set (core/vector_isa.h).
  void sampleRowBody(int n, const Vec3* p, const Vec3* pu, const Vec3* pv, HeightSample* out) const;
  RAYES_TARGET_AVX2 void sampleRowAvx2(int n, const Vec3* p, const Vec3* pu, const Vec3* pv, HeightSample* out) const;
  void sampleRowBaseline(int n, const Vec3* p, const Vec3* pu, const Vec3* pv, HeightSample* out) const;
  NoiseParams params_;
  std::vector<ValueNoise> octaves_;
  std::vector<float> freq_, weight_;
  std::vector<Vec3> shift_;
  float invWeightSum_ = 1;
  float meanSlope_ = 0;
};

// Reads texels [x0, x1) x [y0, y1) of a height map's image, row-major, into out. Thread-safe
// and a pure function of its arguments (the texture cache: whatever its size or thread count).
using HeightTexelReader = std::function<void(int x0, int x1, int y0, int y1, float* out)>;

// A single-channel float image (row 0 at v = 0) with bilinear filtering (texel centres at
// ((i + 0.5) / width, (j + 0.5) / height), clamped at the edges), and a min-max pyramid over
// cells of kCell x kCell texels: pyramid level L holds, per node, the min and max of the texels
// of the 2^L x 2^L cells it covers.
//
// Memory: the texels are not held. They are read through a HeightTexelReader -- for a scene,
// the texture cache (texture/texture_cache.h), bounded by --texture-memory -- once at
// construction, row band by row band, to build the pyramid (about width * height / 24 bytes),
// and again by sample() and by range() over a few texels.
// A bilinear sample lies between the min and max of its 4 texels, so the range over a (u, v)
// rectangle is the min/max over the texels its samples can touch: read directly when they
// are few, else from at most 2 x 2 pyramid nodes.
// Thread safety: const methods are thread-safe if the reader is.
class HeightMap {
 public:
  static constexpr int kCell = 8;  // texels per pyramid cell side
  // std::invalid_argument for non-positive sizes or a non-finite texel (read at construction).
  HeightMap(int width, int height, HeightTexelReader read);
  // An image in memory (tests, benchmarks); also std::invalid_argument if the count does not match.
  HeightMap(int width, int height, std::vector<float> texels);
  // Channel `channel` of the finest level of a texture-cache image (the scene's height maps).
  HeightMap(std::shared_ptr<const TextureImage> image, int channel);
  float sample(float u, float v, float* dhdu = nullptr, float* dhdv = nullptr) const;
  // sample() at n points of one v (a grid row), bit for bit: out[i] = sample(u[i], v), dhdu[i],
  // dhdv[i]. The two texel rows the points read are fetched in one call (per sample, one call
  // each made dicing 1.65x slower through the texture cache).
  void sampleRow(int n, const float* u, float v, float* out, float* dhdu, float* dhdv) const;
  Interval range(float u0, float u1, float v0, float v1) const;
  // Min and max over texels [i0, i1] x [j0, j1] (inclusive, clamped): exact for at most
  // kDirectTexels texels, else from the pyramid (containing the exact range).
  Interval texelRange(int i0, int i1, int j0, int j1) const;
  int width() const { return width_; }
  int height() const { return height_; }
  int levels() const { return int(mins_.size()); }  // pyramid levels
  size_t pyramidBytes() const;
  float texel(int i, int j) const;
  float meanNeighbourDifference() const { return meanDiff_; }

 private:
  static constexpr int kDirectTexels = 256;
  void build();
  HeightTexelReader read_;
  int width_, height_;
  std::vector<std::vector<float>> mins_, maxs_;  // per pyramid level, row-major, levelWidth(L) wide
  std::vector<int> levelWidth_, levelHeight_;
  float roundingMargin_ = 0;
  float meanDiff_ = 0;
};

// Where a scene's height map came from: the file as the scene named it (relative to the
// scene's folder, or absolute) and the channel read. A compiled scene stores it and opens the
// map again (geometry/patch_record.h); empty for maps made in memory.
struct HeightMapOrigin {
  std::string file, channel;
};

// h(u, v) = offset + amplitude * map.sample(u, v).
class HeightMapDisplacement final : public Displacement {
 public:
  HeightMapDisplacement(std::shared_ptr<const HeightMap> map, float amplitude, float offset, HeightMapOrigin origin = {});
  HeightSample sample(Vec3 p, Vec3 pu, Vec3 pv, float u, float v) const override;
  void sampleRow(int n, const Vec3* p, const Vec3* pu, const Vec3* pv, const float* u, float v,
                 HeightSample* out) const override;
  Interval range(const Box3& pBox, float u0, float u1, float v0, float v1) const override;
  float meanSlopePerLength() const override { return 0; }
  float meanSlopePerParameter() const override;
  const char* kind() const override { return "image"; }
  const HeightMap& map() const { return *map_; }
  float amplitude() const { return amplitude_; }
  float offset() const { return offset_; }
  const HeightMapOrigin& origin() const { return origin_; }

 private:
  std::shared_ptr<const HeightMap> map_;
  float amplitude_, offset_;
  HeightMapOrigin origin_;
};

}  // namespace rayes
