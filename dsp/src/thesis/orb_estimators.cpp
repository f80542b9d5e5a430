// The thesis's two methods that need ORB (OpenCV features2d): thesis-orb and
// thesis (see gvs/dsp/thesis.hpp). They are built into gvs::dsp_orb, which the
// desk tool `gvs` links and gvsd does not (docs/architecture.md, "The
// thesis's ORB methods").
#include <algorithm>
#include <cmath>
#include <exception>

#include "estimator_checks.hpp"
#include "gvs/dsp/thesis.hpp"
#include "gvs/dsp/thesis_orb_methods.hpp"
#include "gvs/dsp/vocabulary.hpp"

namespace gvs::dsp {

namespace {

using thesis::frame_problem;
using thesis::set_velocity;

// ---------------------------------------------------------------- thesis-orb
// Thesis 4.3 + 5.1. Speed = RMS displacement (eq. 5.2) * s / dt. The thesis
// divided by the 3 ms exposure (eq. 5.1), but two frames are one frame
// interval apart (16.7 ms at 60 fps), not one exposure: that overstated the
// speed 5.6 times. We use dt between the two frames' light centres.
class ThesisOrbEstimator final : public VelocityEstimator {
 public:
  explicit ThesisOrbEstimator(const EstimatorConfig& config) : camera_(config.camera) {}

  VelocityEstimate estimate(const FrameView& frame) override {
    const std::int64_t t_ns = mid_exposure_ns(frame.t_ns, frame.exposure);
    if (const auto why = frame_problem(frame, camera_)) return no_estimate(frame.index, t_ns, *why);
    try {
      if (!orb_.has_previous()) {
        orb_.set_previous(frame.gray);
        prev_t_ns_ = t_ns;
        return no_estimate(frame.index, t_ns, Method::no_previous);
      }
      const double dt_s = static_cast<double>(t_ns - prev_t_ns_) * 1e-9;
      prev_t_ns_ = t_ns;
      if (!(dt_s > 0.0)) {
        orb_.set_previous(frame.gray);
        return no_estimate(frame.index, t_ns, Method::bad_time);
      }
      const thesis::OrbShift shift = orb_.measure_and_advance(frame.gray);
      if (!shift.ok) return no_estimate(frame.index, t_ns, Method::no_match);
      VelocityEstimate e = no_estimate(frame.index, t_ns, Method::thesis_orb);
      // Texture displacement -> vehicle velocity, mount yaw included.
      set_velocity(e, image_shift_to_velocity(shift.d_row_px, shift.d_col_px, dt_s, camera_));
      e.quality = shift.quality;
      return e;
    } catch (const std::exception&) {
      orb_.reset();
      return no_estimate(frame.index, t_ns, Method::error);
    }
  }
  void reset() override { orb_.reset(); }

 private:
  CameraGeometry camera_;
  thesis::OrbFrameDifference orb_;
  std::int64_t prev_t_ns_ = 0;
};

// -------------------------------------------------------------------- thesis
// Thesis ch. 6 (Fig. 6.1): speed from the Laplacian first; it picks the
// direction method: ORB frame difference below 15 km/h, FFT above. (The
// thesis's own listing, Fig. A.1, compares the raw Laplacian standard
// deviation with the threshold, "speed_main > SPEED_TH -> ORB", which is the
// same switch since the standard deviation falls as speed rises.)
class ThesisEstimator final : public VelocityEstimator {
 public:
  explicit ThesisEstimator(const EstimatorConfig& config)
      : camera_(config.camera),
        lap_(config.camera.mm_per_px),
        fft_(config.camera.width_px, config.camera.height_px),
        previous_(config.camera.height_px, config.camera.width_px, CV_8UC1) {}

  VelocityEstimate estimate(const FrameView& frame) override {
    const std::int64_t t_ns = mid_exposure_ns(frame.t_ns, frame.exposure);
    if (const auto why = frame_problem(frame, camera_)) return no_estimate(frame.index, t_ns, *why);
    try {
      VelocityEstimate e = run(frame, t_ns);
      frame.gray.copyTo(previous_);
      has_previous_ = true;
      return e;
    } catch (const std::exception&) {
      reset();
      return no_estimate(frame.index, t_ns, Method::error);
    }
  }
  void reset() override {
    has_previous_ = false;
    orb_has_previous_ = false;
    orb_.reset();
  }

 private:
  VelocityEstimate run(const FrameView& frame, std::int64_t t_ns) {
    const auto model = thesis::fitted_laplacian_model();
    if (model.empty()) return no_estimate(frame.index, t_ns, Method::no_model);
    const thesis::LaplacianSpeed sp = thesis::invert_laplacian_model(lap_.lap_std(frame.gray), model);
    if (!sp.ok) return no_estimate(frame.index, t_ns, Method::no_texture);

    VelocityEstimate e = no_estimate(frame.index, t_ns, Method::thesis_lap);
    e.has_speed = true;
    e.speed_mps = sp.speed_mps;
    e.quality = sp.quality;

    bool have_direction = false;
    double dir_deg = 0.0;
    double dir_quality = 0.0;
    if (sp.speed_mps < thesis::kSwitchSpeedMps) {
      // ORB frame difference against the previous frame. Its features are
      // cached when ORB also ran on the previous frame.
      if (has_previous_) {
        if (!orb_has_previous_) orb_.set_previous(previous_);
        const thesis::OrbShift shift = orb_.measure_and_advance(frame.gray);
        if (shift.ok && shift.rms_px > 0.0) {
          // The direction does not depend on dt; 1 s keeps the scale harmless.
          dir_deg = direction_deg(image_shift_to_velocity(shift.d_row_px, shift.d_col_px, 1.0, camera_));
          dir_quality = shift.quality;
          have_direction = true;
          e.method = Method::thesis_lap_orb;
        }
      } else {
        orb_.set_previous(frame.gray);
      }
      orb_has_previous_ = true;
    } else {
      orb_has_previous_ = false;
      const thesis::FftAxis axis = fft_.measure(frame.gray);
      if (axis.ok) {
        dir_deg = wrap_axis_deg(axis.axis_cam_deg + camera_.mount_yaw_deg);  // forward assumed
        dir_quality = axis.quality;
        have_direction = true;
        e.method = Method::thesis_lap_fft;
      }
    }
    if (have_direction) {
      e.has_direction = true;
      e.direction_deg = dir_deg;
      e.vx_mps = e.speed_mps * std::cos(deg_to_rad(dir_deg));
      e.vy_mps = e.speed_mps * std::sin(deg_to_rad(dir_deg));
      e.quality = std::min(sp.quality, dir_quality);
    }
    return e;
  }

  CameraGeometry camera_;
  thesis::LaplacianBlur lap_;
  thesis::FftOrientation fft_;
  thesis::OrbFrameDifference orb_;
  cv::Mat previous_;
  bool has_previous_ = false;
  bool orb_has_previous_ = false;
};

}  // namespace

std::unique_ptr<VelocityEstimator> make_thesis_estimator(const EstimatorConfig& config) {
  return std::make_unique<ThesisEstimator>(config);
}
std::unique_ptr<VelocityEstimator> make_thesis_orb_estimator(const EstimatorConfig& config) {
  return std::make_unique<ThesisOrbEstimator>(config);
}

void add_thesis_orb_estimators() {
  static constexpr EstimatorMaker kMakers[] = {
      {"thesis", &make_thesis_estimator},
      {"thesis-orb", &make_thesis_orb_estimator},
  };
  add_estimators(kMakers);
}

}  // namespace gvs::dsp
