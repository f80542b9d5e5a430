#include "gvs/daemon/service_manager.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdlib>
#include <cstring>

namespace gvs::daemon {

namespace {

/// A decimal number filling all of `text`, or nothing.
bool parse_unsigned(const char* text, unsigned long long& out) {
  if (text == nullptr || *text < '0' || *text > '9') return false;
  char* end = nullptr;
  errno = 0;
  out = std::strtoull(text, &end, 10);
  return errno == 0 && end != nullptr && *end == '\0';
}

}  // namespace

bool notify_service_manager(std::string_view state) noexcept {
  const char* path = std::getenv("NOTIFY_SOCKET");
  if (path == nullptr || (path[0] != '/' && path[0] != '@')) return false;
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  const std::size_t length = std::strlen(path);
  if (length < 2 || length >= sizeof address.sun_path) return false;
  std::memcpy(address.sun_path, path, length);
  // '@': the abstract namespace, whose names start with a zero byte and have no terminator.
  if (address.sun_path[0] == '@') address.sun_path[0] = '\0';
  const auto address_size =
      static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + length + (path[0] == '/' ? 1 : 0));
  const int fd = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  const ssize_t sent = sendto(fd, state.data(), state.size(), MSG_NOSIGNAL,
                              reinterpret_cast<const sockaddr*>(&address), address_size);
  close(fd);
  return sent == static_cast<ssize_t>(state.size());
}

std::uint64_t service_watchdog_usec() noexcept {
  unsigned long long usec = 0;
  if (!parse_unsigned(std::getenv("WATCHDOG_USEC"), usec) || usec == 0) return 0;
  const char* pid_text = std::getenv("WATCHDOG_PID");
  if (pid_text != nullptr) {
    unsigned long long pid = 0;
    if (!parse_unsigned(pid_text, pid) || pid != static_cast<unsigned long long>(getpid())) return 0;
  }
  return usec;
}

}  // namespace gvs::daemon
