// Where the CAN sender puts its frames: a SocketCAN interface or a candump
// log. send() and poll_events() are on the real-time path: no allocation, no
// exceptions, no logging; problems come back as return codes, counters and
// events that the caller logs outside the send path.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "gvs/can/frame.hpp"

namespace gvs::can {

enum class SendResult : std::uint8_t {
  Ok,
  WouldBlock,     ///< EAGAIN: socket send buffer full; frame dropped, counted
  NoBuffers,      ///< ENOBUFS: interface queue full; frame dropped, counted
  InterfaceDown,  ///< interface down or removed; frame dropped, counted; the sink reopens it
  Error,          ///< any other failure (errno in SinkCounters::last_errno); frame dropped
};
std::string_view to_string(SendResult r) noexcept;

enum class SinkEventKind : std::uint8_t {
  InterfaceDown,       ///< sending failed with ENETDOWN/ENODEV/ENXIO; detail = errno
  InterfaceUp,         ///< reopened and bound again after InterfaceDown
  BusOff,              ///< error frame: controller went bus-off
  ErrorPassive,        ///< error frame: controller reached error-passive (detail = ctrl bits)
  ErrorActive,         ///< error frame: controller back to error-active
  ControllerProblem,   ///< error frame: RX/TX overflow or warning level (detail = ctrl bits)
  Restarted,           ///< error frame: controller restarted after bus-off
  TxTimeout,           ///< error frame: TX timeout by the driver
  OtherErrorFrame,     ///< error frame of a class we do not map (detail = class bits)
  SendFailed,          ///< first failure of a burst of failed sends (detail = errno)
  EventsLost,          ///< the event queue overflowed (detail = events dropped)
};
std::string_view to_string(SinkEventKind k) noexcept;

struct SinkEvent {
  SinkEventKind kind = SinkEventKind::OtherErrorFrame;
  std::uint32_t detail = 0;
  std::int64_t t_ns = 0;  ///< CLOCK_MONOTONIC when the sink noticed it
};

/// Running totals since the sink was opened.
struct SinkCounters {
  std::uint64_t frames_sent = 0;
  std::uint64_t would_block = 0;     ///< EAGAIN
  std::uint64_t no_buffers = 0;      ///< ENOBUFS
  std::uint64_t dropped_down = 0;    ///< frames not sent because the interface was down
  std::uint64_t other_errors = 0;
  std::uint64_t error_frames = 0;    ///< error frames received
  std::uint64_t bus_off = 0;
  std::uint64_t reopen_attempts = 0;
  std::uint64_t reopens = 0;         ///< successful reopen after the interface came back
  int last_errno = 0;

  [[nodiscard]] std::uint64_t send_failures() const {
    return would_block + no_buffers + dropped_down + other_errors;
  }
};

/// A place to send frames.
class CanSink {
 public:
  CanSink() = default;
  CanSink(const CanSink&) = delete;
  CanSink& operator=(const CanSink&) = delete;
  CanSink(CanSink&&) = delete;
  CanSink& operator=(CanSink&&) = delete;
  virtual ~CanSink() = default;

  /// Sends one frame without blocking. Never throws, never allocates.
  virtual SendResult send(const CanFrame& frame) noexcept = 0;

  /// Reads pending error frames, retries a lost interface when due, flushes
  /// logs; then moves queued events into `out` (oldest first) and returns how
  /// many. Call it once per send cycle. Never throws, never allocates.
  virtual std::size_t poll_events(std::span<SinkEvent> out) noexcept = 0;

  /// FaultBit mask (codec.hpp) for GVS_Status: conditions now, plus events
  /// latched since the previous call (which clears the latch).
  virtual std::uint16_t take_fault_bits() noexcept = 0;

  [[nodiscard]] virtual const SinkCounters& counters() const noexcept = 0;
  /// "socketcan:can0", "candump:/tmp/x.log", ... (for log lines).
  [[nodiscard]] virtual std::string_view description() const noexcept = 0;
};

/// A parsed sink URI: `socketcan:IFACE` or `candump:PATH` (`candump:-` = stdout).
struct SinkUri {
  enum class Kind : std::uint8_t { SocketCan, Candump };
  Kind kind = Kind::SocketCan;
  std::string target;  ///< interface name or file path ("-" = stdout)
};

/// Parses a sink URI. Throws std::invalid_argument naming the URI and the
/// accepted forms when it is malformed (unknown scheme, empty target,
/// interface name longer than 15 characters or containing '/' or spaces).
SinkUri parse_sink_uri(std::string_view uri);

struct SinkOptions {
  std::int64_t reopen_interval_ms = 500;    ///< SocketCAN: retry period while the interface is gone
  std::string candump_interface = "can0";   ///< candump: interface name written in each line
};

/// Opens the sink a URI names. Throws std::runtime_error naming the
/// interface or file and what to do when it cannot be opened.
std::unique_ptr<CanSink> open_sink(std::string_view uri, const SinkOptions& options = {});

}  // namespace gvs::can
