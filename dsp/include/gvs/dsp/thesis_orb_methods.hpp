// The thesis's two ORB methods, thesis-orb and thesis (gvs/dsp/thesis.hpp
// describes them), in their own library gvs::dsp_orb: they need OpenCV's
// features2d, which the car's daemon leaves out. The desk tool `gvs` links
// gvs::dsp_orb and calls add_thesis_orb_estimators() at start, so replay,
// eval and snapshot offer every method; gvsd offers gvs, thesis-fft and
// thesis-laplacian.
#pragma once

#include <memory>

#include "gvs/dsp/estimator.hpp"
#include "gvs/dsp/thesis_orb.hpp"

namespace gvs::dsp {

/// Makes "thesis" and "thesis-orb" known to make_estimator() and
/// estimator_names() (see add_estimators()).
void add_thesis_orb_estimators();

std::unique_ptr<VelocityEstimator> make_thesis_estimator(const EstimatorConfig& config);
std::unique_ptr<VelocityEstimator> make_thesis_orb_estimator(const EstimatorConfig& config);

}  // namespace gvs::dsp
