// The "gvs" estimator: frame checks, method switching, sign resolution and
// bookkeeping. The measurements themselves live in gvs_pair.cpp (frame
// pairs), gvs_single.cpp (one blurred or double-pulse frame).
#include "gvs/dsp/gvs_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string_view>

namespace gvs::dsp {

namespace {

/// Left/right half windows, 5/8 of the width each (they overlap), full height.
cv::Rect half_window(cv::Size size, bool right) {
  const int w = (size.width * 5 / 8) & ~1;
  return {right ? size.width - w : 0, 0, w, size.height};
}

}  // namespace

GvsEstimator::GvsEstimator(const EstimatorConfig& config, const GvsEstimatorSettings& settings)
    : cam_(config.camera),
      set_(settings),
      size_(config.camera.width_px, config.camera.height_px),
      left_(half_window(size_, false)),
      right_(half_window(size_, true)),
      full_spectrum_(size_),
      half_spectrum_(left_.size()),
      hann_spectrum_(size_, 1.0),
      half_correlator_(left_.size()),
      blur_(size_) {
  if (size_.width < 64 || size_.height < 64) {
    throw std::invalid_argument("gvs estimator: camera.width_px/height_px must be at least 64 px");
  }
  if (!(cam_.mm_per_px > 0.0)) {
    throw std::invalid_argument("gvs estimator: camera.mm_per_px must be > 0");
  }
  spec_full_.create(size_, CV_32FC2);
  spec_hann_.create(size_, CV_32FC2);
  for (int i = 0; i < 2; ++i) {
    spec_left_[i].create(left_.size(), CV_32FC2);
    spec_right_[i].create(right_.size(), CV_32FC2);
  }
  prev_gray_.create(size_, CV_8UC1);
  column_pattern_.assign(static_cast<std::size_t>(size_.width), 0.0f);
  column_sum_.assign(static_cast<std::size_t>(size_.width), 0.0);
  pixel_pattern_ = cv::Mat::zeros(size_, CV_32F);
}

void GvsEstimator::learn_pixel_pattern(const cv::Mat& gray, double mean_grey) {
  // offset(r,c) <- offset + a (g(r,c) - frame mean - offset), a = 1/n for
  // the first 100 frames, then 1/100: the texture of moving ground averages
  // out, the sensor's offsets (and the light's fall-off) stay.
  pixel_frames_ = std::min(pixel_frames_ + 1, 100);
  const auto a = static_cast<float>(1.0 / pixel_frames_);
  const auto m = static_cast<float>(mean_grey);
  for (int r = 0; r < gray.rows; ++r) {
    const auto* g = gray.ptr<std::uint8_t>(r);
    auto* p = pixel_pattern_.ptr<float>(r);
    for (int c = 0; c < gray.cols; ++c) p[c] += a * (static_cast<float>(g[c]) - m - p[c]);
  }
}

void GvsEstimator::take_spectrum(WindowedSpectrum& with, const cv::Mat& gray, cv::Mat& spectrum) {
  if (pixel_pattern_in_use_) {
    with.compute(gray, spectrum, pixel_pattern_);
  } else {
    with.compute(gray, spectrum, column_pattern());
  }
}

void GvsEstimator::learn_column_pattern(const cv::Mat& gray, double mean_grey) {
  // offset_c <- offset_c + a (mean of column c - frame mean - offset_c),
  // a = 1/n for the first 50 frames (plain average), then 1/50 (slow EMA).
  std::fill(column_sum_.begin(), column_sum_.end(), 0.0);
  for (int r = 0; r < gray.rows; ++r) {
    const auto* g = gray.ptr<std::uint8_t>(r);
    for (int c = 0; c < gray.cols; ++c) column_sum_[static_cast<std::size_t>(c)] += g[c];
  }
  column_frames_ = std::min(column_frames_ + 1, 50);
  const double a = 1.0 / column_frames_;
  for (std::size_t c = 0; c < column_sum_.size(); ++c) {
    const double offset = column_sum_[c] / gray.rows - mean_grey;
    column_pattern_[c] += static_cast<float>(a * (offset - static_cast<double>(column_pattern_[c])));
  }
}

const float* GvsEstimator::column_pattern() const {
  return column_frames_ >= 10 ? column_pattern_.data() : nullptr;
}

GvsEstimator::~GvsEstimator() = default;

void GvsEstimator::reset() {
  prev_valid_ = false;
  prev_halves_valid_ = false;
  last_valid_ = false;
  has_last_direction_ = false;
  has_last_speed_ = false;
  has_speed_floor_ = false;
  last_pair_valid_ = false;
  mode_ = Mode::pair;
  column_frames_ = 0;
  pixel_frames_ = 0;
  last_single_dark_ = false;
  pixel_pattern_.setTo(cv::Scalar::all(0.0));
  std::fill(column_pattern_.begin(), column_pattern_.end(), 0.0f);
}

VelocityEstimate GvsEstimator::estimate(const FrameView& frame) {
  // The estimate refers to the middle of the light.
  const std::int64_t t_mid = mid_exposure_ns(frame.t_ns, frame.exposure);
  halves_this_frame_ = false;
  sign_known_now_ = false;
  single_frame_tried_ = false;
  if (frame.gray.empty() || frame.gray.type() != CV_8UC1 || frame.gray.size() != size_) {
    reset();
    return no_estimate(frame.index, t_mid, "bad-frame");
  }
  const FrameStats stats = measure_frame(frame.gray);
  if (const char* problem = frame_problem(stats, set_.frame_check)) {
    prev_valid_ = false;
    prev_halves_valid_ = false;
    last_pair_valid_ = false;
    VelocityEstimate e = no_estimate(frame.index, t_mid, problem);
    last_ = e;
    last_valid_ = false;
    return e;
  }
  cur_mean_grey_ = stats.mean_grey;

  const bool had_previous = prev_valid_;
  VelocityEstimate e;
  if (frame.exposure.pulse_count >= 2) {
    e = estimate_double(frame, t_mid);
  } else {
    const double dt_s = static_cast<double>(t_mid - prev_t_mid_ns_) * 1e-9;
    // A pair needs the same blur in both frames: with different exposures the
    // two streak kernels' sinc spectra differ in sign and fool the correlation.
    const double lit_us = frame.exposure.lit_time_us();
    const bool same_exposure = std::abs(lit_us - prev_lit_us_) <= 0.2 * std::max(lit_us, prev_lit_us_);
    const bool consecutive = prev_valid_ && !prev_double_ && same_exposure && dt_s > 0.0 && dt_s < 0.06;
    double still_ratio = 1.0;
    if (consecutive && is_still(frame.gray, still_ratio)) {
      e = no_estimate(frame.index, t_mid, "still");
      e.has_speed = true;
      e.has_yaw_rate = true;
      e.quality = std::clamp(1.0 - still_ratio / set_.still_ratio, 0.1, 1.0);
      last_pair_valid_ = false;
    } else {
      update_mode(dt_s);
      const bool tried_pair = mode_ == Mode::pair && consecutive;
      if (tried_pair) e = estimate_pair(frame, t_mid, dt_s);
      if (e.quality <= 0.0) {
        last_pair_valid_ = false;
        e = estimate_single(frame, t_mid);
        // The pair failed: the frames no longer overlap, go single-frame.
        if (tried_pair && e.quality > 0.0) mode_ = Mode::single;
        // Single-frame without a speed and a short streak: too slow for a
        // streak length, so try the pair (and go back to pair mode if it works).
        if (!tried_pair && consecutive && !e.has_speed && last_axis_anisotropy_ < 0.8) {
          const VelocityEstimate p = estimate_pair(frame, t_mid, dt_s);
          if (p.quality >= 0.5) {
            e = p;
            mode_ = Mode::pair;
          }
        }
      }
    }
  }
  // Fast motion (single-frame mode, or a streak longer than the frame): each
  // frame shows new ground, so column means hold only the fixed pattern.
  const bool fast = e.quality > 0.0 && e.has_direction &&
                    (e.method != std::string_view("pair") && e.method != std::string_view("still"));
  const bool slow = e.has_speed && e.speed_mps <= 2.0;
  if (fast && !slow) learn_column_pattern(frame.gray, stats.mean_grey);
  // The pixel pattern from every frame whose ground moved on by a few
  // grains since the previous one (pairs included: each pixel then sees new
  // texture), and from frames without a speed where the pair did not match or
  // was not tried and the frame is not still: a dark frame at speed shows
  // little but the pattern, which is what is to be learnt. Not from a first
  // frame (nothing to compare it with).
  if (had_previous) {
    const double dt_s = static_cast<double>(t_mid - prev_t_mid_ns_) * 1e-9;
    const double shift_px = e.speed_mps * dt_s / (cam_.mm_per_px * 1e-3);
    const bool moved = e.has_speed ? shift_px >= set_.pixel_pattern_min_shift_px : single_frame_tried_;
    if (moved) learn_pixel_pattern(frame.gray, stats.mean_grey);
  }
  e.tracking = has_last_speed_ && t_mid > last_speed_t_ns_ &&
               static_cast<double>(t_mid - last_speed_t_ns_) * 1e-9 <= set_.speed_memory_s;
  remember(frame, t_mid, e);
  return e;
}

void GvsEstimator::update_mode(double dt_s) {
  // Shift expected between this frame and the previous one, from the last estimate.
  if (!last_valid_) return;  // unknown: keep the mode (pair first)
  if (!last_.has_speed) return;  // no speed: keep the mode (a failing pair switches)
  const double shift_px = last_.speed_mps * dt_s / (cam_.mm_per_px * 1e-3);
  if (mode_ == Mode::pair && shift_px > set_.pair_leave_shift_px) mode_ = Mode::single;
  if (mode_ == Mode::single && shift_px < set_.pair_enter_shift_px) mode_ = Mode::pair;
}

bool GvsEstimator::is_still(const cv::Mat& gray, double& ratio) const {
  // ratio = mean((g1 - k g0)^2) / (2 var(g1)), k = mean1/mean0 (exposure may change).
  // Identical texture: only temporal noise is left (fixed-pattern noise cancels).
  //
  // But a frame that is only fixed-pattern noise (texture smeared flat by a
  // streak much longer than the frame, e.g. under-exposed at speed) repeats
  // too. The asphalt seen through the lens is smooth over neighbouring pixels
  // in both directions; the sensor's pattern is not (pixel offsets are white,
  // column offsets are smooth only down a column). So the frame must also be
  // correlated with its right and its lower neighbour:
  //   rho = cov(g(r,c), g(r,c+1)) / var(g), the same for (r+1,c); min >= still_min_neighbour_corr.
  const double k = prev_mean_grey_ > 0.0 ? cur_mean_grey_ / prev_mean_grey_ : 1.0;
  double diff_sq = 0.0;
  double sum = 0.0;
  double sum_sq = 0.0;
  double sum_right = 0.0;  // sum of g(r,c) g(r,c+1)
  double sum_down = 0.0;   // sum of g(r,c) g(r+1,c)
  std::int64_t n = 0;
  for (int r = 0; r + 1 < gray.rows; r += 2) {
    const auto* g1 = gray.ptr<std::uint8_t>(r);
    const auto* below = gray.ptr<std::uint8_t>(r + 1);
    const auto* g0 = prev_gray_.ptr<std::uint8_t>(r);
    for (int c = 0; c + 1 < gray.cols; c += 2) {
      const double a = g1[c];
      const double d = a - k * g0[c];
      diff_sq += d * d;
      sum += a;
      sum_sq += a * a;
      sum_right += a * g1[c + 1];
      sum_down += a * below[c];
      ++n;
    }
  }
  const double nn = static_cast<double>(n);
  const double mean = sum / nn;
  const double var = sum_sq / nn - mean * mean;
  if (var <= 0.0) return false;
  ratio = diff_sq / nn / (2.0 * var);
  const double rho_right = (sum_right / nn - mean * mean) / var;
  const double rho_down = (sum_down / nn - mean * mean) / var;
  if (ratio >= set_.still_ratio || std::min(rho_right, rho_down) < set_.still_min_neighbour_corr) return false;
  // Alike is not unmoved: two frames smeared by a streak longer than the
  // frame are alike too (each pixel averages centimetres of ground, cracks
  // along the motion stay put, and the fixed pattern and the light's
  // fall-off are the same in both). Standstill needs both frames sharp: fine
  // texture in every direction, well above the sensor's white part.
  return ground_is_sharp(measure_fine_texture(gray)) && ground_is_sharp(measure_fine_texture(prev_gray_));
}

bool GvsEstimator::ground_is_sharp(const FineTexture& t) const {
  return t.isotropy() >= set_.still_min_isotropy && t.step_min_over_max >= set_.still_min_step_ratio &&
         t.weakest_over_difference() >= set_.still_min_fine_texture;
}

GvsEstimator::SignSource GvsEstimator::resolve_sign(Vec2 axis, std::int64_t t_mid_ns,
                                                    double energy_vote, double& sign) const {
  const double age_s = static_cast<double>(t_mid_ns - last_direction_t_ns_) * 1e-9;
  if (has_last_direction_ && age_s <= set_.continuity_max_age_s) {
    const double dot = axis.x * last_direction_.x + axis.y * last_direction_.y;
    // Turning by more than ~70 deg between frames is not physical: then the
    // previous direction does not decide.
    if (std::abs(dot) > 0.35) {
      sign = dot >= 0.0 ? 1.0 : -1.0;
      return SignSource::continuity;
    }
  }
  if (std::abs(energy_vote) >= set_.min_energy_confidence) {
    sign = energy_vote > 0.0 ? 1.0 : -1.0;
    return SignSource::energy;
  }
  sign = axis.x >= 0.0 ? 1.0 : -1.0;  // a car mostly drives forwards
  return SignSource::forward;
}

void GvsEstimator::remember(const FrameView& frame, std::int64_t t_mid_ns,
                            const VelocityEstimate& e) {
  frame.gray.copyTo(prev_gray_);
  prev_valid_ = true;
  prev_double_ = frame.exposure.pulse_count >= 2;
  prev_lit_us_ = frame.exposure.lit_time_us();
  prev_t_mid_ns_ = t_mid_ns;
  prev_mean_grey_ = cur_mean_grey_;
  prev_halves_valid_ = halves_this_frame_;
  if (halves_this_frame_) cur_ = 1 - cur_;
  last_ = e;
  last_valid_ = e.quality > 0.0;
  if (e.has_speed && e.quality > 0.0) {
    has_last_speed_ = true;
    last_speed_mps_ = e.speed_mps;
    last_speed_index_ = e.index;
    last_speed_t_ns_ = t_mid_ns;
  }
  if (e.has_direction && e.quality > 0.0) {
    const double a = deg_to_rad(e.direction_deg);
    last_direction_ = {std::cos(a), std::sin(a)};
    last_direction_t_ns_ = t_mid_ns;
    has_last_direction_ = true;
    last_sign_known_ = sign_known_now_;
  }
}

/// Fills vx, vy, speed and direction from a vehicle-axes velocity.
void set_velocity(VelocityEstimate& e, Vec2 v, bool with_speed) {
  const double speed = std::hypot(v.x, v.y);
  // Below 0.01 m/s the direction is noise (truth.csv leaves it empty too).
  e.has_direction = speed >= VelocityEstimate::kStandstillMps;
  e.direction_deg = e.has_direction ? direction_deg(v) : 0.0;
  if (with_speed) {
    e.has_speed = true;
    e.vx_mps = v.x;
    e.vy_mps = v.y;
    e.speed_mps = speed;
  }
}

std::unique_ptr<VelocityEstimator> make_gvs_estimator(const EstimatorConfig& config) {
  return std::make_unique<GvsEstimator>(config);
}

}  // namespace gvs::dsp
