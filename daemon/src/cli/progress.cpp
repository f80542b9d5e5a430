#include "progress.hpp"

#include <unistd.h>

#include <cstdio>
#include <utility>

namespace gvs::cli {

namespace {
constexpr std::chrono::milliseconds kRedrawPeriod{200};
}  // namespace

Progress::Progress(std::string what, std::size_t total)
    : what_(std::move(what)),
      total_(total),
      enabled_(::isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()),
      next_draw_(start_) {}  // the first frame draws at once, then every kRedrawPeriod

Progress::~Progress() {
  if (drawn_) std::fputs("\r\033[K", stderr);
}

void Progress::update(std::size_t done) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now < next_draw_) return;
  next_draw_ = now + kRedrawPeriod;
  draw(done);
}

void Progress::draw(std::size_t done) {
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate_hz = elapsed_s > 0.0 ? static_cast<double>(done) / elapsed_s : 0.0;
  char left[32] = "?";
  if (rate_hz > 0.0 && total_ >= done) {
    const double left_s = static_cast<double>(total_ - done) / rate_hz;
    std::snprintf(left, sizeof left, "%.0f s", left_s);
  }
  const double pct = total_ > 0 ? 100.0 * static_cast<double>(done) / static_cast<double>(total_) : 0.0;
  std::fprintf(stderr, "\r\033[K%s: %zu/%zu frames (%.0f %%), %.1f frames/s, %s left", what_.c_str(), done, total_,
               pct, rate_hz, left);
  std::fflush(stderr);
  drawn_ = true;
}

}  // namespace gvs::cli
