// SocketCAN raw-socket sink: non-blocking sends, error frames subscribed
// (CAN_RAW_ERR_FILTER), and a lost interface reopened periodically.
#pragma once

#include <cstdint>
#include <string>

#include "gvs/can/bus_health.hpp"
#include "gvs/can/sink.hpp"

namespace gvs::can {

class SocketCanSink final : public CanSink {
 public:
  /// Opens and binds a raw CAN socket on `iface`. Throws std::runtime_error
  /// naming the interface and what to do when the kernel has no CAN support
  /// or the interface does not exist. An interface that exists but is down
  /// is not an error: the sink starts down (InterfaceDown event) and
  /// retries every `reopen_interval_ms`.
  SocketCanSink(std::string iface, std::int64_t reopen_interval_ms = 500);
  ~SocketCanSink() override;

  SendResult send(const CanFrame& frame) noexcept override;
  std::size_t poll_events(std::span<SinkEvent> out) noexcept override;
  std::uint16_t take_fault_bits() noexcept override { return health_.take_fault_bits(); }
  [[nodiscard]] const SinkCounters& counters() const noexcept override { return health_.counters; }
  [[nodiscard]] std::string_view description() const noexcept override { return description_; }

  [[nodiscard]] bool is_open() const noexcept { return fd_ >= 0; }
  /// Test hook: feed an error frame as if the socket had received it.
  void inject_error_frame(const CanFrame& frame) noexcept;

 private:
  /// Opens, configures and binds; returns 0 or an errno. `why` says which step failed.
  int try_open(const char** why) noexcept;
  void go_down(int err) noexcept;
  void close_socket() noexcept;

  std::string iface_;
  std::string description_;
  std::int64_t reopen_interval_ns_;
  std::int64_t next_reopen_ns_ = 0;
  int fd_ = -1;
  BusHealth health_;
};

/// The error-frame classes the sink subscribes to (CAN_RAW_ERR_FILTER):
/// TX timeout, controller problems, bus-off, restarted.
std::uint32_t subscribed_error_classes() noexcept;

}  // namespace gvs::can
