// The thesis's methods as VelocityEstimators (see gvs/dsp/thesis.hpp): the
// two without ORB. thesis-orb and thesis are in orb_estimators.cpp.
#include <exception>

#include "estimator_checks.hpp"
#include "gvs/dsp/vocabulary.hpp"
#include "gvs/dsp/thesis.hpp"

namespace gvs::dsp {

namespace {

using thesis::frame_problem;

// ---------------------------------------------------------------- thesis-fft
// Thesis 4.5: the blur axis of one frame. No speed. One frame cannot tell
// forward from backward: like the thesis we report the forward one, so the
// direction is in (-90, 90].
class ThesisFftEstimator final : public VelocityEstimator {
 public:
  explicit ThesisFftEstimator(const EstimatorConfig& config)
      : camera_(config.camera), fft_(config.camera.width_px, config.camera.height_px) {}

  VelocityEstimate estimate(const FrameView& frame) override {
    const std::int64_t t_ns = mid_exposure_ns(frame.t_ns, frame.exposure);
    if (const auto why = frame_problem(frame, camera_)) return no_estimate(frame.index, t_ns, *why);
    try {
      const thesis::FftAxis axis = fft_.measure(frame.gray);
      if (!axis.ok) return no_estimate(frame.index, t_ns, Method::no_texture);
      VelocityEstimate e = no_estimate(frame.index, t_ns, Method::thesis_fft);
      e.has_direction = true;
      e.direction_deg = wrap_axis_deg(axis.axis_cam_deg + camera_.mount_yaw_deg);
      e.quality = axis.quality;
      return e;
    } catch (const std::exception&) {
      return no_estimate(frame.index, t_ns, Method::error);
    }
  }
  void reset() override {}

 private:
  CameraGeometry camera_;
  thesis::FftOrientation fft_;
};

// ---------------------------------------------------------- thesis-laplacian
// Thesis 5.3: speed only.
class ThesisLaplacianEstimator final : public VelocityEstimator {
 public:
  explicit ThesisLaplacianEstimator(const EstimatorConfig& config)
      : camera_(config.camera), lap_(config.camera.mm_per_px) {}

  VelocityEstimate estimate(const FrameView& frame) override {
    const std::int64_t t_ns = mid_exposure_ns(frame.t_ns, frame.exposure);
    if (const auto why = frame_problem(frame, camera_)) return no_estimate(frame.index, t_ns, *why);
    try {
      const auto model = thesis::fitted_laplacian_model();
      if (model.empty()) return no_estimate(frame.index, t_ns, Method::no_model);
      const thesis::LaplacianSpeed sp = thesis::invert_laplacian_model(lap_.lap_std(frame.gray), model);
      if (!sp.ok) return no_estimate(frame.index, t_ns, Method::no_texture);
      VelocityEstimate e = no_estimate(frame.index, t_ns, Method::thesis_laplacian);
      e.has_speed = true;
      e.speed_mps = sp.speed_mps;  // vx, vy stay 0: known only at standstill (has_velocity_xy)
      e.quality = sp.quality;
      return e;
    } catch (const std::exception&) {
      return no_estimate(frame.index, t_ns, Method::error);
    }
  }
  void reset() override {}

 private:
  CameraGeometry camera_;
  thesis::LaplacianBlur lap_;
};

}  // namespace

std::unique_ptr<VelocityEstimator> make_thesis_fft_estimator(const EstimatorConfig& config) {
  return std::make_unique<ThesisFftEstimator>(config);
}
std::unique_ptr<VelocityEstimator> make_thesis_laplacian_estimator(const EstimatorConfig& config) {
  return std::make_unique<ThesisLaplacianEstimator>(config);
}

}  // namespace gvs::dsp
