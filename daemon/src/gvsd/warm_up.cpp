#include "gvs/daemon/warm_up.hpp"

#include <array>

#include "gvs/daemon/frame_estimator.hpp"

namespace gvs::daemon {

namespace {

constexpr int kMarginPx = 256;  // room to shift and smear the texture
constexpr std::int64_t kFramePeriodNs = 16'666'667;

/// One made-up frame: the ground `dx`, `dy` px from the texture's corner,
/// smeared over `streak_px` along the rows; with `second_dx_px` > 0 a second
/// image that far further on (a double pulse). The light as `pulses` say
/// (none: 3 ms continuous).
struct FrameKind {
  int dx_px;
  int dy_px;
  int streak_px;
  int second_dx_px;
  std::array<core::LightPulse, 2> pulses;
  std::size_t pulse_count;
};

// A sharp pair 4 px apart (crawling): the pair's phase correlations. 60 px
// streaks at 3 ms (7 km/h): the streak's axis, end and refinement. 100 us
// strobes, 20 px streaks (72 km/h). Two 60 us pulses 500 us apart at the same
// speed: 12 px images 100 px apart.
constexpr std::array<FrameKind, 11> kFrames{{
    {0, 0, 1, 0, {}, 0},
    {4, 2, 1, 0, {}, 0},
    {8, 4, 1, 0, {}, 0},
    {0, 0, 60, 0, {}, 0},
    {40, 0, 60, 0, {}, 0},
    {80, 0, 60, 0, {}, 0},
    {0, 0, 20, 0, {{{0.0, 100.0}}}, 1},
    {80, 0, 20, 0, {{{0.0, 100.0}}}, 1},
    {0, 0, 12, 100, {{{0.0, 60.0}, {500.0, 60.0}}}, 2},
    {50, 0, 12, 100, {{{0.0, 60.0}, {500.0, 60.0}}}, 2},
    {100, 0, 12, 100, {{{0.0, 60.0}, {500.0, 60.0}}}, 2},
}};

/// [1 2 1] / 4 along the rows and then the columns (edges kept). By hand
/// rather than cv::GaussianBlur, which OpenCV may run on worker threads of
/// its own.
void smooth_121(cv::Mat& t) {
  cv::Mat copy = t.clone();
  for (int r = 0; r < t.rows; ++r) {
    const float* in = copy.ptr<float>(r);
    float* out = t.ptr<float>(r);
    for (int c = 1; c + 1 < t.cols; ++c) out[c] = 0.25f * (in[c - 1] + 2.0f * in[c] + in[c + 1]);
  }
  t.copyTo(copy);
  for (int r = 1; r + 1 < t.rows; ++r) {
    const float* up = copy.ptr<float>(r - 1);
    const float* in = copy.ptr<float>(r);
    const float* down = copy.ptr<float>(r + 1);
    float* out = t.ptr<float>(r);
    for (int c = 0; c < t.cols; ++c) out[c] = 0.25f * (up[c] + 2.0f * in[c] + down[c]);
  }
}

/// Adds the mean of `length` texels from `in` onwards, for each of `n` pixels.
void add_streak(const float* in, int length, int n, float weight, float* out) {
  double sum = 0.0;
  for (int k = 0; k < length; ++k) sum += static_cast<double>(in[k]);
  for (int c = 0; c < n; ++c) {
    out[c] += weight * static_cast<float>(sum / length);
    sum += static_cast<double>(in[c + length]) - static_cast<double>(in[c]);
  }
}

}  // namespace

WarmUpFrames::WarmUpFrames(const core::CameraGeometry& camera)
    : texture_(camera.height_px + kMarginPx, camera.width_px + kMarginPx, CV_32F),
      row_(static_cast<std::size_t>(camera.width_px)) {
  // Grey ground: white noise smoothed over a few pixels (the grain), mean
  // 110 and 25 grey levels RMS: well lit, nowhere clipped.
  cv::RNG rng(0x67767364u);
  rng.fill(texture_, cv::RNG::NORMAL, 0.0, 1.0);
  for (int i = 0; i < 3; ++i) smooth_121(texture_);
  cv::Scalar mean;
  cv::Scalar sd;
  cv::meanStdDev(texture_, mean, sd);
  texture_.convertTo(texture_, CV_32F, 25.0 / sd[0], 110.0 - 25.0 * mean[0] / sd[0]);
}

std::size_t WarmUpFrames::size() const noexcept { return kFrames.size(); }

void WarmUpFrames::draw(std::size_t i, drivers::FrameSlot& slot) noexcept {
  const FrameKind& k = kFrames[i];
  cv::Mat& grey = slot.view.gray;
  const int width = std::min(grey.cols, static_cast<int>(row_.size()));
  const int rows = std::min(grey.rows, texture_.rows - kMarginPx);
  for (int r = 0; r < rows; ++r) {
    const float* in = texture_.ptr<float>(r + k.dy_px) + k.dx_px;
    std::fill(row_.begin(), row_.end(), 0.0f);
    const float weight = k.second_dx_px > 0 ? 0.5f : 1.0f;
    add_streak(in, k.streak_px, width, weight, row_.data());
    if (k.second_dx_px > 0) add_streak(in + k.second_dx_px, k.streak_px, width, weight, row_.data());
    auto* out = grey.ptr<std::uint8_t>(r);
    for (int c = 0; c < width; ++c) out[c] = cv::saturate_cast<std::uint8_t>(row_[static_cast<std::size_t>(c)]);
  }
  slot.view.index = static_cast<std::int64_t>(i);
  slot.view.t_ns = static_cast<std::int64_t>(i) * kFramePeriodNs;
  slot.view.exposure = core::ExposurePlan{};  // 3000 us, continuous
  for (std::size_t p = 0; p < k.pulse_count; ++p) slot.view.exposure.pulses[p] = k.pulses[p];
  slot.view.exposure.pulse_count = k.pulse_count;
  slot.defect.reset();
}

void warm_up(FrameEstimator& estimator, WarmUpFrames& frames, drivers::FrameSlot& scratch) noexcept {
  for (std::size_t i = 0; i < frames.size(); ++i) {
    frames.draw(i, scratch);
    (void)estimator.estimate(scratch);
  }
  estimator.reset();
  estimator.clear_exception_count();
}

}  // namespace gvs::daemon
