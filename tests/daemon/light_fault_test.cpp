// GVS_FaultLight through the sender's status: a strobe whose writes fail for
// a while raises the bit in the statuses covering the failures, and only in
// those ("since the last status", like the other counted faults).
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <memory>
#include <span>
#include <thread>

#include "gvs/can/sink.hpp"
#include "gvs/drivers/clock.hpp"
#include "gvs/daemon/pipeline.hpp"
#include "gvsd_test_support.hpp"
#include "steady_camera.hpp"

namespace gvs::daemon {
namespace {

/// A hardware-timed strobe whose fire() reports a failed write while `failing`.
class ScriptedStrobe final : public drivers::StrobeDriver {
 public:
  explicit ScriptedStrobe(std::shared_ptr<std::atomic<bool>> failing) : failing_(std::move(failing)) {}
  std::string describe() const override { return "scripted strobe"; }
  bool arm(const core::ExposurePlan&, double) noexcept override { return true; }
  drivers::FireReport fire(std::int64_t) noexcept override {
    drivers::FireReport r;
    r.error = failing_->load();
    return r;
  }
  std::span<const drivers::StrobeEdge> last_edges() const noexcept override { return {}; }
  bool hardware_timed() const noexcept override { return true; }

 private:
  std::shared_ptr<std::atomic<bool>> failing_;
};

TEST(LightFault, StrobeErrorsRaiseGvsFaultLightInTheNextStatusOnly) {
  const std::string log = (std::filesystem::temp_directory_path() /
                           ("gvsd_light_fault_" + std::to_string(getpid()) + ".log")).string();
  auto failing = std::make_shared<std::atomic<bool>>(false);
  PipelineHooks hooks;
  hooks.make_light = [failing](const drivers::StrobeConfig&) { return std::make_unique<ScriptedStrobe>(failing); };
  Pipeline p(testing::unprivileged_config(), std::make_unique<testing::SteadyCamera>(),
             make_frame_estimator("truth", {}), can::open_sink("candump:" + log), hooks);
  p.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(350));
  const std::int64_t fail_from_real = drivers::real_now_ns();
  failing->store(true);
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  failing->store(false);
  const std::int64_t fail_to_real = drivers::real_now_ns();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  p.request_stop();
  p.join();
  const auto msgs = testing::read_candump_log(log);
  std::filesystem::remove(log);

  EXPECT_GT(p.counters().light_errors.load(), 0u);
  ASSERT_GE(msgs.status.size(), 8u);
  int clean_before = 0, flagged_during = 0, clean_after = 0;
  for (std::size_t i = 0; i + 1 < msgs.status.size(); ++i) {  // the last one is Stopping
    const bool light = (msgs.status[i].decoded.status_msg.faults & can::kFaultLight) != 0;
    const std::int64_t t = msgs.status[i].t_ns;
    if (t < fail_from_real) {
      EXPECT_FALSE(light) << "status " << i << " before any strobe error";
      ++clean_before;
    } else if (i > 0 && msgs.status[i - 1].t_ns > fail_to_real + 50 * drivers::kNsPerMs) {
      // The previous status already counted every error: nothing new since.
      EXPECT_FALSE(light) << "status " << i << " after the strobe recovered";
      ++clean_after;
    } else {
      flagged_during += light ? 1 : 0;
    }
  }
  EXPECT_GE(clean_before, 2);
  EXPECT_GE(flagged_during, 1) << "GVS_FaultLight while the strobe's writes fail";
  EXPECT_GE(clean_after, 2);
}

}  // namespace
}  // namespace gvs::daemon
