// The interface every velocity estimator implements, and the factory that
// builds one from its configuration.
#pragma once

#include <memory>
#include <span>
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

/// Names accepted in EstimatorConfig::method: gvs::dsp's own (gvs,
/// thesis-fft, thesis-laplacian) and those added with add_estimators().
std::vector<std::string> estimator_names();

/// Builds the estimator named in `config.method`. Throws std::invalid_argument
/// naming the method and the allowed names when it is unknown, and saying so
/// when it is a desk-only method this program was built without.
std::unique_ptr<VelocityEstimator> make_estimator(const EstimatorConfig& config);

/// A method name and the function that builds its estimator.
struct EstimatorMaker {
  const char* name;
  std::unique_ptr<VelocityEstimator> (*make)(const EstimatorConfig&);
};

/// Adds methods that live outside gvs::dsp (the thesis's ORB methods in
/// gvs::dsp_orb: add_thesis_orb_estimators()). Set-up only: call it before
/// any estimator is made; adding a name again changes nothing.
void add_estimators(std::span<const EstimatorMaker> makers);

}  // namespace gvs::dsp
