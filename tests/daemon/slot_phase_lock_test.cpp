// SlotPhaseLock alone, on made-up times: which rates lock, the first step,
// the slew, the budget's memory, and a sender over 200 s of a camera whose
// clock runs fast, with estimator times that vary.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "gvs/daemon/slot_phase_lock.hpp"

namespace gvs::daemon {
namespace {

constexpr std::int64_t kMs = 1'000'000;

TEST(SlotPhaseLock, LocksOnRatesThatDivideOrAreMultiplesOfTheCanRate) {
  EXPECT_EQ(SlotPhaseLock::modulus_ns(20 * kMs, 100.0), 10 * kMs);  // two frames per period
  EXPECT_EQ(SlotPhaseLock::modulus_ns(20 * kMs, 250.0), 4 * kMs);
  EXPECT_EQ(SlotPhaseLock::modulus_ns(4 * kMs, 250.0), 4 * kMs);
  EXPECT_EQ(SlotPhaseLock::modulus_ns(20 * kMs, 50.0), 20 * kMs);
  EXPECT_EQ(SlotPhaseLock::modulus_ns(20 * kMs, 25.0), 20 * kMs);  // a frame every other period
  EXPECT_EQ(SlotPhaseLock::modulus_ns(20 * kMs, 60.0), std::nullopt);
  EXPECT_EQ(SlotPhaseLock::modulus_ns(20 * kMs, 0.0), std::nullopt);
  try {
    SlotPhaseLock lock(20 * kMs, 60.0);
    ADD_FAILURE() << "60 fps against 50 Hz accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("60"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("50"), std::string::npos) << e.what();
  }
}

TEST(SlotPhaseLock, FirstStepPutsTheSlotAfterThePublishAndNeverEarlier) {
  SlotPhaseLock lock(20 * kMs, 100.0, 1 * kMs, 100'000);
  EXPECT_EQ(lock.adjust(500 * kMs), 500 * kMs) << "nothing to lock to before the first estimate";
  // 100 fps on a grid at 3.3 ms (mod 10), each published 4 ms after its
  // capture; the first frame reached gvsd 2.7 ms late (a cold first render).
  std::int64_t captured = 453 * kMs + 300'000;
  for (std::size_t k = 0; k < SlotPhaseLock::kLockAfter; ++k, captured += 10 * kMs) {
    const std::int64_t late = k == 0 ? 2'700'000 : 0;
    lock.on_estimate(captured + late, captured + late + 4 * kMs);
    if (k + 1 < SlotPhaseLock::kLockAfter) {
      EXPECT_EQ(lock.adjust(500 * kMs), 500 * kMs) << "not locked on " << k + 1 << " estimates";
      EXPECT_FALSE(lock.locked());
    }
  }
  const std::int64_t next = lock.adjust(500 * kMs);
  EXPECT_TRUE(lock.locked());
  EXPECT_GE(next, 500 * kMs);
  EXPECT_EQ((next - (453 * kMs + 300'000 + 4 * kMs + 1 * kMs)) % (10 * kMs), 0)
      << next << ": the grid's phase, not the late frame's";
  EXPECT_LT(next - 500 * kMs, 10 * kMs);
}

TEST(SlotPhaseLock, OnceLockedTheSlotsMoveAtMostTheSlewPerPeriod) {
  SlotPhaseLock lock(20 * kMs, 50.0, 1 * kMs, 100'000);
  std::int64_t next = 1000 * kMs;
  std::int64_t capture = 910 * kMs;
  for (std::size_t k = 0; k < SlotPhaseLock::kLockAfter; ++k, capture += 20 * kMs)
    lock.on_estimate(capture, capture + 3 * kMs);
  capture -= 20 * kMs;
  next = lock.adjust(next + 20 * kMs);
  ASSERT_TRUE(lock.locked());
  for (int k = 0; k < 60; ++k) {
    capture += 20 * kMs;
    if (k == 5) capture += 3 * kMs;  // the camera's phase jumps by 3 ms, for good
    if (k == 40) capture += 1 * kMs;  // one frame reaches gvsd 1 ms late ...
    if (k == 41) capture -= 1 * kMs;  // ... and the next on time
    lock.on_estimate(capture, capture + 3 * kMs);
    const std::int64_t planned = next + 20 * kMs;
    const std::int64_t adjusted = lock.adjust(planned);
    EXPECT_LE(std::llabs(adjusted - planned), 100'000) << "period " << k;
    if (k < 8) {
      EXPECT_EQ(adjusted, planned) << "period " << k << ": the median phase has not moved yet";
    }
    next = adjusted;
  }
  // The median follows the jump after four frames; 3 ms at 0.1 ms per
  // period: back on the target 30 periods later, and the late frame moved nothing.
  EXPECT_EQ((next - (capture + 4 * kMs)) % (20 * kMs), 0);
}

TEST(SlotPhaseLock, TheBudgetIsTheSecondSlowestOfTheLast64Estimates) {
  SlotPhaseLock lock(20 * kMs, 100.0);
  std::int64_t t = 0;
  lock.on_estimate(t, t + 9 * kMs);  // a slow frame
  EXPECT_EQ(lock.budget_ns(), 9 * kMs) << "the only one so far";
  t += 10 * kMs;
  lock.on_estimate(t, t + 3 * kMs);
  EXPECT_EQ(lock.budget_ns(), 3 * kMs) << "one slow frame does not move the slots";
  t += 10 * kMs;
  lock.on_estimate(t, t + 8 * kMs);  // a second one
  EXPECT_EQ(lock.budget_ns(), 8 * kMs);
  for (int k = 0; k < 61; ++k) {
    t += 10 * kMs;
    lock.on_estimate(t, t + 3 * kMs);
  }
  EXPECT_EQ(lock.budget_ns(), 8 * kMs) << "both slow frames among the last 64";
  t += 10 * kMs;
  lock.on_estimate(t, t + 3 * kMs);
  EXPECT_EQ(lock.budget_ns(), 3 * kMs) << "the first is out: one slow frame left";
}

/// A sender with the lock over a camera `fps` whose clock runs 100 ppm fast,
/// estimator times 2-5 ms (a fixed pseudo-random sequence): the age of the
/// estimate each slot carries, after the first second.
std::vector<std::int64_t> carried_ages(double fps, std::int64_t period_ns, std::vector<std::int64_t>& periods) {
  SlotPhaseLock lock(period_ns, fps, 1 * kMs, 100'000);
  const double frame_ns = 1e9 / fps / (1.0 + 100e-6);
  std::uint32_t rng = 12345;
  auto delay_ns = [&] {
    rng = rng * 1664525u + 1013904223u;
    return 2 * kMs + static_cast<std::int64_t>(rng % 3000u) * 1000;
  };
  std::int64_t next = 7 * kMs + 123'456;  // any phase
  std::int64_t previous = next;
  std::int64_t frame = 0;
  std::int64_t newest_captured = -1, newest_published = -1, seen_captured = -1;
  std::int64_t pending_captured = 0, pending_published = 0;
  bool pending = false;
  std::vector<std::int64_t> ages;
  for (int k = 0; k < static_cast<int>(200e9 / static_cast<double>(period_ns)); ++k) {
    // Every frame published by the wake-up; the newest is what the sender reads.
    for (;;) {
      if (!pending) {
        pending_captured = static_cast<std::int64_t>(static_cast<double>(frame) * frame_ns);
        pending_published = pending_captured + delay_ns();
        pending = true;
      }
      if (pending_published > next) break;
      newest_captured = pending_captured;
      newest_published = pending_published;
      pending = false;
      ++frame;
    }
    if (newest_captured >= 0 && next >= 1'000 * kMs) ages.push_back(next - newest_captured);
    if (newest_captured != seen_captured && newest_captured >= 0) {
      lock.on_estimate(newest_captured, newest_published);
      seen_captured = newest_captured;
    }
    next = lock.adjust(next + period_ns);
    if (previous >= 1'000 * kMs) periods.push_back(next - previous);
    previous = next;
  }
  return ages;
}

TEST(SlotPhaseLock, ASenderCarriesEachFrameOnceItIsPublishedOverADriftingCamera) {
  for (const auto& [fps, period_ns] : {std::pair{100.0, 20 * kMs}, std::pair{50.0, 20 * kMs},
                                       std::pair{250.0, 4 * kMs}, std::pair{250.0, 20 * kMs}}) {
    std::vector<std::int64_t> periods;
    const std::vector<std::int64_t> ages = carried_ages(fps, period_ns, periods);
    ASSERT_GT(ages.size(), 1000u);
    // The slowest estimates take 5 ms: every slot carries a frame captured
    // at most 5 ms + the margin + one slew step + the drift of one period
    // ago (the second slowest of 64 is within 0.05 ms of the slowest here).
    const std::int64_t oldest = *std::max_element(ages.begin(), ages.end());
    EXPECT_LE(oldest, 6 * kMs + 150'000) << fps << " fps, period " << period_ns;
    const std::int64_t youngest = *std::min_element(ages.begin(), ages.end());
    EXPECT_GE(youngest, 2 * kMs) << "never a frame not yet published";
    for (const std::int64_t p : periods) ASSERT_LE(std::llabs(p - period_ns), 100'000);
  }
}

}  // namespace
}  // namespace gvs::daemon
