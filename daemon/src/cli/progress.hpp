// A one-line progress report on standard error (frames done, rate, time
// left) for long gvs commands; silent when standard error is not a terminal,
// so logs, pipes and tests get only the results.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace gvs::cli {

class Progress {
 public:
  /// `what` names the work ("sim", "replay"); `total` is the expected count.
  Progress(std::string what, std::size_t total);
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  /// Clears the line, so the command's own output starts on a clean one.
  ~Progress();

  /// `done` items are finished; redraws at most every 200 ms.
  void update(std::size_t done);

 private:
  void draw(std::size_t done);

  std::string what_;
  std::size_t total_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point next_draw_;
};

}  // namespace gvs::cli
