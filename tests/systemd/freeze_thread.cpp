// gvs_freeze_thread PID THREAD_NAME SECONDS — stops ONE thread of a running
// process (the others run on), as a hung thread would be, for the watchdog
// test of the service (tests/systemd/service_in_qemu_guest.sh).
//
// The thread is found by its name (/proc/PID/task/*/comm, set by gvsd with
// pthread_setname_np), seized with PTRACE_SEIZE and stopped with
// PTRACE_INTERRUPT: only that task stops, unlike SIGSTOP, which stops the
// whole process. It stays stopped until SECONDS pass or the process is gone
// (systemd's watchdog kills it); leaving detaches it. Needs CAP_SYS_PTRACE.
#include <sys/ptrace.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

namespace {

pid_t find_thread(const std::string& pid, const std::string& name) {
  const std::filesystem::path tasks = "/proc/" + pid + "/task";
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(tasks, ec)) {
    std::ifstream comm(entry.path() / "comm");
    std::string comm_name;
    if (std::getline(comm, comm_name) && comm_name == name) {
      return static_cast<pid_t>(std::stol(entry.path().filename().string()));
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s PID THREAD_NAME SECONDS\n", argv[0]);
    return 2;
  }
  const std::string pid = argv[1];
  const std::string name = argv[2];
  const double seconds = std::stod(argv[3]);
  const pid_t tid = find_thread(pid, name);
  if (tid == 0) {
    std::fprintf(stderr, "freeze_thread: process %s has no thread named '%s' (see /proc/%s/task/*/comm)\n",
                 pid.c_str(), name.c_str(), pid.c_str());
    return 1;
  }
  if (ptrace(PTRACE_SEIZE, tid, nullptr, nullptr) != 0 || ptrace(PTRACE_INTERRUPT, tid, nullptr, nullptr) != 0) {
    std::fprintf(stderr, "freeze_thread: ptrace of thread %d: %s (needs CAP_SYS_PTRACE)\n", tid, std::strerror(errno));
    return 1;
  }
  int status = 0;
  if (waitpid(tid, &status, __WALL) != tid || !WIFSTOPPED(status)) {
    std::fprintf(stderr, "freeze_thread: thread %d did not stop\n", tid);
    return 1;
  }
  std::printf("freeze_thread: thread %d (%s) of process %s stopped\n", tid, name.c_str(), pid.c_str());
  std::fflush(stdout);
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < until && std::filesystem::exists("/proc/" + pid)) {
    // Reap the tracee's exit if the process was killed meanwhile.
    (void)waitpid(tid, &status, __WALL | WNOHANG);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return 0;  // exiting detaches the thread if it still exists
}
