#include "gvs/can/height_receiver.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <ctime>
#include <stdexcept>

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

namespace gvs::can {

bool HeightHistory::add(std::int64_t t_ns, double height_mm) noexcept {
  if (!std::isfinite(height_mm) || !(height_mm > 0.0)) return false;
  if (count_ > 0 && t_ns < nth_newest(0).t_ns) return false;
  samples_[next_] = {t_ns, height_mm};
  next_ = (next_ + 1) % kCapacity;
  if (count_ < kCapacity) ++count_;
  ++kept_;
  return true;
}

std::optional<double> HeightHistory::at(std::int64_t t_ns, std::int64_t max_gap_ns) const noexcept {
  if (count_ == 0) return std::nullopt;
  const Sample& newest = nth_newest(0);
  if (t_ns >= newest.t_ns) {
    if (t_ns - newest.t_ns <= max_gap_ns) return newest.height_mm;
    return std::nullopt;
  }
  for (std::size_t n = 1; n < count_; ++n) {
    const Sample& before = nth_newest(n);
    if (before.t_ns > t_ns) continue;
    const Sample& after = nth_newest(n - 1);
    if (after.t_ns - before.t_ns > max_gap_ns) return std::nullopt;
    if (after.t_ns == before.t_ns) return after.height_mm;
    // h(t) = h0 + (h1 - h0) (t - t0) / (t1 - t0)
    const double f = static_cast<double>(t_ns - before.t_ns) / static_cast<double>(after.t_ns - before.t_ns);
    return before.height_mm + (after.height_mm - before.height_mm) * f;
  }
  return std::nullopt;  // older than every sample kept
}

HeightReceiver::HeightReceiver(std::string iface, ForeignSignal signal)
    : iface_(std::move(iface)), signal_(signal) {
  validate(signal_);
  if (iface_.empty() || iface_.size() >= IFNAMSIZ) {
    throw std::invalid_argument("CAN interface name '" + iface_ + "' for the height must be 1.." +
                                std::to_string(IFNAMSIZ - 1) + " characters");
  }
  const auto fail = [this](const char* what) {
    const int err = errno;
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    throw std::runtime_error("cannot receive the height on CAN interface '" + iface_ + "' (" + what +
                             "): " + std::strerror(err) +
                             "; check that the interface exists and is up (ip link show " + iface_ + ")");
  };
  fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (fd_ < 0) fail("socket");
  can_filter filter{};
  filter.can_id = signal_.extended ? (signal_.can_id | CAN_EFF_FLAG) : signal_.can_id;
  filter.can_mask = CAN_EFF_FLAG | CAN_RTR_FLAG | (signal_.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
  if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, &filter, sizeof filter) != 0) fail("CAN_RAW_FILTER");
  const int on = 1;
  if (::setsockopt(fd_, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on) != 0) fail("SO_TIMESTAMPNS");
  ifreq ifr{};
  std::memcpy(ifr.ifr_name, iface_.data(), iface_.size());
  if (::ioctl(fd_, SIOCGIFINDEX, &ifr) != 0) fail("SIOCGIFINDEX");
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifr.ifr_ifindex;
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) fail("bind");
}

HeightReceiver::~HeightReceiver() {
  if (fd_ >= 0) ::close(fd_);
}

namespace {

std::int64_t ns_of(const timespec& ts) { return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec; }

}  // namespace

std::size_t HeightReceiver::drain(HeightHistory& history) noexcept {
  // The kernel stamps a frame on CLOCK_REALTIME (SO_TIMESTAMPNS); the
  // estimates live on CLOCK_MONOTONIC. Their offset, read now, moves it.
  timespec mono{};
  timespec real{};
  ::clock_gettime(CLOCK_MONOTONIC, &mono);
  ::clock_gettime(CLOCK_REALTIME, &real);
  const std::int64_t real_to_mono_ns = ns_of(mono) - ns_of(real);
  std::size_t added = 0;
  for (int guard = 0; guard < 1024; ++guard) {
    can_frame cf{};
    iovec iov{&cf, sizeof cf};
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timespec))];
    msghdr msg{};
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control;
    msg.msg_controllen = sizeof control;
    const ssize_t n = ::recvmsg(fd_, &msg, MSG_DONTWAIT);
    if (n < 0) {
      if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) ++read_errors_;
      break;
    }
    if (static_cast<std::size_t>(n) < sizeof cf) continue;
    std::int64_t t_ns = ns_of(mono);
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
      if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_TIMESTAMPNS) {
        timespec stamp{};
        std::memcpy(&stamp, CMSG_DATA(c), sizeof stamp);
        t_ns = ns_of(stamp) + real_to_mono_ns;
      }
    }
    CanFrame f;
    f.extended = (cf.can_id & CAN_EFF_FLAG) != 0;
    f.remote = (cf.can_id & CAN_RTR_FLAG) != 0;
    f.error = (cf.can_id & CAN_ERR_FLAG) != 0;
    f.id = cf.can_id & (f.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
    f.len = cf.len > 8 ? 8 : cf.len;
    std::memcpy(f.data.data(), cf.data, 8);
    ++frames_;
    const std::optional<double> mm = read_signal(f, signal_);
    if (!mm) continue;
    if (history.add(t_ns, *mm)) ++added;
  }
  return added;
}

}  // namespace gvs::can
