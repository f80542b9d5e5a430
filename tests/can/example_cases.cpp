#include "example_cases.hpp"

#include "gvs/can/e2e.hpp"

namespace gvs::can::test {

namespace {

void add_header(ExampleCase& c) {
  c.expect["GVS_CRC"] = c.frame.data[0];
  c.expect["GVS_Counter"] = e2e_counter(c.frame);
}

ExampleCase velocity_case(const VelocityMsg& v, std::uint8_t counter) {
  ExampleCase c{"GVS_Velocity", encode_velocity(v, MessageIds{}, counter), {}};
  add_header(c);
  c.expect["GVS_Valid"] = v.valid;
  c.expect["GVS_SpeedValid"] = v.speed_valid;
  c.expect["GVS_DirectionValid"] = v.direction_valid;
  c.expect["GVS_YawRateValid"] = v.yaw_rate_valid;
  c.expect["GVS_Speed"] = v.speed_valid ? v.speed_mps : 0.0;
  c.expect["GVS_Direction"] = v.direction_valid ? v.direction_deg : 0.0;
  c.expect["GVS_YawRate"] = v.yaw_rate_valid ? v.yaw_rate_dps : 0.0;
  c.expect["GVS_Quality"] = v.quality_pct;
  return c;
}

ExampleCase xy_case(const VelocityXyMsg& m, std::uint8_t counter) {
  ExampleCase c{"GVS_VelocityXY", encode_velocity_xy(m, MessageIds{}, counter), {}};
  add_header(c);
  c.expect["GVS_Valid"] = m.valid;
  c.expect["GVS_Vx"] = m.valid ? m.vx_mps : 0.0;
  c.expect["GVS_Vy"] = m.valid ? m.vy_mps : 0.0;
  c.expect["GVS_Age"] = m.age_ms;
  c.expect["GVS_ScaleSource"] = static_cast<double>(m.scale_source);
  return c;
}

ExampleCase status_case(const StatusMsg& m, std::uint8_t counter) {
  ExampleCase c{"GVS_Status", encode_status(m, MessageIds{}, counter), {}};
  add_header(c);
  static const char* const kFaultNames[] = {
      "GVS_FaultCamera",        "GVS_FaultEstimateStale",   "GVS_FaultRingOverrun",
      "GVS_FaultDeadlineMiss",  "GVS_FaultCanBusOff",       "GVS_FaultCanErrorPassive",
      "GVS_FaultCanController", "GVS_FaultCanInterfaceDown", "GVS_FaultCanSendError",
      "GVS_FaultLight",         "GVS_FaultNoRealtime",      "GVS_FaultImplausible",
      "GVS_FaultScaleUncorrected"};
  c.expect["GVS_State"] = static_cast<double>(m.state);
  for (unsigned i = 0; i < std::size(kFaultNames); ++i) c.expect[kFaultNames[i]] = (m.faults >> i) & 1u;
  c.expect["GVS_DroppedFrames"] = m.dropped_frames;
  c.expect["GVS_RingOverruns"] = m.ring_overruns;
  c.expect["GVS_CanSendErrors"] = m.can_send_errors;
  c.expect["GVS_Method"] = m.method;
  return c;
}

ExampleCase timing_case(const TimingMsg& m, std::uint8_t counter) {
  ExampleCase c{"GVS_Timing", encode_timing(m, MessageIds{}, counter), {}};
  add_header(c);
  c.expect["GVS_Exposure"] = m.exposure_us;
  c.expect["GVS_ProcessingTime"] = m.processing_time_us;
  c.expect["GVS_LateWakeups"] = m.late_wakeups;
  return c;
}

ExampleCase ride_height_case(const RideHeightMsg& m, std::uint8_t counter) {
  ExampleCase c{"GVS_RideHeight", encode_ride_height(m, MessageIds{}, counter), {}};
  add_header(c);
  c.expect["GVS_HeightValid"] = m.height_valid;
  c.expect["GVS_PitchValid"] = m.pitch_valid;
  c.expect["GVS_RollValid"] = m.roll_valid;
  c.expect["GVS_ScaleSource"] = static_cast<double>(m.scale_source);
  c.expect["GVS_Height"] = m.height_valid ? m.height_mm : 0.0;
  c.expect["GVS_Pitch"] = m.pitch_valid ? m.pitch_deg : 0.0;
  c.expect["GVS_Roll"] = m.roll_valid ? m.roll_deg : 0.0;
  c.expect["GVS_HeightAge"] = m.age_ms;
  return c;
}

}  // namespace

std::vector<ExampleCase> example_cases() {
  std::vector<ExampleCase> cases;
  cases.push_back(velocity_case(worked_example_velocity(), kWorkedExampleCounter));
  // Extremes of every range and sign.
  cases.push_back(velocity_case({true, true, true, true, 81.91, 180.0, 204.7, 100.0}, 15));
  cases.push_back(velocity_case({true, true, true, true, 0.0, -180.0, -204.7, 0.0}, 0));
  cases.push_back(velocity_case({false, false, true, true, 0.0, 90.01, -0.1, 33.0}, 1));
  cases.push_back(velocity_case({false, true, false, false, 69.44, 0.0, 0.0, 55.0}, 2));
  cases.push_back(xy_case({true, 69.444, -12.345, 3}, 4));
  cases.push_back(xy_case({true, -163.835, 163.835, 0}, 5));
  cases.push_back(xy_case({false, 0.0, 0.0, 65535}, 6));
  cases.push_back(xy_case({true, 1.5, 0.25, 12, ScaleSourceCode::External}, 13));
  cases.push_back(xy_case({true, 10.0, -0.5, 7, ScaleSourceCode::LaserDots}, 14));
  cases.push_back(status_case({SensorState::Running, 0, 0, 0, 0, 16}, 7));
  cases.push_back(status_case({SensorState::Fault, 0x1FFF, 255, 128, 1, 255}, 8));
  cases.push_back(status_case({SensorState::Running, kFaultScaleUncorrected, 0, 0, 0, 40}, 13));
  cases.push_back(status_case({SensorState::Stopping, kFaultCanInterfaceDown | kFaultLight, 17, 3, 99, 1}, 9));
  cases.push_back(status_case({SensorState::Degraded, kFaultImplausible, 0, 0, 0, 0}, 12));
  cases.push_back(timing_case({65535, 0, 255}, 10));
  cases.push_back(timing_case({1234, 5678, 9}, 11));
  cases.push_back(ride_height_case({true, true, true, ScaleSourceCode::LaserDots, 60.37, -1.25, 0.84, 3}, 0));
  cases.push_back(ride_height_case({true, true, true, ScaleSourceCode::LaserDots, 655.35, 20.47, -20.47, 0}, 15));
  cases.push_back(ride_height_case({true, false, true, ScaleSourceCode::LaserDots, 59.80, 0.0, -0.42, 126}, 3));
  cases.push_back(ride_height_case({true, false, false, ScaleSourceCode::External, 58.12, 0.0, 0.0, 4}, 1));
  cases.push_back(ride_height_case({false, false, false, ScaleSourceCode::Nominal, 0.0, 0.0, 0.0, 127}, 2));
  return cases;
}

}  // namespace gvs::can::test
