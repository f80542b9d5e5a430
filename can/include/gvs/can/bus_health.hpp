// Turning Linux CAN error frames and send failures into fault bits, counters
// and events. Shared by the sinks; testable without a CAN interface (vcan
// cannot produce real error frames, so tests feed frames in directly).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "gvs/can/frame.hpp"
#include "gvs/can/sink.hpp"

namespace gvs::can {

/// What one error frame (linux/can/error.h) says. `frame.error` must be set
/// and `frame.id` hold the CAN_ERR_* class bits (without CAN_ERR_FLAG).
struct ErrorFrameInfo {
  std::uint32_t class_bits = 0;  ///< CAN_ERR_* class mask
  std::uint8_t controller = 0;   ///< data[1]: CAN_ERR_CRTL_* bits (when class has CAN_ERR_CRTL)
  bool tx_timeout = false;
  bool bus_off = false;
  bool restarted = false;
  bool error_passive = false;    ///< RX or TX passive
  bool error_warning = false;    ///< RX or TX warning level
  bool error_active = false;     ///< back to error-active
  bool overflow = false;         ///< RX or TX buffer overflow
  std::uint8_t tx_error_count = 0;  ///< data[6] when class has CAN_ERR_CNT
  std::uint8_t rx_error_count = 0;  ///< data[7] when class has CAN_ERR_CNT
};
ErrorFrameInfo decode_error_frame(const CanFrame& frame) noexcept;

/// Fixed-capacity FIFO of sink events (no allocation); overflow is counted
/// and reported as one EventsLost event.
class EventQueue {
 public:
  static constexpr std::size_t kCapacity = 64;
  void push(SinkEventKind kind, std::uint32_t detail, std::int64_t t_ns) noexcept;
  std::size_t drain(std::span<SinkEvent> out) noexcept;
  [[nodiscard]] std::size_t size() const noexcept { return count_; }

 private:
  std::array<SinkEvent, kCapacity> items_{};
  std::size_t head_ = 0;
  std::size_t count_ = 0;
  std::uint32_t lost_ = 0;
};

/// Bus and interface state of one sink: current conditions plus latches
/// that hold a transient problem until the next GVS_Status takes it.
class BusHealth {
 public:
  void on_error_frame(const CanFrame& frame, std::int64_t t_ns) noexcept;
  /// Interface went down or was removed (errno in `err`).
  void on_interface_down(int err, std::int64_t t_ns) noexcept;
  void on_interface_up(std::int64_t t_ns) noexcept;
  /// A send result, so failures latch kFaultCanSendError and the first of a
  /// burst becomes a SendFailed event.
  void on_send(SendResult result, int err, std::int64_t t_ns) noexcept;

  /// Current conditions OR'ed with the latches; clears the latches.
  std::uint16_t take_fault_bits() noexcept;

  [[nodiscard]] bool interface_down() const noexcept { return interface_down_; }
  [[nodiscard]] bool bus_off() const noexcept { return bus_off_; }
  [[nodiscard]] bool error_passive() const noexcept { return error_passive_; }

  SinkCounters counters;
  EventQueue events;

 private:
  bool interface_down_ = false;
  bool bus_off_ = false;
  bool error_passive_ = false;
  bool in_send_failure_burst_ = false;
  std::uint16_t latched_ = 0;
};

}  // namespace gvs::can
