// Bad frames on the daemon's frame path (dsp::FrameProcessor, the code gvsd's
// processing thread and `gvs replay` run), with the product estimator:
// black, saturated, uniform, pure noise, wrong size, zero / absurd / NaN
// exposure, timestamps going backwards or jumping, frames the source could
// not read. Each must get no estimate (quality 0, a named reason), never a
// confident wrong value; the next good frame must be measured normally.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "gvs/daemon/frame_estimator.hpp"
#include "gvs/dsp/frame_processor.hpp"
#include "gvs/drivers/simulator.hpp"
#include "gvs/core/geometry.hpp"

namespace gvs::daemon {
namespace {

/// 100 km/h straight ahead at 60 fps, 3 ms exposure: every good frame carries
/// a direction (docs/accuracy.md: 100 % above 15 km/h).
class FrameFaults : public ::testing::Test {
 protected:
  void SetUp() override {
    drivers::SimulatorConfig sc;
    sc.scenario = "sine";
    sc.seed = 3;
    drivers::Simulator sim(sc);
    drivers::SimFrame f;
    for (int i = 0; i < 12 && sim.next(f); ++i) {
      good_.push_back({f.gray.clone(), f.record.index, f.record.t_ns, f.record.exposure});
      truth_deg_.push_back(f.truth.direction_deg.value_or(0.0));
    }
    ASSERT_EQ(good_.size(), 12u);
    config_.estimator.method = "gvs";
    config_.estimator.camera = sc.camera;
  }

  /// A good frame's estimate must be a real measurement within 1 deg of truth.
  void expect_good(const core::VelocityEstimate& e, std::size_t i, const std::string& after) {
    ASSERT_TRUE(e.has_direction) << "good frame " << i << " after " << after << ": " << e.method;
    EXPECT_GT(e.quality, 0.0) << after;
    EXPECT_LT(std::abs(core::wrap_deg(e.direction_deg - truth_deg_[i])), 1.0)
        << "good frame " << i << " after " << after << ": " << e.direction_deg << " vs " << truth_deg_[i];
  }
  static void expect_nothing(const core::VelocityEstimate& e, const std::string& what) {
    EXPECT_FALSE(e.has_direction) << what << " gave a direction (" << e.method << ")";
    EXPECT_FALSE(e.has_speed) << what << " gave a speed (" << e.method << ")";
    EXPECT_FALSE(e.has_yaw_rate) << what;
    EXPECT_EQ(e.quality, 0.0) << what;
    EXPECT_NE(e.method, core::Method::none) << what << ": no reason named";
  }

  /// A bad frame with the timing of good frame `i` (it replaces it).
  core::FrameView bad_like(std::size_t i, cv::Mat pixels) const {
    core::FrameView v = good_[i];
    v.gray = std::move(pixels);
    return v;
  }
  [[nodiscard]] cv::Mat filled(int value) const {
    return cv::Mat(good_[0].gray.size(), CV_8UC1, cv::Scalar(value));
  }

  std::vector<core::FrameView> good_;
  std::vector<double> truth_deg_;
  dsp::FrameProcessorConfig config_;
};

struct BadFrame {
  std::string name;
  std::function<core::FrameView(const FrameFaults&, std::size_t)> make;
  std::vector<core::Method> reasons;  ///< acceptable outcomes for "why no estimate"
};

TEST_F(FrameFaults, EachBadFrameGetsNoEstimateAndTheNextGoodFrameIsMeasured) {
  // Fixed-pattern-free pure noise: every pixel independent, no streak axis.
  cv::Mat noise(good_[0].gray.size(), CV_8UC1);
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  const cv::Mat small(good_[0].gray.rows / 2, good_[0].gray.cols / 2, CV_8UC1, cv::Scalar(100));
  const std::vector<BadFrame> bad = {
      {"black", [&](const FrameFaults&, std::size_t i) { return bad_like(i, filled(0)); }, {core::Method::dark}},
      {"saturated", [&](const FrameFaults&, std::size_t i) { return bad_like(i, filled(255)); },
       {core::Method::saturated}},
      {"uniform grey", [&](const FrameFaults&, std::size_t i) { return bad_like(i, filled(128)); },
       {core::Method::no_texture}},
      {"pure noise", [&](const FrameFaults&, std::size_t i) { return bad_like(i, noise.clone()); }, {}},
      {"wrong size", [&](const FrameFaults&, std::size_t i) { return bad_like(i, small.clone()); },
       {core::Method::wrong_size}},
      {"zero exposure",
       [&](const FrameFaults&, std::size_t i) {
         core::FrameView v = good_[i];
         v.exposure.exposure_us = 0.0;
         return v;
       },
       {core::Method::bad_exposure}},
      {"absurd exposure (10 s)",
       [&](const FrameFaults&, std::size_t i) {
         core::FrameView v = good_[i];
         v.exposure.exposure_us = 1e7;
         return v;
       },
       {core::Method::bad_exposure}},
      {"NaN exposure",
       [&](const FrameFaults&, std::size_t i) {
         core::FrameView v = good_[i];
         v.exposure.exposure_us = std::numeric_limits<double>::quiet_NaN();
         return v;
       },
       {core::Method::bad_exposure}},
      {"time backwards",
       [&](const FrameFaults&, std::size_t i) {
         core::FrameView v = good_[i];
         v.t_ns = good_[0].t_ns - 1'000'000'000;
         return v;
       },
       {core::Method::time_backwards}},
  };
  for (const BadFrame& b : bad) {
    SCOPED_TRACE(b.name);
    dsp::FrameProcessor p(config_);
    for (std::size_t i = 0; i < 4; ++i) expect_good(p.process(good_[i]), i, "start");
    const core::VelocityEstimate e = p.process(b.make(*this, 4));
    expect_nothing(e, b.name);
    if (!b.reasons.empty()) {
      EXPECT_NE(std::find(b.reasons.begin(), b.reasons.end(), e.method), b.reasons.end())
          << b.name << " was named '" << e.method << "'";
    }
    // The next good frames are measured as usual (after "time backwards" the
    // estimator restarts from the bad frame's clock, so a normal frame
    // after it is a forward gap: still measured from one frame).
    for (std::size_t i = 5; i < 8; ++i) expect_good(p.process(good_[i]), i, b.name);
    const dsp::FrameRejectCounters& r = p.rejects();
    const bool input_reject = b.name == "wrong size" || b.name.find("exposure") != std::string::npos ||
                              b.name == "time backwards";
    EXPECT_EQ(r.total(), input_reject ? 1u : 0u) << b.name << " counted as an input reject";
    for (const core::RejectReasonInfo& reason : core::kRejectReasons) {
      const bool this_one = input_reject && reason.method == e.method;
      EXPECT_EQ(r.of(reason.reason), this_one ? 1u : 0u) << b.name << " counted as " << reason.method;
    }
  }
}

TEST_F(FrameFaults, TimestampJumpForgetsThePairButMeasuresTheFrame) {
  dsp::FrameProcessor p(config_);
  for (std::size_t i = 0; i < 4; ++i) expect_good(p.process(good_[i]), i, "start");
  // The camera stalls for 3 s; every later frame is shifted by that much.
  constexpr std::int64_t kJumpNs = 3'000'000'000;
  for (std::size_t i = 4; i < 8; ++i) {
    core::FrameView v = good_[i];
    v.t_ns += kJumpNs;
    const core::VelocityEstimate e = p.process(v);
    expect_good(e, i, "a 3 s jump");
    EXPECT_NEAR(static_cast<double>(e.t_ns - v.t_ns) / 1e6, v.exposure.light_centre_us() / 1e3, 1.0)
        << "reported at its own mid-exposure time";
  }
  EXPECT_EQ(p.rejects().time_gap, 1u);
  EXPECT_EQ(p.rejects().total(), 0u);
}

TEST_F(FrameFaults, UnreadableFrameIsNamedCountedAndSkipped) {
  dsp::FrameProcessor p(config_);
  for (std::size_t i = 0; i < 4; ++i) expect_good(p.process(good_[i]), i, "start");
  const core::VelocityEstimate e = p.reject(good_[4], core::RejectReason::unreadable);
  expect_nothing(e, "unreadable");
  EXPECT_EQ(e.method, core::Method::unreadable);
  EXPECT_EQ(e.index, good_[4].index);
  for (std::size_t i = 5; i < 8; ++i) expect_good(p.process(good_[i]), i, "unreadable");
  EXPECT_EQ(p.rejects().of(core::RejectReason::unreadable), 1u);
  EXPECT_EQ(p.rejects().total(), 1u);
}

// Each defect a source reports is counted under its own reason and names
// itself in the estimate, so the health line tells a dark LED ring from an
// unreadable file.
TEST_F(FrameFaults, EachSourceDefectIsCountedUnderItsOwnReason) {
  dsp::FrameProcessor p(config_);
  for (std::size_t i = 0; i < 4; ++i) expect_good(p.process(good_[i]), i, "start");
  std::uint64_t n = 0;
  for (const core::RejectReasonInfo& reason : core::kRejectReasons) {
    SCOPED_TRACE(core::reject_word(reason.reason));
    for (std::uint64_t k = 0; k <= n; ++k) {  // reason i is reported i + 1 times
      const core::VelocityEstimate e = p.reject(good_[4], reason.reason);
      expect_nothing(e, core::reject_word(reason.reason));
      EXPECT_EQ(e.method, reason.method);
    }
    ++n;
  }
  n = 0;
  for (const core::RejectReasonInfo& reason : core::kRejectReasons) {
    EXPECT_EQ(p.rejects().of(reason.reason), ++n) << core::reject_word(reason.reason);
  }
  EXPECT_EQ(p.rejects().total(), n * (n + 1) / 2);
}

// The processing thread's estimator: a slot the light check marked dark
// counts as no-light-in-exposure, not as unreadable.
TEST_F(FrameFaults, FrameEstimatorCountsSlotDefectsPerReason) {
  const std::unique_ptr<FrameEstimator> est = make_frame_estimator("gvs", config_.estimator.camera);
  drivers::FrameSlot slot;
  slot.view = good_[0];
  slot.defect = core::RejectReason::no_light_in_exposure;
  EXPECT_EQ(est->estimate(slot).method, core::Method::no_light_in_exposure);
  slot.view = good_[1];
  slot.defect = core::RejectReason::no_exposure_metadata;
  EXPECT_EQ(est->estimate(slot).method, core::Method::no_exposure_metadata);
  slot.view = good_[2];
  slot.defect = core::RejectReason::no_light_in_exposure;
  (void)est->estimate(slot);
  const core::RejectCounts counts = est->rejected_frames();
  EXPECT_EQ(counts[static_cast<std::size_t>(core::RejectReason::no_light_in_exposure)], 2u);
  EXPECT_EQ(counts[static_cast<std::size_t>(core::RejectReason::no_exposure_metadata)], 1u);
  EXPECT_EQ(counts[static_cast<std::size_t>(core::RejectReason::unreadable)], 0u);
}

TEST_F(FrameFaults, ABurstOfBadFramesNeverGivesAnEstimate) {
  // 20 bad frames in a row, of every kind, interleaved: no estimate at all.
  dsp::FrameProcessor p(config_);
  for (std::size_t i = 0; i < 4; ++i) expect_good(p.process(good_[i]), i, "start");
  cv::RNG rng(11);
  for (int k = 0; k < 20; ++k) {
    core::FrameView v = good_[4 + static_cast<std::size_t>(k % 4)];
    v.t_ns = good_[4].t_ns + k * 16'666'667LL;
    v.index = good_[4].index + k;
    switch (k % 5) {
      case 0: v.gray = filled(0); break;
      case 1: v.gray = filled(255); break;
      case 2: v.gray = filled(90); break;
      case 3:
        v.gray = cv::Mat(good_[0].gray.size(), CV_8UC1);
        rng.fill(v.gray, cv::RNG::UNIFORM, 0, 256);
        break;
      default: v.exposure.exposure_us = -5.0; break;
    }
    expect_nothing(p.process(v), "bad frame " + std::to_string(k));
  }
}

}  // namespace
}  // namespace gvs::daemon
