// gvsd's own sd_notify and sd_watchdog_enabled (service_manager.hpp): the
// datagrams a service manager receives, on a path and in the abstract
// namespace, and the watchdog variables. (gvsd_e2e_test.cpp drives the same
// code through the binary with a fake NOTIFY_SOCKET.)
#include "gvs/daemon/service_manager.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace {

using gvs::daemon::notify_service_manager;
using gvs::daemon::service_watchdog_usec;

/// A bound datagram socket standing in for systemd's notify socket.
class FakeNotifySocket {
 public:
  /// `name`: a path, or '@' + a name in the abstract namespace.
  explicit FakeNotifySocket(const std::string& name) : name_(name) {
    fd_ = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    std::memcpy(a.sun_path, name.data(), name.size());
    if (name[0] == '@') a.sun_path[0] = '\0';
    const auto size = static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + name.size());
    bound_ = bind(fd_, reinterpret_cast<const sockaddr*>(&a), size) == 0;
    timeval timeout{1, 0};
    setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  }
  ~FakeNotifySocket() {
    close(fd_);
    if (name_[0] == '/') std::filesystem::remove(name_);
  }
  FakeNotifySocket(const FakeNotifySocket&) = delete;
  FakeNotifySocket& operator=(const FakeNotifySocket&) = delete;

  [[nodiscard]] bool bound() const { return bound_; }
  std::string receive() {
    char buffer[512];
    const ssize_t n = recv(fd_, buffer, sizeof buffer, 0);
    return n < 0 ? std::string("(nothing)") : std::string(buffer, static_cast<std::size_t>(n));
  }

 private:
  std::string name_;
  int fd_ = -1;
  bool bound_ = false;
};

TEST(ServiceManager, NotifiesAPathSocket) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("gvs-notify-" + std::to_string(getpid()))).string();
  FakeNotifySocket manager(path);
  ASSERT_TRUE(manager.bound());
  setenv("NOTIFY_SOCKET", path.c_str(), 1);
  EXPECT_TRUE(notify_service_manager("READY=1\nSTATUS=starting"));
  EXPECT_EQ(manager.receive(), "READY=1\nSTATUS=starting");
  EXPECT_TRUE(notify_service_manager("WATCHDOG=1"));
  EXPECT_EQ(manager.receive(), "WATCHDOG=1");
  unsetenv("NOTIFY_SOCKET");
}

TEST(ServiceManager, NotifiesAnAbstractSocket) {
  const std::string name = "@gvs-notify-test-" + std::to_string(getpid());
  FakeNotifySocket manager(name);
  ASSERT_TRUE(manager.bound());
  setenv("NOTIFY_SOCKET", name.c_str(), 1);
  EXPECT_TRUE(notify_service_manager("STOPPING=1"));
  EXPECT_EQ(manager.receive(), "STOPPING=1");
  unsetenv("NOTIFY_SOCKET");
}

TEST(ServiceManager, WithoutAManagerNothingIsSent) {
  unsetenv("NOTIFY_SOCKET");
  EXPECT_FALSE(notify_service_manager("READY=1"));
  setenv("NOTIFY_SOCKET", "relative/path", 1);
  EXPECT_FALSE(notify_service_manager("READY=1"));
  setenv("NOTIFY_SOCKET", "/nonexistent-dir/notify", 1);
  EXPECT_FALSE(notify_service_manager("READY=1"));
  unsetenv("NOTIFY_SOCKET");
}

TEST(ServiceManager, WatchdogIntervalIsForThisProcessOnly) {
  unsetenv("WATCHDOG_USEC");
  unsetenv("WATCHDOG_PID");
  EXPECT_EQ(service_watchdog_usec(), 0U);
  setenv("WATCHDOG_USEC", "1000000", 1);
  EXPECT_EQ(service_watchdog_usec(), 1000000U);
  setenv("WATCHDOG_PID", std::to_string(getpid()).c_str(), 1);
  EXPECT_EQ(service_watchdog_usec(), 1000000U);
  setenv("WATCHDOG_PID", std::to_string(getpid() + 1).c_str(), 1);
  EXPECT_EQ(service_watchdog_usec(), 0U);
  unsetenv("WATCHDOG_PID");
  for (const char* bad : {"", "0", "-5", "12x", "x"}) {
    setenv("WATCHDOG_USEC", bad, 1);
    EXPECT_EQ(service_watchdog_usec(), 0U) << bad;
  }
  unsetenv("WATCHDOG_USEC");
}

}  // namespace
