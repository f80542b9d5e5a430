// The 2022 thesis's methods (../shared/seed/gvs-thesis-2022.txt), ported as the
// measured baseline every gvs estimator is compared with, corrected to gvs's
// axes (shared/spec/dataset-format.md) and to the real frame interval.
//
// Estimators (EstimatorConfig::method):
//   thesis-fft        blur axis from the FFT of one frame, no speed (4.5)
//   thesis-laplacian  speed from the Laplacian's standard deviation (5.3)
// and, in gvs::dsp_orb only (gvs/dsp/thesis_orb_methods.hpp: the desk tool
// has them, gvsd does not link OpenCV's features2d):
//   thesis-orb        ORB frame difference: direction and speed (4.3, 5.1)
//   thesis            the overall system (ch. 6): speed from the Laplacian;
//                     direction from ORB below 15 km/h, from the FFT above.
//                     Its `method` says where the direction came from:
//                     Method::thesis_lap_orb, thesis_lap_fft, or thesis_lap
//                     (speed only: the direction part measured nothing).
#pragma once

#include <memory>

#include "gvs/dsp/estimator.hpp"
#include "gvs/dsp/thesis_fft.hpp"
#include "gvs/dsp/thesis_laplacian.hpp"

namespace gvs::dsp {

namespace thesis {
/// Thesis 4.1: "in the GVS system the method switching is done at 15 Km/h".
constexpr double kSwitchSpeedMps = 15.0 / 3.6;
}  // namespace thesis

std::unique_ptr<VelocityEstimator> make_thesis_fft_estimator(const EstimatorConfig& config);
std::unique_ptr<VelocityEstimator> make_thesis_laplacian_estimator(const EstimatorConfig& config);

}  // namespace gvs::dsp
