// The `candump -L` log format (can-utils): one frame a line,
//   (1699999999.123456) vcan0 123#0011223344556677
// seconds.microseconds, interface, ID (3 hex digits standard, 8 extended,
// error frames 8 digits with CAN_ERR_FLAG 0x20000000), '#', data in
// uppercase hex ("R" for a remote frame). Writing and robust reading.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "gvs/can/bus_health.hpp"
#include "gvs/can/frame.hpp"
#include "gvs/can/sink.hpp"

namespace gvs::can {

/// Longest line format_candump_line writes, without the terminating NUL.
inline constexpr std::size_t kCandumpLineMax = 96;

/// Writes one log line (with '\n') into `out`; returns its length, or 0 when
/// `out` is too small. `t_ns` is wall-clock time (CLOCK_REALTIME) in ns.
/// Interface names are cut to 15 characters (IFNAMSIZ - 1).
std::size_t format_candump_line(const CanFrame& frame, std::int64_t t_ns, std::string_view iface, char* out,
                                std::size_t out_size) noexcept;

struct LoggedFrame {
  std::int64_t t_ns = 0;
  std::string_view iface;  ///< points into the parsed line
  CanFrame frame;
};

/// Parses one line of a candump -L log. Returns nullopt for anything that is
/// not a classical CAN frame in that format (CAN FD lines, comments, junk).
/// Accepts arbitrary bytes: never throws, never reads outside `line`.
std::optional<LoggedFrame> parse_candump_line(std::string_view line) noexcept;

/// A CanSink that writes frames as candump -L lines to a file or stdout.
class CandumpSink final : public CanSink {
 public:
  using Clock = std::int64_t (*)();  ///< wall-clock ns; nullptr = CLOCK_REALTIME

  /// `path` "-" writes to stdout. Throws std::runtime_error naming the file
  /// and what to do when it cannot be opened for writing.
  CandumpSink(const std::string& path, std::string iface = "can0", Clock clock = nullptr);
  ~CandumpSink() override;

  SendResult send(const CanFrame& frame) noexcept override;
  std::size_t poll_events(std::span<SinkEvent> out) noexcept override;
  std::uint16_t take_fault_bits() noexcept override { return health_.take_fault_bits(); }
  [[nodiscard]] const SinkCounters& counters() const noexcept override { return health_.counters; }
  [[nodiscard]] std::string_view description() const noexcept override { return description_; }

 private:
  static constexpr std::size_t kBufferSize = 16384;
  std::unique_ptr<char[]> buffer_;
  std::FILE* file_ = nullptr;
  bool owns_file_ = false;
  std::string iface_;
  std::string description_;
  Clock clock_;
  BusHealth health_;
};

}  // namespace gvs::can
