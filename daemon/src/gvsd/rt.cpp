#include "gvs/daemon/rt.hpp"

#include <link.h>
#include <malloc.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <sstream>

namespace gvs::daemon {

void prefault_stack(std::size_t bytes) noexcept {
  if (bytes == 0) return;
  // A variable-length region on this thread's stack, written once per page.
  auto* region = static_cast<volatile unsigned char*>(__builtin_alloca(bytes));
  constexpr std::size_t kPage = 4096;
  for (std::size_t i = 0; i < bytes; i += kPage) region[i] = 0;
}

ThreadRtReport setup_this_thread(const ThreadConfig& config, int prefault_stack_kb) noexcept {
  ThreadRtReport r;
  r.applied = true;
  if (config.priority > 0) {
    sched_param param{};
    param.sched_priority = config.priority;
    r.sched_errno = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
    r.fifo = r.sched_errno == 0;
  }
  if (config.cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(static_cast<std::size_t>(config.cpu), &set);
    r.affinity_errno = pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
    r.pinned = r.affinity_errno == 0;
  }
  prefault_stack(static_cast<std::size_t>(prefault_stack_kb) * 1024U);
  return r;
}

namespace {

/// dl_iterate_phdr visits the program itself first: mlock (without
/// MLOCK_ONFAULT) makes each of its loaded segments resident and locked now.
int lock_first_object(dl_phdr_info* info, std::size_t /*size*/, void* result) noexcept {
  const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  for (ElfW(Half) i = 0; i < info->dlpi_phnum; ++i) {
    const ElfW(Phdr)& ph = info->dlpi_phdr[i];
    if (ph.p_type != PT_LOAD) continue;
    const std::uintptr_t begin = (info->dlpi_addr + ph.p_vaddr) & ~(page - 1);
    const std::uintptr_t end = info->dlpi_addr + ph.p_vaddr + ph.p_memsz;
    if (mlock(reinterpret_cast<const void*>(begin), end - begin) != 0) *static_cast<int*>(result) = errno;
  }
  return 1;  // the program only, not the libraries
}

}  // namespace

int lock_all_memory(bool on_fault) noexcept {
  const int flags = MCL_CURRENT | MCL_FUTURE | (on_fault ? MCL_ONFAULT : 0);
  if (mlockall(flags) != 0) return errno;
  int program_errno = 0;
  if (on_fault) (void)dl_iterate_phdr(lock_first_object, &program_errno);
  return program_errno;
}

std::uint64_t thread_page_faults() noexcept {
  rusage usage{};
  if (getrusage(RUSAGE_THREAD, &usage) != 0) return 0;
  return static_cast<std::uint64_t>(usage.ru_minflt) + static_cast<std::uint64_t>(usage.ru_majflt);
}

int set_thread_memory_defaults(int stack_kb) noexcept {
  (void)mallopt(M_ARENA_MAX, 1);
  (void)mallopt(M_MMAP_THRESHOLD, 256 * 1024);
  pthread_attr_t attr;
  if (const int e = pthread_getattr_default_np(&attr); e != 0) return e;
  int e = pthread_attr_setstacksize(&attr, static_cast<std::size_t>(stack_kb) * 1024U);
  if (e == 0) e = pthread_setattr_default_np(&attr);
  pthread_attr_destroy(&attr);
  return e;
}

std::string describe(const ThreadRtReport& r, const ThreadConfig& wanted) {
  std::ostringstream s;
  if (wanted.priority == 0) {
    s << "normal scheduling (configured)";
  } else if (r.fifo) {
    s << "SCHED_FIFO " << wanted.priority;
  } else {
    s << "normal scheduling (SCHED_FIFO " << wanted.priority << " refused: " << std::strerror(r.sched_errno) << ')';
  }
  if (wanted.cpu >= 0) {
    if (r.pinned) {
      s << " on CPU " << wanted.cpu;
    } else {
      s << ", any CPU (CPU " << wanted.cpu << " refused: " << std::strerror(r.affinity_errno) << ')';
    }
  }
  return s.str();
}

}  // namespace gvs::daemon
