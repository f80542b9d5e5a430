// Talking to systemd without libsystemd: the notification protocol of
// sd_notify(3) and the watchdog variables of sd_watchdog_enabled(3), both
// stable and documented for reimplementation (systemd.io, "Notify socket").
// libsystemd would bring 7 more shared libraries (libgcrypt, liblz4, ...)
// into gvsd for these two calls (docs/performance.md, "Footprint").
#pragma once

#include <cstdint>
#include <string_view>

namespace gvs::daemon {

/// Sends `state` ("READY=1", "STATUS=...", "WATCHDOG=1", newline-separated
/// assignments) as one datagram to the AF_UNIX socket named by
/// $NOTIFY_SOCKET (a path, or '@' for the abstract namespace). Returns false
/// when the variable is unset or unusable or the send failed: gvsd was not
/// started by systemd with Type=notify, and nothing is owed.
bool notify_service_manager(std::string_view state) noexcept;

/// The watchdog interval systemd asks for ($WATCHDOG_USEC) when it is meant
/// for this process ($WATCHDOG_PID unset or ours); 0 when there is none.
std::uint64_t service_watchdog_usec() noexcept;

}  // namespace gvs::daemon
