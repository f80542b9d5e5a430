// The laser-dot finder's shapes, in units of the spot's sigma unless
// named otherwise (docs/estimator.md, "Height from the laser dots"): shared
// by the tracks (tracks.cpp), the finding and the mask (dot_finder.cpp),
// steps 4 and 5 (fourth_dot.cpp, near_last_plane.cpp).
#pragma once

#include <cstddef>

namespace gvs::dsp::dots {

inline constexpr double kPsfSigmaPx = 0.5;      // lens and pixel, as the simulator's
inline constexpr double kHeightMarginMm = 3.0;  // tilt moves a dot along its track by up to ~1.5 mm of height
inline constexpr double kInnerSigmas = 1.5;     // the spot: within 1.5 sigma
inline constexpr double kRingInnerSigmas = 2.5;  // the ground around it
inline constexpr double kRingOuterSigmas = 3.5;
inline constexpr double kWindowSigmas = 3.0;    // the centroid's window
inline constexpr double kWeightSigmas = 1.0;    // the centroid's Gaussian weight, in spot sigmas
inline constexpr double kMaskFullSigmas = 3.0;  // mask: the ground's mean inside, tapering to the frame by ...
inline constexpr double kMaskEdgeSigmas = 4.5;  // ... here

/// Samples either side searched for a dot beside where three dots' plane put
/// the fourth (steps 4 and 5), past the few samples of the place itself: a
/// grain taken for one of the three, off its ground by up to what
/// max_tilt_deg lets a plane pass (3 deg over the dots' 28 mm: about 1.5 mm),
/// moves the prediction by up to about as much, at 10 px per mm of height on
/// the fourth beam; the fourth dot shows there.
inline constexpr long kBesideSamples = 15;

/// True if `shows(i)` holds for a sample i of a track of n samples that lies
/// inner + 1 .. kBesideSamples samples either side of `centre`.
template <class Shows>
bool shows_beside(long centre, long inner, long n, Shows shows) {
  for (long d = inner + 1; d <= kBesideSamples; ++d) {
    for (const long i : {centre - d, centre + d}) {
      if (i >= 0 && i < n && shows(static_cast<std::size_t>(i))) return true;
    }
  }
  return false;
}

}  // namespace gvs::dsp::dots
