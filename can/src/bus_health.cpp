#include "gvs/can/bus_health.hpp"

#include <linux/can.h>
#include <linux/can/error.h>

#include <cerrno>

#include "gvs/can/codec.hpp"

namespace gvs::can {

ErrorFrameInfo decode_error_frame(const CanFrame& frame) noexcept {
  ErrorFrameInfo info;
  info.class_bits = frame.id & CAN_ERR_MASK;
  const std::uint8_t len = frame.len > 8 ? 8 : frame.len;
  if ((info.class_bits & CAN_ERR_CRTL) != 0 && len > 1) {
    info.controller = frame.data[1];
    const std::uint8_t c = info.controller;
    info.error_passive = (c & (CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE)) != 0;
    info.error_warning = (c & (CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_TX_WARNING)) != 0;
    info.overflow = (c & (CAN_ERR_CRTL_RX_OVERFLOW | CAN_ERR_CRTL_TX_OVERFLOW)) != 0;
    info.error_active = (c & CAN_ERR_CRTL_ACTIVE) != 0;
  }
  info.tx_timeout = (info.class_bits & CAN_ERR_TX_TIMEOUT) != 0;
  info.bus_off = (info.class_bits & CAN_ERR_BUSOFF) != 0;
  info.restarted = (info.class_bits & CAN_ERR_RESTARTED) != 0;
  if ((info.class_bits & CAN_ERR_CNT) != 0 && len > 7) {
    info.tx_error_count = frame.data[6];
    info.rx_error_count = frame.data[7];
  }
  return info;
}

void EventQueue::push(SinkEventKind kind, std::uint32_t detail, std::int64_t t_ns) noexcept {
  if (count_ == kCapacity) {
    ++lost_;
    return;
  }
  items_[(head_ + count_) % kCapacity] = SinkEvent{kind, detail, t_ns};
  ++count_;
}

std::size_t EventQueue::drain(std::span<SinkEvent> out) noexcept {
  std::size_t n = 0;
  if (lost_ != 0 && n < out.size()) {
    out[n++] = SinkEvent{SinkEventKind::EventsLost, lost_, 0};
    lost_ = 0;
  }
  while (count_ > 0 && n < out.size()) {
    out[n++] = items_[head_];
    head_ = (head_ + 1) % kCapacity;
    --count_;
  }
  return n;
}

void BusHealth::on_error_frame(const CanFrame& frame, std::int64_t t_ns) noexcept {
  const ErrorFrameInfo e = decode_error_frame(frame);
  ++counters.error_frames;
  bool mapped = false;
  if (e.bus_off) {
    bus_off_ = true;
    ++counters.bus_off;
    latched_ |= kFaultCanBusOff;
    events.push(SinkEventKind::BusOff, e.class_bits, t_ns);
    mapped = true;
  }
  if (e.restarted) {
    bus_off_ = false;
    error_passive_ = false;
    events.push(SinkEventKind::Restarted, e.class_bits, t_ns);
    mapped = true;
  }
  if (e.error_passive) {
    if (!error_passive_) events.push(SinkEventKind::ErrorPassive, e.controller, t_ns);
    error_passive_ = true;
    latched_ |= kFaultCanErrorPassive;
    mapped = true;
  }
  if (e.error_active) {
    error_passive_ = false;
    events.push(SinkEventKind::ErrorActive, e.controller, t_ns);
    mapped = true;
  }
  if (e.error_warning || e.overflow) {
    latched_ |= kFaultCanController;
    events.push(SinkEventKind::ControllerProblem, e.controller, t_ns);
    mapped = true;
  }
  if (e.tx_timeout) {
    latched_ |= kFaultCanController;
    events.push(SinkEventKind::TxTimeout, e.class_bits, t_ns);
    mapped = true;
  }
  if (!mapped) {
    if ((e.class_bits & CAN_ERR_CRTL) != 0) latched_ |= kFaultCanController;
    events.push(SinkEventKind::OtherErrorFrame, e.class_bits, t_ns);
  }
}

void BusHealth::on_interface_down(int err, std::int64_t t_ns) noexcept {
  if (!interface_down_) events.push(SinkEventKind::InterfaceDown, static_cast<std::uint32_t>(err), t_ns);
  interface_down_ = true;
  latched_ |= kFaultCanInterfaceDown;
}

void BusHealth::on_interface_up(std::int64_t t_ns) noexcept {
  if (interface_down_) events.push(SinkEventKind::InterfaceUp, 0, t_ns);
  interface_down_ = false;
  // A fresh socket on a reappeared interface: controller state is unknown
  // until the next error frame; do not keep reporting the old bus-off.
  bus_off_ = false;
  error_passive_ = false;
}

void BusHealth::on_send(SendResult result, int err, std::int64_t t_ns) noexcept {
  switch (result) {
    case SendResult::Ok:
      ++counters.frames_sent;
      in_send_failure_burst_ = false;
      return;
    case SendResult::WouldBlock: ++counters.would_block; break;
    case SendResult::NoBuffers: ++counters.no_buffers; break;
    case SendResult::InterfaceDown: ++counters.dropped_down; break;
    case SendResult::Error: ++counters.other_errors; break;
  }
  counters.last_errno = err;
  latched_ |= kFaultCanSendError;
  if (!in_send_failure_burst_ && result != SendResult::InterfaceDown) {
    events.push(SinkEventKind::SendFailed, static_cast<std::uint32_t>(err), t_ns);
  }
  in_send_failure_burst_ = true;
}

std::uint16_t BusHealth::take_fault_bits() noexcept {
  std::uint16_t bits = latched_;
  if (interface_down_) bits |= kFaultCanInterfaceDown;
  if (bus_off_) bits |= kFaultCanBusOff;
  if (error_passive_) bits |= kFaultCanErrorPassive;
  latched_ = 0;
  return bits;
}

std::string_view to_string(SendResult r) noexcept {
  switch (r) {
    case SendResult::Ok: return "ok";
    case SendResult::WouldBlock: return "would-block (EAGAIN)";
    case SendResult::NoBuffers: return "no-buffers (ENOBUFS)";
    case SendResult::InterfaceDown: return "interface-down";
    case SendResult::Error: return "error";
  }
  return "?";
}

std::string_view to_string(SinkEventKind k) noexcept {
  switch (k) {
    case SinkEventKind::InterfaceDown: return "interface down";
    case SinkEventKind::InterfaceUp: return "interface up again";
    case SinkEventKind::BusOff: return "bus-off";
    case SinkEventKind::ErrorPassive: return "error-passive";
    case SinkEventKind::ErrorActive: return "error-active again";
    case SinkEventKind::ControllerProblem: return "controller problem";
    case SinkEventKind::Restarted: return "controller restarted";
    case SinkEventKind::TxTimeout: return "TX timeout";
    case SinkEventKind::OtherErrorFrame: return "error frame";
    case SinkEventKind::SendFailed: return "send failed";
    case SinkEventKind::EventsLost: return "events lost";
  }
  return "?";
}

}  // namespace gvs::can
