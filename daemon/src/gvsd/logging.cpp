#include "gvs/daemon/logging.hpp"

#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>
#include <string_view>

#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include "gvs/drivers/camera_device.hpp"

namespace gvs::daemon {

namespace {

/// `%*` in the pattern: the syslog priority digit for journald's `<N>` prefix.
class SyslogPriorityFlag final : public spdlog::custom_flag_formatter {
 public:
  void format(const spdlog::details::log_msg& msg, const std::tm& /*tm*/, spdlog::memory_buf_t& dest) override {
    const char digit = static_cast<char>('0' + syslog_priority(msg.level));
    dest.push_back(digit);
  }
  [[nodiscard]] std::unique_ptr<custom_flag_formatter> clone() const override {
    return spdlog::details::make_unique<SyslogPriorityFlag>();
  }
};

/// JOURNAL_STREAM is "DEV:INODE" of the journal stream; it counts only when
/// our stderr is still that stream (not redirected by the caller).
bool stderr_is_journal_stream() {
  const char* env = std::getenv("JOURNAL_STREAM");
  if (env == nullptr || *env == '\0') return false;
  unsigned long long dev = 0;
  unsigned long long ino = 0;
  if (std::sscanf(env, "%llu:%llu", &dev, &ino) != 2) return false;
  struct stat st {};
  if (fstat(2, &st) != 0) return false;
  return static_cast<unsigned long long>(st.st_dev) == dev && static_cast<unsigned long long>(st.st_ino) == ino;
}

}  // namespace

int syslog_priority(spdlog::level::level_enum level) {
  switch (level) {
    case spdlog::level::critical: return 2;
    case spdlog::level::err: return 3;
    case spdlog::level::warn: return 4;
    case spdlog::level::info: return 6;
    default: return 7;
  }
}

bool running_under_systemd() {
  const char* invocation = std::getenv("INVOCATION_ID");
  return stderr_is_journal_stream() || (invocation != nullptr && *invocation != '\0');
}

std::shared_ptr<spdlog::logger> setup_logging(const std::string& level, bool journal) {
  std::shared_ptr<spdlog::logger> logger;
  if (journal) {
    auto sink = std::make_shared<spdlog::sinks::stderr_sink_mt>();
    auto formatter = std::make_unique<spdlog::pattern_formatter>();
    formatter->add_flag<SyslogPriorityFlag>('*').set_pattern("<%*>%v");
    sink->set_formatter(std::move(formatter));
    logger = std::make_shared<spdlog::logger>("gvsd", sink);
  } else {
    auto sink = std::make_shared<spdlog::sinks::stderr_color_sink_mt>();
    sink->set_pattern("%H:%M:%S.%e gvsd %^%l%$: %v");
    logger = std::make_shared<spdlog::logger>("gvsd", sink);
  }
  logger->set_level(spdlog::level::from_str(level));
  logger->flush_on(spdlog::level::trace);
  spdlog::set_default_logger(logger);
  silence_library_logs();
  // libcamera's own lines into this log at their level, without colours.
  drivers::route_camera_library_log([](std::string_view camera_level, std::string_view message) {
    auto at = spdlog::level::info;
    if (camera_level == "DEBUG") at = spdlog::level::debug;
    if (camera_level == "WARN") at = spdlog::level::warn;
    if (camera_level == "ERROR") at = spdlog::level::err;
    if (camera_level == "FATAL") at = spdlog::level::critical;
    spdlog::log(at, "libcamera: {}", message);
  });
  return logger;
}

void silence_library_logs() { cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT); }

std::string describe_exception(const std::exception& e) {
  if (const auto* cv_error = dynamic_cast<const cv::Exception*>(&e)) {
    std::string text = "OpenCV: " + cv_error->err;
    if (!cv_error->func.empty()) text += " (in " + cv_error->func + ")";
    for (char& c : text) {
      if (c == '\n') c = ' ';
    }
    return text;
  }
  return e.what();
}

}  // namespace gvs::daemon
