// How fine a light's grid of beams needs to be when its beams are glossy (docs/design.md,
// "Light beam tracing", As built). A glossy segment's gather is its flux triangle blurred by the
// lobe (width σ): a beam much narrower than the lobe adds no detail to the image, only another
// footprint integral (lbt/gaussian_triangle.h) at every gather point its widened box holds, and
// beams narrower than the lobe overlap by dozens there. The rule: the angular width a beam has
// after its first glossy scattering is about cellsPerSigma·σ of that scatterer.
//
// footprintAngle(s) is that width: the longest side of the triangle where the corner rays end,
// over the segment's mean length (the footprint's size as seen from the scatterer, which is what
// the lobe's blur σ·r compares with; for a convergent beam it is the size at the receiver, not
// at a focus). It scales as 1/N with the light's grid resolution N, so a probe at a coarse
// resolution gives the resolution of the rule:
//   N = ceil(N_probe · median over the probe's first-bounce glossy segments of (width / σ) / cellsPerSigma).
// 0 when the probe has no glossy first-bounce segment, or when they are fewer than its specular
// ones (a grid shared with specular beams keeps its resolution: coarse specular beams would be
// visibly faceted).
#pragma once
#include <span>
#include <vector>
#include "lbt/beam_segment.h"

namespace rayes {

// The angular width of a segment's footprint in radians (0 for a degenerate or escaping segment:
// any corner ending at or past `far`).
double footprintAngle(const BeamSegment& s, float far);

// The grid resolution of the rule from a probe traced at probeResolution (its segments after one
// scattering, without splits), at least 1; 0: the rule does not apply (see above).
int lobeResolution(std::span<const BeamSegment> probe, int probeResolution, double cellsPerSigma, float far);
// The same in two steps, for a probe traced in chunks: each chunk's widths (in units of σ) and
// specular first-bounce segments added to `widths` and `specular`, then the rule from them all.
void addProbeWidths(std::span<const BeamSegment> probe, float far, std::vector<double>& widths, size_t& specular);
int lobeResolution(std::vector<double>& widths, size_t specular, int probeResolution, double cellsPerSigma);

}  // namespace rayes
