// The ray's footprint at a hit, as texture filtering needs it (docs/design.md, "Texture
// footprints"). A ray carries a cone (Ray::coneWidth, coneSpread: its width w = coneWidth +
// t coneSpread where it meets the surface); cut by the tangent plane, the cone's cross-section
// is an ellipse with a minor axis of length w along n x d and a major axis of length
// w / |cos θ| along d's projection onto the plane. Its two axes, solved against the surface
// derivatives dP/du, dP/dv (least squares), are the footprint in the patch parameters; through
// a uv set's Jacobian, in (s, t). Axes are full widths (one pixel of a camera ray spans one
// axis), the convention of OpenImageIO's dsdx, dtdx, dsdy, dtdy.
//
// Pure functions of their arguments; thread-safe; O(1). Every result is finite, for any input
// (grazing, a degenerate Jacobian, zero or huge widths): see the caps below.
#pragma once
#include "core/ray_batch.h"
#include "core/vec.h"
#include "shading/texture_query.h"

namespace rayes {

// The stretch along d's projection is at most this: 1 / |cos θ| reaches it at θ ≈ 89.1°. Beyond
// it the footprint stays that long, so a ray at 89.99° cannot make a filter average a whole
// texture (or an infinite width); what is left unfiltered there is averaged by the pixel's
// samples. 64 is twice OpenImageIO's default anisotropy (32), so an image lookup is never
// asked for less than it can give.
inline constexpr float kMaxFootprintStretch = 64;

// An axis in (u, v) or (s, t) is at most this long per component: a footprint larger than
// every texture repetition filters to the texture's mean long before, and the bound keeps a
// near-singular Jacobian (a sliver quad) from producing infinities.
inline constexpr float kMaxFootprintAxis = 1e6f;

// The footprint's world-space axes: A along d's projection onto the plane (length w / |cos θ|,
// capped at kMaxFootprintStretch w), B along n x d (length w). d need not be unit; n is a unit
// normal. At normal incidence (n x d = 0) A and B are any orthogonal pair of the plane. w <= 0
// or non-finite, or n or d zero or non-finite: both axes zero (a point sample).
void footprintAxes(Vec3 d, Vec3 n, float w, Vec3& A, Vec3& B);

// A world-space vector of the tangent plane in the patch parameters: the least-squares (du, dv)
// with du dP/du + dv dP/dv closest to `a`. A degenerate Jacobian (a collapsed edge, a pole:
// dP/du or dP/dv zero, or the two parallel) gives the minimum-norm solution of a slightly
// regularised system (a 1e-9 ridge), so the collapsed direction gets no extent; both zero give (0, 0).
// Each component is clamped to ±kMaxFootprintAxis.
void toParameters(Vec3 a, Vec3 dpdu, Vec3 dpdv, float& du, float& dv);

// How much of a camera ray's cone to filter over: filtering over a whole pixel per sample and
// then averaging the pixel's samples would blur twice, so the footprint of a camera ray shrinks
// with the samples per pixel, as pbrt-v4 scales its camera ray differentials: max(1/8, 1/√spp).
float cameraFootprintScale(int samplesPerPixel);

// The texture query at patch parameters (u, v) of a hit with surface derivatives `dpd` (null: a
// point sample), for a ray of direction d whose cone is `width` wide there, with geometric normal
// n. `uv` (null: the leaf has no uv set) maps the patch's axes into the uv set.
TextureQuery footprintQuery(float u, float v, Vec3 d, Vec3 n, float width, const HitDerivatives* dpd,
                            const TexCoordSample* uv);

}  // namespace rayes
