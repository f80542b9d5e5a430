// The estimate as the bus sees it: every method the estimators, the frame
// checks and the truth source report goes out in GVS_Status with its own
// GVS_Method code, which decodes back to the same method.
#include <gtest/gtest.h>

#include <optional>
#include <set>

#include "gvs/can/codec.hpp"
#include "gvs/daemon/bus_estimate.hpp"
#include "gvs/core/estimate.hpp"
#include "gvs/core/method.hpp"

namespace gvs::daemon {
namespace {

TEST(BusEstimate, EveryMethodGoesOutWithItsOwnCodeAndDecodesBack) {
  const can::MessageIds ids;
  std::set<int> codes;
  for (const core::MethodInfo& info : core::kMethods) {
    if (info.method == core::Method::unknown) continue;  // only read from foreign CSVs, never estimated
    SCOPED_TRACE(info.word);
    core::VelocityEstimate e;
    e.method = info.method;
    can::StatusMsg status;
    status.method = bus_estimate(e).method_code;
    const can::DecodedFrame d = can::decode(can::encode_status(status, ids, 0), ids);
    ASSERT_EQ(d.status, can::DecodeStatus::Ok);
    EXPECT_NE(d.status_msg.method, 255) << "sent as 'unknown'";
    EXPECT_EQ(core::method_from_can_code(d.status_msg.method), std::optional<core::Method>(info.method));
    EXPECT_STREQ(method_word_of_code(d.status_msg.method), info.word) << "the word gvs monitor shows";
    codes.insert(d.status_msg.method);
  }
  EXPECT_EQ(codes.size(), core::kMethodCount - 1) << "two methods share a code";
  EXPECT_EQ(method_word_of_code(250), nullptr) << "a code outside the table has no word";
}

TEST(BusEstimate, CarriesTheQuantitiesWithTheirFlags) {
  core::VelocityEstimate e;
  e.t_ns = 123;
  e.has_speed = true;
  e.speed_mps = 0.0;  // standing still: vx, vy known without a direction
  e.has_yaw_rate = true;
  e.yaw_rate_dps = -1.5;
  e.quality = 0.7;
  e.method = core::Method::still;
  can::BusEstimate b = bus_estimate(e);
  EXPECT_EQ(b.t_ns, 123);
  EXPECT_TRUE(b.has_speed && b.has_yaw_rate && b.has_velocity_xy);
  EXPECT_FALSE(b.has_direction);
  EXPECT_EQ(b.yaw_rate_dps, -1.5);
  EXPECT_EQ(b.quality, 0.7);
  EXPECT_EQ(b.method_code, core::method_can_code(core::Method::still));
  e.speed_mps = 5.0;  // moving without a direction: no vx, vy
  b = bus_estimate(e);
  EXPECT_FALSE(b.has_velocity_xy);
}

}  // namespace
}  // namespace gvs::daemon
