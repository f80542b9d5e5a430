// gvs_can_vcan_bench: the SocketCAN sink on a real (virtual) bus. Runs where
// vcan0 exists and is up (tests/bench/qemu-vcan.sh provides one):
//   gvs_can_vcan_bench traffic [IFACE]  sends the gvs messages for 2 s on the
//       20/100 ms schedule, receives them on a second raw socket and checks
//       every frame's bytes, CRCs, alive counters, rates and decoded values;
//   gvs_can_vcan_bench fault [IFACE]    takes the interface down and up, then
//       deletes and re-creates it while sending: the sink must report it
//       (events, fault bits, counters), keep running and resume; error frames
//       written onto the bus and injected directly must become fault bits.
// Needs root (interface up/down). Prints one line per check; exit 0 = all passed.
#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "gvs/can/codec.hpp"
#include "gvs/can/e2e.hpp"
#include "gvs/can/monitor.hpp"
#include "gvs/can/socketcan_sink.hpp"

using namespace gvs::can;

namespace {

int g_failures = 0;
int g_checks = 0;

void check(bool ok, const std::string& what) {
  ++g_checks;
  if (!ok) ++g_failures;
  std::printf("%s %s\n", ok ? "ok  " : "FAIL", what.c_str());
  std::fflush(stdout);
}

std::int64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

void sleep_until(std::int64_t t_ns) {
  timespec ts{static_cast<time_t>(t_ns / 1'000'000'000), static_cast<long>(t_ns % 1'000'000'000)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

int open_receiver(const std::string& iface) {
  const int fd = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK, CAN_RAW);
  if (fd < 0) return -1;
  ifreq ifr{};
  std::strncpy(ifr.ifr_name, iface.c_str(), IFNAMSIZ - 1);
  if (::ioctl(fd, SIOCGIFINDEX, &ifr) != 0) {
    ::close(fd);
    return -1;
  }
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifr.ifr_ifindex;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

/// Reads every pending frame into `out` (data frames only).
void receive_all(int fd, std::vector<CanFrame>& out, MonitorState& mon) {
  if (fd < 0) return;
  for (;;) {
    can_frame cf{};
    const ssize_t n = ::recv(fd, &cf, sizeof cf, 0);
    if (n != static_cast<ssize_t>(sizeof cf)) return;
    CanFrame f;
    f.error = (cf.can_id & CAN_ERR_FLAG) != 0;
    f.extended = (cf.can_id & CAN_EFF_FLAG) != 0;
    f.id = cf.can_id & (f.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
    f.len = cf.len;
    std::memcpy(f.data.data(), cf.data, 8);
    mon.feed(f, now_ns());
    out.push_back(f);
  }
}

bool set_link_up(const std::string& iface, bool up) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) return false;
  ifreq ifr{};
  std::strncpy(ifr.ifr_name, iface.c_str(), IFNAMSIZ - 1);
  bool ok = ::ioctl(fd, SIOCGIFFLAGS, &ifr) == 0;
  if (ok) {
    ifr.ifr_flags = static_cast<short>(up ? (ifr.ifr_flags | IFF_UP) : (ifr.ifr_flags & ~IFF_UP));
    ok = ::ioctl(fd, SIOCSIFFLAGS, &ifr) == 0;
  }
  ::close(fd);
  return ok;
}

BusEstimate estimate_for_cycle(int cycle, std::int64_t t_ns) {
  BusEstimate e;
  e.t_ns = t_ns - 7'000'000;  // 7 ms old at send time
  e.has_speed = e.has_direction = e.has_velocity_xy = true;
  e.has_yaw_rate = cycle % 2 == 0;
  e.speed_mps = 5.0 + 0.1 * cycle;
  e.direction_deg = -30.0 + 0.5 * cycle;
  e.vx_mps = e.speed_mps * std::cos(e.direction_deg * M_PI / 180.0);
  e.vy_mps = e.speed_mps * std::sin(e.direction_deg * M_PI / 180.0);
  e.yaw_rate_dps = 10.0 - 0.2 * cycle;
  e.quality = 0.75;
  e.method_code = 33;
  e.scale_source = ScaleSourceCode::LaserDots;
  e.has_height = e.has_pitch = e.has_roll = true;
  e.height_mm = 60.0 + 0.01 * cycle;
  e.pitch_deg = -0.5 + 0.01 * cycle;
  e.roll_deg = 0.25;
  return e;
}

struct CycleResult {
  int sent = 0;
  int down_results = 0;
  std::vector<SinkEvent> events;
  std::uint16_t fault_bits = 0;
};

/// One 20 ms cycle: two velocity frames, status + timing every fifth cycle.
void run_cycle(Encoder& enc, SocketCanSink& sink, int cycle, std::int64_t t, std::vector<CanFrame>& sent,
               CycleResult& r) {
  const BusEstimate e = estimate_for_cycle(cycle, t);
  CanFrame v, x;
  enc.estimate_frames(&e, t, ValidityRule{}, true, v, x);
  std::vector<CanFrame> frames{v, x, enc.ride_height(ride_height_from_estimate(&e, t, ValidityRule{}))};
  if (cycle % 5 == 0) {
    StatusMsg st{SensorState::Running, 0, 0, 0, static_cast<std::uint8_t>(sink.counters().send_failures()),
                 e.method_code};
    st.faults = sink.take_fault_bits();
    r.fault_bits |= st.faults;
    frames.push_back(enc.status(st));
    frames.push_back(enc.timing({1500, 2100, 0}));
  }
  for (const CanFrame& f : frames) {
    const SendResult res = sink.send(f);
    if (res == SendResult::Ok) {
      ++r.sent;
      sent.push_back(f);
    } else if (res == SendResult::InterfaceDown) {
      ++r.down_results;
    }
  }
  SinkEvent ev[16];
  const std::size_t n = sink.poll_events(ev);
  for (std::size_t i = 0; i < n; ++i) {
    r.events.push_back(ev[i]);
    std::printf("     event at cycle %d: %.*s (detail %u)\n", cycle, static_cast<int>(to_string(ev[i].kind).size()),
                to_string(ev[i].kind).data(), ev[i].detail);
  }
}

bool has_event(const std::vector<SinkEvent>& events, SinkEventKind k) {
  for (const SinkEvent& e : events) {
    if (e.kind == k) return true;
  }
  return false;
}

int traffic(const std::string& iface) {
  SocketCanSink sink(iface);
  Encoder enc({});
  const int rx = open_receiver(iface);
  check(rx >= 0, "second raw socket bound to " + iface);
  MonitorState mon;
  std::vector<CanFrame> sent, received;
  CycleResult r;
  constexpr int kCycles = 100;
  const std::int64_t start = now_ns() + 20'000'000;
  for (int c = 0; c < kCycles; ++c) {
    const std::int64_t t = start + std::int64_t{c} * 20'000'000;
    sleep_until(t);
    run_cycle(enc, sink, c, t, sent, r);
    receive_all(rx, received, mon);
  }
  usleep(50'000);
  receive_all(rx, received, mon);

  check(r.sent == kCycles * 3 + kCycles / 5 * 2, "sent " + std::to_string(r.sent) + " frames without a failure");
  check(sink.counters().send_failures() == 0, "no send failures counted");
  check(received.size() == sent.size(), "received " + std::to_string(received.size()) + " of " +
                                            std::to_string(sent.size()) + " frames");
  bool same = received.size() == sent.size();
  for (std::size_t i = 0; same && i < sent.size(); ++i) {
    same = received[i].id == sent[i].id && received[i].len == 8 && received[i].data == sent[i].data;
  }
  check(same, "every received frame is byte-identical and in order");
  for (const MessageSpec& m : kMessages) {
    const MessageStats& s = mon.stats(m.kind);
    const double want = 1000.0 / m.period_ms;
    char buf[160];
    std::snprintf(buf, sizeof buf, "%.*s: %llu frames, mean %.2f Hz (want %.0f), max gap %.1f ms, CRC errors %llu, "
                  "counter jumps %llu", static_cast<int>(m.name.size()), m.name.data(),
                  static_cast<unsigned long long>(s.frames), s.mean_rate_hz(), want, s.max_gap_ms,
                  static_cast<unsigned long long>(s.crc_errors), static_cast<unsigned long long>(s.counter_jumps));
    check(s.frames > 0 && std::fabs(s.mean_rate_hz() - want) < 0.1 * want && s.crc_errors == 0 &&
              s.counter_jumps == 0,
          buf);
  }
  const auto last = estimate_for_cycle(kCycles - 1, 0);
  check(std::fabs(mon.velocity().speed_mps - last.speed_mps) <= 0.005 + 1e-9 &&
            std::fabs(mon.velocity().direction_deg - last.direction_deg) <= 0.005 + 1e-9 && mon.velocity().valid &&
            !mon.velocity().yaw_rate_valid,
        "last GVS_Velocity decodes to the last estimate (odd cycle: no yaw rate)");
  check(mon.velocity_xy().valid && mon.velocity_xy().age_ms == 7 &&
            std::fabs(mon.velocity_xy().vx_mps - last.vx_mps) <= 0.0025 + 1e-9,
        "last GVS_VelocityXY: valid, age 7 ms, vx matches");
  check(mon.status().state == SensorState::Running && mon.status().faults == 0, "GVS_Status running, no faults");
  check(mon.ride_height().height_valid && mon.ride_height().pitch_valid && mon.ride_height().roll_valid &&
            mon.ride_height().scale_source == ScaleSourceCode::LaserDots && mon.ride_height().age_ms == 7 &&
            std::fabs(mon.ride_height().height_mm - 60.99) <= 0.005 + 1e-9 &&
            std::fabs(mon.ride_height().pitch_deg - 0.49) <= 0.005 + 1e-9,
        "last GVS_RideHeight: height 60.99 mm, pitch 0.49 deg, laser dots, age 7 ms");
  if (rx >= 0) ::close(rx);
  return 0;
}

int fault(const std::string& iface) {
  SocketCanSink sink(iface, 200);
  Encoder enc({});
  int rx = open_receiver(iface);
  MonitorState mon;
  std::vector<CanFrame> sent, received;
  CycleResult before, down, after, removed, back;
  std::int64_t t = now_ns();
  auto cycles = [&](int from, int to, CycleResult& r) {
    for (int c = from; c < to; ++c) {
      t += 20'000'000;
      sleep_until(t);
      run_cycle(enc, sink, c, t, sent, r);
      receive_all(rx, received, mon);
    }
  };
  cycles(0, 10, before);
  check(before.sent > 0 && before.down_results == 0 && sink.is_open(), "sending before the fault");

  check(set_link_up(iface, false), "ip link set " + iface + " down");
  cycles(10, 30, down);
  check(down.down_results > 0, "send() returns InterfaceDown while down (" + std::to_string(down.down_results) +
                                   " frames)");
  check(has_event(down.events, SinkEventKind::InterfaceDown), "InterfaceDown event reported");
  check((down.fault_bits & kFaultCanInterfaceDown) != 0, "GVS_FaultCanInterfaceDown set in the status");
  check(sink.counters().dropped_down > 0, "dropped frames counted");

  check(set_link_up(iface, true), "ip link set " + iface + " up");
  const std::size_t received_before_up = received.size();
  cycles(30, 60, after);
  check(has_event(after.events, SinkEventKind::InterfaceUp), "InterfaceUp event: the sink reopened by itself");
  check(sink.is_open() && received.size() > received_before_up + 10, "frames flow again after up (" +
                                                                         std::to_string(received.size() -
                                                                                        received_before_up) + ")");

  // Remove the interface and create it again (new ifindex).
  const std::string del = "ip link del dev " + iface + " 2>/dev/null || busybox ip link del dev " + iface;
  check(std::system(del.c_str()) == 0, "interface deleted");
  cycles(60, 75, removed);
  check(removed.down_results > 0 && has_event(removed.events, SinkEventKind::InterfaceDown),
        "removal detected (InterfaceDown)");
  const std::string add = "(ip link add dev " + iface + " type vcan 2>/dev/null || busybox ip link add dev " + iface +
                          " type vcan) && (ip link set " + iface + " up 2>/dev/null || busybox ip link set " + iface +
                          " up)";
  check(std::system(add.c_str()) == 0, "interface re-created and up");
  if (rx >= 0) ::close(rx);
  rx = open_receiver(iface);
  const std::size_t received_before_readd = received.size();
  cycles(75, 110, back);
  check(has_event(back.events, SinkEventKind::InterfaceUp) && sink.is_open(), "sink reopened the new interface");
  check(received.size() > received_before_readd + 10, "frames flow on the re-created interface");
  check(sink.counters().reopens >= 2, "reopens counted: " + std::to_string(sink.counters().reopens));

  // Error frames. vcan has no controller, so it never generates them; a raw
  // socket may write a frame with CAN_ERR_FLAG set, which vcan loops back to
  // every socket subscribed to that error class.
  const int tx = open_receiver(iface);
  can_frame cf{};
  cf.can_id = CAN_ERR_FLAG | CAN_ERR_CRTL;
  cf.len = CAN_ERR_DLC;
  cf.data[1] = CAN_ERR_CRTL_TX_PASSIVE;
  const bool wrote = tx >= 0 && ::write(tx, &cf, sizeof cf) == static_cast<ssize_t>(sizeof cf);
  usleep(20'000);
  SinkEvent ev[16];
  std::size_t n = sink.poll_events(ev);
  bool passive_seen = false;
  for (std::size_t i = 0; i < n; ++i) passive_seen |= ev[i].kind == SinkEventKind::ErrorPassive;
  std::printf("     error frame written on %s: %s; seen by the sink: %s\n", iface.c_str(), wrote ? "yes" : "no",
              passive_seen ? "yes" : "no");
  check(wrote && passive_seen, "an error frame on the bus becomes an ErrorPassive event");
  check(wrote && (sink.take_fault_bits() & kFaultCanErrorPassive) != 0, "... and GVS_FaultCanErrorPassive");
  if (tx >= 0) ::close(tx);

  CanFrame busoff;
  busoff.error = true;
  busoff.id = CAN_ERR_BUSOFF;
  busoff.len = 8;
  sink.inject_error_frame(busoff);
  n = sink.poll_events(ev);
  check(n >= 1 && ev[0].kind == SinkEventKind::BusOff, "injected bus-off error frame → BusOff event");
  check((sink.take_fault_bits() & kFaultCanBusOff) != 0, "... and GVS_FaultCanBusOff");
  check(mon.stats(MessageKind::Velocity).crc_errors == 0, "no CRC errors across the faults");
  if (rx >= 0) ::close(rx);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  const std::string iface = argc > 2 ? argv[2] : "vcan0";
  try {
    if (mode == "traffic") {
      traffic(iface);
    } else if (mode == "fault") {
      fault(iface);
    } else {
      std::fprintf(stderr, "usage: gvs_can_vcan_bench traffic|fault [IFACE]\n");
      return 2;
    }
  } catch (const std::exception& e) {
    std::printf("FAIL %s\n", e.what());
    return 1;
  }
  std::printf("%d passed, %d failed\n", g_checks - g_failures, g_failures);
  return g_failures == 0 ? 0 : 1;
}
