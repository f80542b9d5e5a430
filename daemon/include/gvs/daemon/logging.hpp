// gvsd's log: spdlog to stderr (stdout may carry candump lines). On a desk
// with colours and times; under systemd (JOURNAL_STREAM names our stderr, or
// INVOCATION_ID is set) plain lines with `<N>` syslog level prefixes, which
// journald turns into priorities. Only the main thread logs.
#pragma once

#include <exception>
#include <memory>
#include <string>

#include <spdlog/logger.h>

namespace gvs::daemon {

/// True when stderr goes to the journal or we run as a systemd unit.
bool running_under_systemd();

/// Creates the "gvsd" logger and makes it the default; `level` is one of
/// log_level_names(). `journal` picks the systemd format.
std::shared_ptr<spdlog::logger> setup_logging(const std::string& level, bool journal);

/// Turns OpenCV's own log lines ("[ WARN:0@0.1] global loadsave.cpp ...")
/// off: gvs and gvsd report every failure they act on in their own words.
/// setup_logging() calls it; the gvs tool calls it at start.
void silence_library_logs();

/// One line for a caught exception: OpenCV's cv::Exception as "OpenCV: what
/// failed (in function)" without its source path and version banner,
/// anything else as what().
std::string describe_exception(const std::exception& e);

/// Syslog priority (0 emerg .. 7 debug) of an spdlog level.
int syslog_priority(spdlog::level::level_enum level);

}  // namespace gvs::daemon
