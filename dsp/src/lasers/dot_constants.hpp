// The laser-dot finder's shapes, in units of the spot's sigma unless
// named otherwise (docs/estimator.md, "Height from the laser dots"): shared
// by the tracks (tracks.cpp), the finding and the mask (dot_finder.cpp).
#pragma once

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

}  // namespace gvs::dsp::dots
