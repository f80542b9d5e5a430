#include <gtest/gtest.h>

#include <linux/can/error.h>

#include <random>
#include <vector>

#include "gvs/can/bus_health.hpp"
#include "gvs/can/codec.hpp"
#include "gvs/can/monitor.hpp"

namespace gvs::can {
namespace {

CanFrame error_frame(std::uint32_t classes, std::uint8_t ctrl = 0) {
  CanFrame f;
  f.error = true;
  f.id = classes;
  f.len = 8;
  f.data[1] = ctrl;
  return f;
}

std::vector<SinkEvent> drain(BusHealth& h) {
  std::vector<SinkEvent> out(EventQueue::kCapacity + 1);
  out.resize(h.events.drain(out));
  return out;
}

TEST(ErrorFrames, DecodeLinuxErrorClasses) {
  ErrorFrameInfo e = decode_error_frame(error_frame(CAN_ERR_BUSOFF));
  EXPECT_TRUE(e.bus_off);
  e = decode_error_frame(error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_TX_PASSIVE));
  EXPECT_TRUE(e.error_passive);
  EXPECT_FALSE(e.bus_off);
  e = decode_error_frame(error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_RX_OVERFLOW));
  EXPECT_TRUE(e.overflow);
  e = decode_error_frame(error_frame(CAN_ERR_CRTL | CAN_ERR_CNT, CAN_ERR_CRTL_ACTIVE));
  EXPECT_TRUE(e.error_active);
  CanFrame cnt = error_frame(CAN_ERR_CRTL | CAN_ERR_CNT, CAN_ERR_CRTL_TX_WARNING);
  cnt.data[6] = 97;
  cnt.data[7] = 3;
  e = decode_error_frame(cnt);
  EXPECT_TRUE(e.error_warning);
  EXPECT_EQ(e.tx_error_count, 97);
  EXPECT_EQ(e.rx_error_count, 3);
  EXPECT_TRUE(decode_error_frame(error_frame(CAN_ERR_RESTARTED)).restarted);
  CanFrame shortf = error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_TX_PASSIVE);
  shortf.len = 1;
  EXPECT_FALSE(decode_error_frame(shortf).error_passive) << "data[1] absent in a 1-byte frame";
}

TEST(BusHealth, BusOffErrorPassiveAndControllerBecomeFaultsAndEvents) {
  BusHealth h;
  h.on_error_frame(error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_RX_PASSIVE), 1);
  h.on_error_frame(error_frame(CAN_ERR_BUSOFF), 2);
  auto ev = drain(h);
  ASSERT_EQ(ev.size(), 2u);
  EXPECT_EQ(ev[0].kind, SinkEventKind::ErrorPassive);
  EXPECT_EQ(ev[1].kind, SinkEventKind::BusOff);
  std::uint16_t bits = h.take_fault_bits();
  EXPECT_TRUE(bits & kFaultCanBusOff);
  EXPECT_TRUE(bits & kFaultCanErrorPassive);
  // Conditions persist until the controller says otherwise.
  EXPECT_EQ(h.take_fault_bits(), kFaultCanBusOff | kFaultCanErrorPassive);
  h.on_error_frame(error_frame(CAN_ERR_RESTARTED), 3);
  EXPECT_EQ(h.take_fault_bits(), 0);
  EXPECT_EQ(drain(h).at(0).kind, SinkEventKind::Restarted);
  // A transient controller problem is latched for exactly one status.
  h.on_error_frame(error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_TX_OVERFLOW), 4);
  EXPECT_EQ(h.take_fault_bits(), kFaultCanController);
  EXPECT_EQ(h.take_fault_bits(), 0);
  EXPECT_EQ(drain(h).at(0).kind, SinkEventKind::ControllerProblem);
  EXPECT_EQ(h.counters.error_frames, 4u);
  EXPECT_EQ(h.counters.bus_off, 1u);
}

TEST(BusHealth, SendFailuresAreCountedAndReportedOncePerBurst) {
  BusHealth h;
  h.on_send(SendResult::NoBuffers, ENOBUFS, 1);
  h.on_send(SendResult::NoBuffers, ENOBUFS, 2);
  h.on_send(SendResult::WouldBlock, EAGAIN, 3);
  h.on_send(SendResult::Ok, 0, 4);
  h.on_send(SendResult::WouldBlock, EAGAIN, 5);
  EXPECT_EQ(h.counters.no_buffers, 2u);
  EXPECT_EQ(h.counters.would_block, 2u);
  EXPECT_EQ(h.counters.frames_sent, 1u);
  EXPECT_EQ(h.counters.send_failures(), 4u);
  const auto ev = drain(h);
  ASSERT_EQ(ev.size(), 2u);
  EXPECT_EQ(ev[0].kind, SinkEventKind::SendFailed);
  EXPECT_EQ(ev[0].detail, static_cast<std::uint32_t>(ENOBUFS));
  EXPECT_EQ(h.take_fault_bits(), kFaultCanSendError);
}

TEST(BusHealth, InterfaceDownAndUp) {
  BusHealth h;
  h.on_interface_down(ENETDOWN, 1);
  h.on_interface_down(ENETDOWN, 2);
  EXPECT_EQ(h.take_fault_bits(), kFaultCanInterfaceDown);
  h.on_interface_up(3);
  EXPECT_EQ(h.take_fault_bits(), 0) << "the latch was taken by the previous status";
  const auto ev = drain(h);
  ASSERT_EQ(ev.size(), 2u);
  EXPECT_EQ(ev[0].kind, SinkEventKind::InterfaceDown);
  EXPECT_EQ(ev[1].kind, SinkEventKind::InterfaceUp);
}

TEST(EventQueue, OverflowIsReportedNotSilent) {
  EventQueue q;
  for (std::size_t i = 0; i < EventQueue::kCapacity + 5; ++i) q.push(SinkEventKind::BusOff, 0, 0);
  std::vector<SinkEvent> out(EventQueue::kCapacity + 10);
  const std::size_t n = q.drain(out);
  ASSERT_EQ(n, EventQueue::kCapacity + 1);
  EXPECT_EQ(out[0].kind, SinkEventKind::EventsLost);
  EXPECT_EQ(out[0].detail, 5u);
}

TEST(Monitor, RatesCountersAndValues) {
  Encoder enc({});
  MonitorState mon;
  std::int64_t t = 1'000'000'000;
  BusEstimate e;
  e.has_speed = e.has_direction = e.has_velocity_xy = true;
  e.speed_mps = 10.0;
  e.vx_mps = 10.0;
  e.direction_deg = 0.0;
  e.quality = 0.9;  // above the rule's min_quality
  for (int cycle = 0; cycle < 100; ++cycle) {
    e.t_ns = t - 5'000'000;
    CanFrame v, x;
    enc.estimate_frames(&e, t, ValidityRule{}, true, v, x);
    mon.feed(v, t);
    mon.feed(x, t + 100'000);
    if (cycle % 5 == 0) mon.feed(enc.status({SensorState::Running, 0, 0, 0, 0, 16}), t + 200'000);
    t += 20'000'000;
  }
  EXPECT_NEAR(mon.stats(MessageKind::Velocity).mean_rate_hz(), 50.0, 0.01);
  EXPECT_NEAR(mon.stats(MessageKind::Velocity).recent_rate_hz(), 50.0, 0.01);
  EXPECT_NEAR(mon.stats(MessageKind::Status).mean_rate_hz(), 10.0, 0.01);
  EXPECT_EQ(mon.stats(MessageKind::Velocity).counter_jumps, 0u);
  EXPECT_EQ(mon.stats(MessageKind::Velocity).crc_errors, 0u);
  EXPECT_NEAR(mon.velocity().speed_mps, 10.0, 0.005);
  EXPECT_TRUE(mon.velocity().valid);
  EXPECT_EQ(mon.velocity_xy().age_ms, 5u);

  // A lost frame, a corrupted frame, a foreign frame, an error frame.
  (void)enc.velocity({});  // never delivered
  mon.feed(enc.velocity({}), t);
  CanFrame bad = enc.velocity({});
  bad.data[5] ^= 1;
  mon.feed(bad, t + 20'000'000);
  CanFrame other;
  other.id = 0x100;
  other.len = 2;
  mon.feed(other, t);
  CanFrame err;
  err.error = true;
  err.id = CAN_ERR_BUSOFF;
  err.len = 8;
  mon.feed(err, t);
  const MessageStats& s = mon.stats(MessageKind::Velocity);
  EXPECT_EQ(s.counter_jumps, 1u);
  EXPECT_EQ(s.frames_lost, 1u);
  EXPECT_EQ(s.crc_errors, 1u);
  EXPECT_EQ(mon.other_frames(), 1u);
  EXPECT_EQ(mon.bus_errors().bus_off, 1u);
  EXPECT_FALSE(mon.velocity().valid) << "last good frame was an all-invalid one";
  const std::string view = mon.render(t + 40'000'000);
  EXPECT_NE(view.find("GVS_Velocity"), std::string::npos);
  EXPECT_NE(view.find("bus-off 1"), std::string::npos) << view;
  EXPECT_NE(view.find("faults 0x0000  dropped"), std::string::npos) << "no names without faults: " << view;
  // Fault bits by name, the new GVS_FaultImplausible among them.
  mon.feed(enc.status({SensorState::Degraded, kFaultCamera | kFaultImplausible, 0, 0, 0, 16}), t + 60'000'000);
  const std::string flagged = mon.render(t + 60'000'000);
  EXPECT_NE(flagged.find("faults 0x0801 (Camera, Implausible)"), std::string::npos) << flagged;
}

TEST(Monitor, SilenceIsFlaggedAndNotShownAsValid) {
  Encoder enc({});
  MonitorState mon;
  std::int64_t t = 1'000'000'000;
  const VelocityMsg valid{true, true, true, true, 10.0, 0.0, 0.0, 90.0};
  for (int cycle = 0; cycle < 50; ++cycle, t += 20'000'000) {
    mon.feed(enc.velocity(valid), t);
    if (cycle % 5 == 0) mon.feed(enc.status({SensorState::Running, 0, 0, 0, 0, 16}), t + 100'000);
  }
  const std::int64_t last = t - 20'000'000;
  // One period after the last frame: current, valid, 50 Hz.
  const std::string flowing = mon.render(last + 20'000'000);
  EXPECT_EQ(flowing.find("NO DATA"), std::string::npos) << flowing;
  EXPECT_NE(flowing.find("valid yes"), std::string::npos) << flowing;
  EXPECT_FALSE(mon.silent(MessageKind::Velocity, last + 20'000'000));
  // Status comes every 100 ms: 200 ms without one is not yet silence.
  EXPECT_FALSE(mon.silent(MessageKind::Status, last + 200'000'000));
  // Half a second of nothing: said on top, validity "old", rate 0.
  const std::string quiet = mon.render(last + 500'000'000);
  EXPECT_NE(quiet.find("NO DATA for 500 ms"), std::string::npos) << quiet;
  EXPECT_EQ(quiet.find("valid yes"), std::string::npos) << quiet;
  EXPECT_NE(quiet.find("36.00 km/h  valid old"), std::string::npos) << quiet;
  EXPECT_NE(quiet.find("GVS_Velocity         50       0.0     50.0"), std::string::npos) << quiet;
  EXPECT_TRUE(mon.silent(MessageKind::Velocity, last + 500'000'000));
  EXPECT_TRUE(mon.silent(MessageKind::Status, last + 500'000'000));
}

TEST(Monitor, SurvivesArbitraryFramesAndTimes) {
  std::mt19937_64 rng(99);
  MonitorState mon;
  for (int i = 0; i < 200000; ++i) {
    CanFrame f;
    f.id = static_cast<std::uint32_t>(rng());
    if (rng() % 2) f.id = 0x300 + static_cast<std::uint32_t>(rng() % 4);
    f.extended = rng() % 8 == 0;
    f.remote = rng() % 16 == 0;
    f.error = rng() % 16 == 0;
    f.len = static_cast<std::uint8_t>(rng());  // even > 8
    for (auto& b : f.data) b = static_cast<std::uint8_t>(rng());
    mon.feed(f, static_cast<std::int64_t>(rng()));
  }
  const std::string view = mon.render(static_cast<std::int64_t>(rng()));
  EXPECT_FALSE(view.empty());
  EXPECT_EQ(mon.total_frames(), 200000u);
}

}  // namespace
}  // namespace gvs::can
