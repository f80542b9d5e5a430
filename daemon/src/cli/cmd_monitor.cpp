// gvs monitor: a live view of decoded gvs CAN traffic (speed, direction, yaw
// rate, validity, age, message rates, alive-counter jumps, CRC errors, bus
// error frames), from a SocketCAN interface or a candump -L log file.
//   gvs monitor can0                 live view until Ctrl-C
//   gvs monitor run.log              replay the log, print a summary
//   gvs monitor run.log --follow     keep reading the growing log (like tail -f)
//   gvsd | gvs monitor -             live view of a pipe until it ends
// The decoding and statistics are gvs::can::MonitorState (can/).
#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>

#include <CLI/CLI.hpp>

#include "gvs/can/candump.hpp"
#include "gvs/can/codec.hpp"
#include "gvs/can/monitor.hpp"
#include "gvs/daemon/bus_estimate.hpp"
#include "usage.hpp"

namespace gvs::cli {

namespace {

struct MonitorCliOptions {
  std::string target;
  std::uint32_t base_id = can::kDefaultBaseId;
  bool follow = false;
  int refresh_ms = 250;
  double max_seconds = 0.0;  ///< 0 = until Ctrl-C (bus / --follow)
  bool plain = false;        ///< no screen clearing (for logs and pipes)
};

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop = true; }

std::int64_t realtime_ns() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

void show(const can::MonitorState& mon, std::int64_t now_ns, const MonitorCliOptions& o, const std::string& source) {
  if (!o.plain) std::fputs("\033[H\033[2J", stdout);
  std::printf("source: %s\n%s", source.c_str(), mon.render(now_ns).c_str());
  if (o.plain) std::fputs("\n", stdout);
  std::fflush(stdout);
}

/// A log to read (file, FIFO) rather than a CAN interface name.
bool is_log_path(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) return !S_ISDIR(st.st_mode);
  return path.find('/') != std::string::npos;  // a missing file, named as such
}

[[noreturn]] void not_candump(const std::string& source, std::size_t line_no, const std::string& line) {
  throw std::runtime_error(source + ": line " + std::to_string(line_no) + " is not a candump -L line ('" +
                           line.substr(0, 60) + "'); gvs monitor reads lines like '(1700000000.000000) can0 "
                           "301#0011223344556677': record one with 'candump -L can0 > run.log' or "
                           "'gvsd --can candump:run.log' (or pipe 'gvsd --can candump:-')");
}

/// A candump -L log from a file or a pipe, read without blocking so the view
/// refreshes while frames arrive and shows when they stop. A pipe ends at
/// end of input; a regular file with --follow is waited on like tail -f.
void monitor_stream(const MonitorCliOptions& o) {
  const bool from_stdin = o.target == "-";
  const std::string source = from_stdin ? "standard input" : o.target;
  const int fd = from_stdin ? STDIN_FILENO : ::open(o.target.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("cannot read candump log '" + o.target + "': " + std::strerror(errno));
  struct stat st {};
  const bool regular = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
  const bool wait_at_end = regular && o.follow;  // a growing log file
  const bool live = !regular || o.follow;        // refresh while reading

  can::MonitorState mon(can::MessageIds{o.base_id}, daemon::method_word_of_code);
  std::string pending;
  std::size_t line_no = 0;
  bool seen_frame = false;
  // Log timestamps may come from another clock (or another day): "now" for
  // the view is the last frame's log time plus the wall time since it came.
  std::int64_t last_arrival_ns = 0;
  const auto view_now = [&] {
    return seen_frame ? mon.last_t_ns() + (realtime_ns() - last_arrival_ns) : 0;
  };
  const auto take_line = [&](const std::string& line) {
    ++line_no;
    if (line.empty() || line[0] == '#') return;
    const auto parsed = can::parse_candump_line(line);
    if (!parsed) {
      if (!seen_frame) not_candump(source, line_no, line);  // wrong input, not a damaged line
      mon.note_malformed_line();
      return;
    }
    seen_frame = true;
    last_arrival_ns = realtime_ns();
    mon.feed(parsed->frame, parsed->t_ns);
  };

  const std::int64_t start = realtime_ns();
  std::int64_t next_refresh = start;
  char buf[65536];
  bool at_end = false;
  while (!g_stop) {
    pollfd p{fd, POLLIN, 0};
    const bool ready = regular ? !at_end : ::poll(&p, 1, 50) > 0;
    if (ready) {
      const ssize_t n = ::read(fd, buf, sizeof buf);
      if (n < 0 && errno != EINTR && errno != EAGAIN) {
        throw std::runtime_error("reading " + source + ": " + std::strerror(errno));
      }
      at_end = n == 0;
      if (n > 0) pending.append(buf, static_cast<std::size_t>(n));
      for (std::size_t nl; (nl = pending.find('\n')) != std::string::npos;) {
        take_line(pending.substr(0, nl));
        pending.erase(0, nl + 1);
      }
    } else if (regular) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));  // following: the file may grow
      at_end = false;
    }
    if (at_end && !wait_at_end) break;
    const std::int64_t now = realtime_ns();
    if (live && now >= next_refresh) {
      show(mon, view_now(), o, source + (o.follow ? " (following)" : ""));
      next_refresh = now + std::int64_t{o.refresh_ms} * 1'000'000;
    }
    if (o.max_seconds > 0 && static_cast<double>(now - start) / 1e9 >= o.max_seconds) break;
  }
  if (!pending.empty()) take_line(pending);  // a last line without '\n'
  if (!from_stdin) ::close(fd);
  // Summary: a finished log is seen from its last frame; a live one from now.
  MonitorCliOptions plain = o;
  plain.plain = true;
  show(mon, live ? view_now() : mon.last_t_ns(), plain, source + " (summary)");
}

void monitor_bus(const MonitorCliOptions& o) {
  if (o.target.size() >= IFNAMSIZ) throw std::invalid_argument("'" + o.target + "' is neither a file nor a CAN interface name");
  const int fd = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
  if (fd < 0) {
    throw std::runtime_error("cannot open a CAN socket for '" + o.target + "': " + std::strerror(errno) +
                             "; is SocketCAN available (modprobe can-raw)? For a log file, check the path");
  }
  const can_err_mask_t all_errors = CAN_ERR_MASK;
  ::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &all_errors, sizeof all_errors);
  ifreq ifr{};
  std::memcpy(ifr.ifr_name, o.target.data(), o.target.size());
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  if (::ioctl(fd, SIOCGIFINDEX, &ifr) != 0 ||
      (addr.can_ifindex = ifr.ifr_ifindex,
       ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0)) {
    const int err = errno;
    ::close(fd);
    throw std::runtime_error("cannot listen on CAN interface '" + o.target + "': " + std::strerror(err) +
                             "; check the name (ip link show) or give a candump log file");
  }
  can::MonitorState mon(can::MessageIds{o.base_id}, daemon::method_word_of_code);
  const std::int64_t start = realtime_ns();
  std::int64_t next_refresh = 0;
  while (!g_stop) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 50) > 0) {
      can_frame cf{};
      while (::recv(fd, &cf, sizeof cf, MSG_DONTWAIT) == static_cast<ssize_t>(sizeof cf)) {
        can::CanFrame f;
        f.error = (cf.can_id & CAN_ERR_FLAG) != 0;
        f.extended = !f.error && (cf.can_id & CAN_EFF_FLAG) != 0;
        f.remote = !f.error && (cf.can_id & CAN_RTR_FLAG) != 0;
        f.id = cf.can_id & (f.error ? CAN_ERR_MASK : f.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
        f.len = cf.len > 8 ? 8 : cf.len;
        std::memcpy(f.data.data(), cf.data, 8);
        mon.feed(f, realtime_ns());
      }
    }
    const std::int64_t now = realtime_ns();
    if (now >= next_refresh) {
      show(mon, now, o, o.target);
      next_refresh = now + std::int64_t{o.refresh_ms} * 1'000'000;
    }
    if (o.max_seconds > 0 && static_cast<double>(now - start) / 1e9 >= o.max_seconds) break;
  }
  ::close(fd);
  MonitorCliOptions plain = o;
  plain.plain = true;
  show(mon, realtime_ns(), plain, o.target + " (summary)");
}

void run_monitor(MonitorCliOptions o) {
  can::validate_base_id(o.base_id);
  // Screen-clearing escapes only for a person at a terminal, never into a pipe or a file.
  if (::isatty(STDOUT_FILENO) == 0) o.plain = true;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  if (o.target == "-" || is_log_path(o.target)) {
    monitor_stream(o);
  } else {
    if (o.follow) throw std::invalid_argument("--follow is for log files; '" + o.target + "' is not a file");
    monitor_bus(o);
  }
}

}  // namespace

void register_monitor(CLI::App& app) {
  auto opts = std::make_shared<MonitorCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "monitor", "Live view of decoded gvs CAN traffic from an interface (can0) or a candump -L log file");
  cmd->add_option("target", opts->target, "CAN interface (e.g. vcan0) or candump -L log file ('-' = stdin)")
      ->required();
  cmd->add_option("--base-id", opts->base_id, "Base CAN ID of the gvs messages (default 0x300)");
  cmd->add_flag("--follow", opts->follow, "Keep reading a growing log file (like tail -f); a pipe ends at end of input");
  cmd->add_option("--refresh-ms", opts->refresh_ms, "Screen refresh period")->check(whole_number_in(20, 10000));
  cmd->add_option("--seconds", opts->max_seconds, "Stop after this many seconds (interface, pipe or --follow)")
      ->check(positive_number());
  cmd->add_flag("--plain", opts->plain, "Do not clear the screen between refreshes (always so when output is not a terminal)");
  cmd->callback([opts] { run_monitor(*opts); });
}

}  // namespace gvs::cli
