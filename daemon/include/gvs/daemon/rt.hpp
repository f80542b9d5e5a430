// Real-time setup: SCHED_FIFO priority and CPU affinity per thread, locked
// memory, prefaulted stacks. Every call reports instead of throwing, so the
// same binary runs on a desk without the privilege.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "gvs/daemon/config.hpp"

namespace gvs::daemon {

/// What happened when a thread asked for its scheduling.
struct ThreadRtReport {
  bool applied = false;   ///< the thread ran its setup
  bool fifo = false;      ///< runs SCHED_FIFO at the requested priority
  int sched_errno = 0;    ///< why not (0 = not requested or ok)
  bool pinned = false;    ///< runs on the requested CPU
  int affinity_errno = 0;
};

/// Called by a thread on itself: priority (0 = leave normal scheduling), CPU
/// (-1 = any), then prefaults `prefault_stack_kb` of its stack.
ThreadRtReport setup_this_thread(const ThreadConfig& config, int prefault_stack_kb) noexcept;

/// Touches `bytes` of stack below the caller so later page faults cannot occur there.
void prefault_stack(std::size_t bytes) noexcept;

/// mlockall(MCL_CURRENT | MCL_FUTURE), with MCL_ONFAULT when `on_fault`
/// (pages are locked as they are first touched, so mapped code and buffers
/// never touched take no RAM); returns 0 or errno. With `on_fault`, gvsd's
/// own code and static data (about 1.6 MB) are still made resident whole:
/// a path first run under load (a late wake-up, a skipped frame) would
/// otherwise fault on a real-time thread.
int lock_all_memory(bool on_fault) noexcept;

/// Page faults (minor + major) of the calling thread so far
/// (getrusage(RUSAGE_THREAD)); 0 if the kernel refuses.
std::uint64_t thread_page_faults() noexcept;

/// Process-wide, before gvsd starts a thread (with memory locked whole,
/// lock_on_fault = false, address space reserved is memory held; locked as
/// touched, pages touched once stay held):
///  - one malloc arena for all threads: glibc gives each new thread that
///    allocates an arena of its own, reserving 64 MiB of address space each;
///    gvsd's threads do not allocate in their loops, so they need no arena
///    of their own;
///  - a fixed mmap threshold (256 KiB): a large buffer freed at start-up
///    (the simulator's texture before its tile) goes back to the kernel
///    instead of staying in the heap, resident and locked;
///  - threads started from here on (gvsd's, libcamera's) get `stack_kb`
///    stacks, not glibc's default of RLIMIT_STACK (8 MiB), which mlockall
///    would make resident whole.
/// Returns 0 or the errno of the stack default (the arena limit cannot fail).
int set_thread_memory_defaults(int stack_kb) noexcept;

/// "SCHED_FIFO 80 on CPU 1" / "normal scheduling (EPERM: ...)".
std::string describe(const ThreadRtReport& report, const ThreadConfig& wanted);

}  // namespace gvs::daemon
