// The product estimator, method "gvs": picks per frame the measurement the
// physics allows (docs/estimator.md).
//
//   still       consecutive frames identical up to noise: speed 0
//   pair        consecutive frames overlap (slow): phase correlation of two
//               half-frame windows -> shift (velocity, sign included) and the
//               difference of their shifts -> yaw rate
//   blur-*      one frame: streak axis (power spectrum orientation) and, when
//               the streak fits in the frame, its length (derivative
//               autocorrelation) -> direction up to sign, and speed
//   streak-*    as blur-*, but the streak is too long to measure: direction only
//   short-streak one frame whose streak is too short to carry a direction
//               (quality 0; the exposure controller lengthens the exposure)
//   dpiv-*      double-pulse frame: displacement between the two images
//               (autocorrelation side peak) -> velocity up to sign
// The suffix says what decided the sign: -cont (continuity with the previous
// estimate), -energy (unequal pulse energies), -fwd (no history: forward assumed).
#pragma once

#include <cstdint>
#include <memory>

#include "gvs/dsp/estimator.hpp"
#include "gvs/dsp/gvs_analysis.hpp"
#include "gvs/dsp/gvs_settings.hpp"
#include "gvs/dsp/gvs_tracking.hpp"

namespace gvs::dsp {

/// Per frame: checks the frame, picks the analysis its exposure and the
/// tracked motion allow (still, pair, streak, double pulse;
/// gvs_analysis.hpp), and updates the tracking state (gvs_tracking.hpp).
class GvsEstimator final : public VelocityEstimator {
 public:
  explicit GvsEstimator(const EstimatorConfig& config, const GvsEstimatorSettings& settings = {});
  ~GvsEstimator() override;

  VelocityEstimate estimate(const FrameView& frame) override;
  void reset() override;

  /// What the estimator carries between frames (for tests and tools).
  [[nodiscard]] const TrackingState& tracking() const { return track_; }

 private:
  /// A frame lit once: still, pair or single-frame, and the pair's second chance.
  VelocityEstimate estimate_one_light(const FrameView& frame, std::int64_t t_mid_ns, double mean_grey,
                                      FrameOutcome& outcome);
  /// The sensor's pattern from this frame, if its estimate shows the ground moved on.
  void learn_sensor_pattern(const FrameView& frame, std::int64_t t_mid, double mean_grey,
                            const VelocityEstimate& e, bool single_frame_tried);

  CameraGeometry cam_;
  GvsEstimatorSettings set_;
  cv::Size size_;
  SpectrumWorkspace spectra_;  ///< working buffers of the one-frame analyses
  PairWorkspace pair_;         ///< working buffers of the pair analysis
  TrackingState track_;
};

/// Factory entry for the "gvs" method.
std::unique_ptr<VelocityEstimator> make_gvs_estimator(const EstimatorConfig& config);

}  // namespace gvs::dsp
