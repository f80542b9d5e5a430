#include "gvs/can/socketcan_sink.hpp"

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <stdexcept>

namespace gvs::can {

namespace {

std::int64_t monotonic_ns() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

bool is_down_errno(int err) noexcept { return err == ENETDOWN || err == ENODEV || err == ENXIO; }

can_frame to_linux(const CanFrame& f) noexcept {
  can_frame cf{};
  cf.can_id = f.extended ? ((f.id & CAN_EFF_MASK) | CAN_EFF_FLAG) : (f.id & CAN_SFF_MASK);
  if (f.remote) cf.can_id |= CAN_RTR_FLAG;
  cf.len = f.len > 8 ? 8 : f.len;
  std::memcpy(cf.data, f.data.data(), 8);
  return cf;
}

CanFrame from_linux(const can_frame& cf) noexcept {
  CanFrame f;
  f.error = (cf.can_id & CAN_ERR_FLAG) != 0;
  f.extended = !f.error && (cf.can_id & CAN_EFF_FLAG) != 0;
  f.remote = !f.error && (cf.can_id & CAN_RTR_FLAG) != 0;
  f.id = f.error ? (cf.can_id & CAN_ERR_MASK) : f.extended ? (cf.can_id & CAN_EFF_MASK) : (cf.can_id & CAN_SFF_MASK);
  f.len = cf.len > 8 ? 8 : cf.len;
  std::memcpy(f.data.data(), cf.data, 8);
  return f;
}

}  // namespace

std::uint32_t subscribed_error_classes() noexcept {
  return CAN_ERR_TX_TIMEOUT | CAN_ERR_CRTL | CAN_ERR_BUSOFF | CAN_ERR_RESTARTED;
}

SocketCanSink::SocketCanSink(std::string iface, std::int64_t reopen_interval_ms)
    : iface_(std::move(iface)),
      description_("socketcan:" + iface_),
      reopen_interval_ns_(reopen_interval_ms * 1'000'000) {
  if (iface_.empty() || iface_.size() >= IFNAMSIZ) {
    throw std::invalid_argument("CAN interface name '" + iface_ + "' must be 1.." + std::to_string(IFNAMSIZ - 1) +
                                " characters, e.g. can0 or vcan0");
  }
  if (reopen_interval_ms <= 0) {
    throw std::invalid_argument("CAN reopen interval must be > 0 ms (got " + std::to_string(reopen_interval_ms) + ")");
  }
  const char* why = "";
  const int err = try_open(&why);
  if (err == 0) return;
  if (err == ENETDOWN) {  // exists but down: run and wait for it
    go_down(err);
    return;
  }
  std::string hint;
  if (err == EAFNOSUPPORT || err == EPROTONOSUPPORT) {
    hint = "the kernel has no SocketCAN support: load the can and can-raw modules (modprobe can-raw)";
  } else if (err == ENODEV) {
    hint = "no such interface: check the name, plug in the adapter, or create a virtual bus with "
           "`ip link add dev " + iface_ + " type vcan && ip link set up " + iface_ + "`";
  } else {
    hint = "check that the interface is a CAN interface and that gvsd may use it";
  }
  throw std::runtime_error("cannot open CAN interface '" + iface_ + "' (" + why + "): " + std::strerror(err) + "; " +
                           hint);
}

SocketCanSink::~SocketCanSink() { close_socket(); }

void SocketCanSink::close_socket() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

int SocketCanSink::try_open(const char** why) noexcept {
  close_socket();
  const int fd = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (fd < 0) {
    *why = "socket(PF_CAN, SOCK_RAW, CAN_RAW)";
    return errno;
  }
  auto fail = [&](const char* step) {
    const int e = errno;
    *why = step;
    ::close(fd);
    return e;
  };
  // Receive no data frames (we only send), only the error frames we subscribe to.
  if (::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, nullptr, 0) != 0) return fail("CAN_RAW_FILTER");
  const can_err_mask_t err_mask = subscribed_error_classes();
  if (::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &err_mask, sizeof err_mask) != 0) {
    return fail("CAN_RAW_ERR_FILTER");
  }
  ifreq ifr{};
  std::memcpy(ifr.ifr_name, iface_.data(), iface_.size());
  if (::ioctl(fd, SIOCGIFINDEX, &ifr) != 0) return fail("SIOCGIFINDEX");
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifr.ifr_ifindex;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) return fail("bind");
  if (::ioctl(fd, SIOCGIFFLAGS, &ifr) != 0) return fail("SIOCGIFFLAGS");
  if ((ifr.ifr_flags & IFF_UP) == 0) {
    ::close(fd);
    *why = "interface is down";
    return ENETDOWN;
  }
  fd_ = fd;
  return 0;
}

void SocketCanSink::go_down(int err) noexcept {
  close_socket();
  const std::int64_t now = monotonic_ns();
  health_.on_interface_down(err, now);
  next_reopen_ns_ = now + reopen_interval_ns_;
}

SendResult SocketCanSink::send(const CanFrame& frame) noexcept {
  if (fd_ < 0) {
    health_.on_send(SendResult::InterfaceDown, ENETDOWN, 0);
    return SendResult::InterfaceDown;
  }
  const can_frame cf = to_linux(frame);
  const ssize_t n = ::write(fd_, &cf, sizeof cf);
  SendResult r = SendResult::Ok;
  int err = 0;
  if (n != static_cast<ssize_t>(sizeof cf)) {
    err = n < 0 ? errno : EIO;
    if (err == EAGAIN || err == EWOULDBLOCK) {
      r = SendResult::WouldBlock;
    } else if (err == ENOBUFS) {
      r = SendResult::NoBuffers;
    } else if (is_down_errno(err)) {
      r = SendResult::InterfaceDown;
      go_down(err);
    } else {
      r = SendResult::Error;
    }
  }
  health_.on_send(r, err, r == SendResult::Ok ? 0 : monotonic_ns());
  return r;
}

void SocketCanSink::inject_error_frame(const CanFrame& frame) noexcept {
  health_.on_error_frame(frame, monotonic_ns());
}

std::size_t SocketCanSink::poll_events(std::span<SinkEvent> out) noexcept {
  const std::int64_t now = monotonic_ns();
  if (fd_ >= 0) {
    // Drain pending error frames (bounded, non-blocking).
    for (int k = 0; k < 64; ++k) {
      can_frame cf{};
      const ssize_t n = ::recv(fd_, &cf, sizeof cf, MSG_DONTWAIT);
      if (n < 0) {
        if (is_down_errno(errno)) go_down(errno);
        break;
      }
      if (n == static_cast<ssize_t>(sizeof cf) && (cf.can_id & CAN_ERR_FLAG) != 0) {
        health_.on_error_frame(from_linux(cf), now);
      }
    }
    // The interface may be down without a pending socket error (taken down
    // while we were idle): ask it.
    if (fd_ >= 0) {
      ifreq ifr{};
      std::memcpy(ifr.ifr_name, iface_.data(), iface_.size());
      if (::ioctl(fd_, SIOCGIFFLAGS, &ifr) != 0) {
        go_down(errno);
      } else if ((ifr.ifr_flags & IFF_UP) == 0) {
        go_down(ENETDOWN);
      }
    }
  } else if (now >= next_reopen_ns_) {
    ++health_.counters.reopen_attempts;
    const char* why = "";
    if (try_open(&why) == 0) {
      ++health_.counters.reopens;
      health_.on_interface_up(now);
    } else {
      next_reopen_ns_ = now + reopen_interval_ns_;
    }
  }
  return health_.events.drain(out);
}

}  // namespace gvs::can
