// A counting wake-up signal between two threads (a POSIX semaphore): the
// producer posts without blocking or allocating (sem_post is async-signal-
// safe), the consumer waits with a timeout so it can notice a stop request.
#pragma once

#include <semaphore.h>

#include <cerrno>
#include <cstdint>
#include <ctime>
#include <stdexcept>

namespace gvs::drivers {

class Wakeup {
 public:
  Wakeup() {
    if (sem_init(&sem_, 0, 0) != 0) throw std::runtime_error("Wakeup: sem_init failed");
  }
  ~Wakeup() { sem_destroy(&sem_); }
  Wakeup(const Wakeup&) = delete;
  Wakeup& operator=(const Wakeup&) = delete;

  void post() noexcept { sem_post(&sem_); }

  /// Waits until posted or `timeout_ns` passed; true when posted.
  bool wait_for(std::int64_t timeout_ns) noexcept {
    timespec deadline{};
    clock_gettime(CLOCK_MONOTONIC, &deadline);
    constexpr std::int64_t kNsPerSecond = 1'000'000'000;
    std::int64_t ns = deadline.tv_nsec + timeout_ns;
    deadline.tv_sec += static_cast<time_t>(ns / kNsPerSecond);
    deadline.tv_nsec = static_cast<long>(ns % kNsPerSecond);
    for (;;) {
      if (sem_clockwait(&sem_, CLOCK_MONOTONIC, &deadline) == 0) return true;
      if (errno != EINTR) return false;
    }
  }

 private:
  sem_t sem_{};
};

}  // namespace gvs::drivers
