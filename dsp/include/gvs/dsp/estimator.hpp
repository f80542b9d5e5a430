// The interface every velocity estimator implements, and the factory that
// builds one from its configuration.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "gvs/dsp/vocabulary.hpp"

namespace gvs::dsp {

/// Settings shared by all estimators. `method` picks the estimator by name
/// (see estimator_names()).
struct EstimatorConfig {
  std::string method = "gvs";
  CameraGeometry camera;
};

/// Frame in, estimate out. Frames arrive in capture order; an estimator may
/// keep the previous frame (pair methods). estimate() is on the real-time
/// path: it never throws and does not allocate once it has seen a frame of
/// the configured size (buffers are made in the constructor).
class VelocityEstimator {
 public:
  VelocityEstimator() = default;
  VelocityEstimator(const VelocityEstimator&) = delete;
  VelocityEstimator& operator=(const VelocityEstimator&) = delete;
  VelocityEstimator(VelocityEstimator&&) = delete;
  VelocityEstimator& operator=(VelocityEstimator&&) = delete;
  virtual ~VelocityEstimator() = default;

  virtual VelocityEstimate estimate(const FrameView& frame) = 0;
  /// Forget history (after a gap, a source restart or a reconfiguration).
  virtual void reset() = 0;
};

/// Names accepted in EstimatorConfig::method.
std::vector<std::string> estimator_names();

/// Builds the estimator named in `config.method`. Throws std::invalid_argument
/// naming the method and the allowed names when it is unknown.
std::unique_ptr<VelocityEstimator> make_estimator(const EstimatorConfig& config);

}  // namespace gvs::dsp
