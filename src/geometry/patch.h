// START HERE for geometry. A Patch is one top-level leaf: a surface over the unit square
// (u, v) in [0,1]^2 that can be diced on demand at any level m into a (2^m+1)^2 vertex grid.
//
// Contract (docs/design.md, invariant 1): bounds() contains every point that dice() can produce at any
// level and any shutter time, displacement included. The top level, early ray termination and
// crack-free level of detail all rest on this; tests/geometry and tests/dicing check it by sampling.
//
// Patches are immutable after construction and all methods are const and thread-safe: many
// threads dice different patches (or the same one) at once, each into its own DiceBuffer.
#pragma once
#include <cstdint>
#include <memory>
#include "core/box.h"
#include "core/vec.h"

namespace rayes {

// A point on a patch: position and the (not necessarily unit) surface normal dP/du x dP/dv,
// made finite at degenerate points (poles) by the patch.
struct SurfacePoint {
  Vec3 p;
  Vec3 n;
};

// A patch's first and second partial derivatives at one (u, v), for the kinds that have them
// in closed form (BezierPatch::derivativesOnRow, BilinearPatch::derivatives): a displaced
// surface's normal needs the base normal's derivatives, which come from these.
struct SurfaceDerivatives {
  Vec3 pu, pv;         // dP/du, dP/dv (their cross product is the kind's raw normal, bit for bit)
  Vec3 puu, puv, pvv;  // second derivatives
};

class Patch {
 public:
  virtual ~Patch() = default;

  // Conservative bound of every diced point (see the contract above).
  virtual Box3 bounds() const = 0;

  // A conservative bound of the true surface over the parameter rectangle [u0,u1] x [v0,v1]
  // (every shutter time, displacement included): the per-micro-quad form of bounds(), used
  // where a dicing must be bounded by the surface it approximates (crack-free borders).
  // The default, bounds(), is always valid; kinds override it with something tighter.
  virtual Box3 boundsOver(float u0, float u1, float v0, float v1) const { return bounds(); }

  // An upper bound on the length of any iso-parameter curve of the patch. The side of a
  // micro-quad at level m is then at most about sizeBound() / 2^m; level-of-detail selection
  // uses this, and so does nothing else, so it only has to be a reasonable, stable estimate.
  virtual float sizeBound() const = 0;

  // The surface at (u, v). Must be deterministic: the same (u, v) gives the same bits, which is
  // what makes the level-k subgrid of a level-m dicing identical to a level-k dicing.
  virtual SurfacePoint evaluate(float u, float v) const = 0;

  // Fills a (2^level+1)^2 grid, row-major with u along a row: p[j*(2^level+1)+i] is the point
  // at (u, v) = (i/2^level, j/2^level). The default evaluates every vertex; kinds override it to
  // evaluate boundary rows in a canonical orientation so that neighbouring patches that share
  // a border produce bit-identical border vertices (watertight seams).
  virtual void dice(int level, Vec3* positions, Vec3* normals) const;

  // A bound on the distance between the level-m dicing (micro-quads split into triangles) and
  // the true surface, as a coefficient C: the bound is C / 4^m. Zero for planar patches. Used
  // to offset secondary rays just enough (shading), instead of the thesis's l / 2^m, which
  // at coarse levels pushes origins across the scene. The default derives C from the box
  // (C = longest side: the thesis's rule at m = 0, and safe for any patch inside its box).
  virtual float dicingErrorCoefficient() const { return bounds().longestSide(); }

  // Short name of the kind, for stats ("bezier", "bilinear", ...).
  virtual const char* kind() const = 0;
  // What the surface is made of, for the stats' feature counts (decorators answer for the
  // patch they wrap): displaced by a height function, a face of a subdivision surface.
  virtual bool isDisplaced() const { return false; }
  virtual bool isSubdivision() const { return false; }

  // --- Motion (thesis §6.3). A patch may carry K >= 1 time samples: the same surface (same
  // kind, same parametrisation) at increasing times sampleTime(0) < ... < sampleTime(K-1).
  // At time t in [t_i, t_i+1] the surface is the point-wise linear interpolation of samples i
  // and i+1 at equal (u, v); outside the keyframe range the time clamps. bounds() and
  // boundsOver() cover every sample (and so, by convexity, every interpolated time); dice()
  // and evaluate() are sample 0. A static patch (the default) has one sample and pays nothing.
  virtual int timeSamples() const { return 1; }
  virtual float sampleTime(int sample) const { return 0.0f; }
  // dice() / evaluate() / boundsOver() of one time sample (0 <= sample < timeSamples()).
  virtual void diceAt(int sample, int level, Vec3* positions, Vec3* normals) const {
    dice(level, positions, normals);
  }
  virtual SurfacePoint evaluateAt(int sample, float u, float v) const { return evaluate(u, v); }
  virtual Box3 boundsOverAt(int sample, float u0, float u1, float v0, float v1) const {
    return boundsOver(u0, u1, v0, v1);
  }

  // --- Crack-free level of detail (docs/architecture.md, "Crack-free and watertight").
  // True when a dicing's border polyline can leave the true border curve, so neighbours diced
  // at different levels can leave slits that the bottom level must close with conservative
  // border boxes. Borders that are straight at every level (planar bilinear patches) need
  // none. boundsOver() is then called with a degenerate rectangle (u0 == u1 or v0 == v1 on a
  // border): it must bound the true border curve piece. A displaced kind must answer true
  // (its default does, through a positive dicingErrorCoefficient()).
  virtual bool needsBorderClosure() const { return dicingErrorCoefficient() > 0.0f; }

  // Bounds of the true border curve over the 2^split equal pieces of segment j of border e at
  // level k, of time sample `sample`, in order along the border: piece i covers the parameter
  // interval [(j 2^split + i) / 2^(k+split), (j 2^split + i + 1) / 2^(k+split)] of border e
  // (0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0; the parameter is u on borders 0 and 2, v on 1
  // and 3). Each box holds what boundsOverAt on the piece's degenerate rectangle must hold,
  // but need not have its bits: crack-closing regions take their radii from these
  // (DiceBuffer::borderRadius), up to 64 pieces at a time. The default is boundsOverAt per
  // piece; Bézier kinds restrict the border curve once and halve it. split <= kMaxPieceSplit.
  static constexpr int kMaxPieceSplit = 7;
  virtual void borderPieceBoundsAt(int sample, int e, int k, uint32_t j, int split, Box3* out) const;

  // A box that contains boundsOverAt(sample, u0, u1, v0, v1) as computed, every coordinate
  // as far out or farther, at a fraction of its cost; false where the kind has none cheaper
  // (the default). A static dicing tests rays against it before it computes a border
  // segment's box (DiceBuffer::mayEnterRegionBox): a ray that misses it misses the box.
  virtual bool coarseBoundsOverAt(int sample, float u0, float u1, float v0, float v1, Box3& out) const {
    return false;
  }
};

using PatchPtr = std::shared_ptr<const Patch>;

}  // namespace rayes
