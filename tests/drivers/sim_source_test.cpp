// The simulated camera (sim: source) says when it cannot render in real time.
#include <gtest/gtest.h>

#include <atomic>
#include <string>

#include "gvs/drivers/sim_source.hpp"

namespace gvs::drivers {
namespace {

std::string health_after_two_frames(double fps) {
  SimulatorConfig c;
  c.scenario = "sine";
  c.fps = fps;
  c.exposure_us = 100.0;  // fits in the shortest frame period below
  c.loop = true;
  c.periodic_texture = true;
  SimSource source(c);
  FrameSlot slot;
  source.prepare(slot);
  const std::atomic<bool> stop{false};
  for (int i = 0; i < 2; ++i) EXPECT_EQ(source.next(slot, stop), SourceStatus::frame);
  return source.health_text();
}

TEST(SimSource, SaysWhenItRendersSlowerThanTheFrameRate) {
  // A render takes milliseconds: a 2000 fps camera (0.5 ms a frame) is
  // beyond any machine, a 5 fps one (200 ms) within it.
  const std::string slow = health_after_two_frames(2000.0);
  EXPECT_NE(slow.find("ms per frame"), std::string::npos) << slow;
  EXPECT_NE(slow.find("sim: renders "), std::string::npos) << slow;
  EXPECT_NE(slow.find(" of 2000 fps on this machine: the frames it cannot render in time are dropped"),
            std::string::npos)
      << slow;
  EXPECT_EQ(health_after_two_frames(5.0), "") << "a source that keeps up says nothing";
}

}  // namespace
}  // namespace gvs::drivers
