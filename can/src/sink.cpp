#include "gvs/can/sink.hpp"

#include <stdexcept>

#include "gvs/can/candump.hpp"
#include "gvs/can/socketcan_sink.hpp"

namespace gvs::can {

namespace {

[[noreturn]] void bad_uri(std::string_view uri, std::string_view what) {
  throw std::invalid_argument("CAN sink '" + std::string(uri) + "': " + std::string(what) +
                              "; use socketcan:IFACE (e.g. socketcan:can0) or candump:PATH "
                              "(candump:- for stdout)");
}

}  // namespace

SinkUri parse_sink_uri(std::string_view uri) {
  const std::size_t colon = uri.find(':');
  if (colon == std::string_view::npos) bad_uri(uri, "no scheme");
  const std::string_view scheme = uri.substr(0, colon);
  const std::string_view target = uri.substr(colon + 1);
  if (target.empty()) bad_uri(uri, "empty target");
  SinkUri out;
  out.target = std::string(target);
  if (scheme == "socketcan") {
    out.kind = SinkUri::Kind::SocketCan;
    if (target.size() > 15) bad_uri(uri, "interface names have at most 15 characters");
    for (const char c : target) {
      if (c == '/' || c == ' ' || c == '\t' || c == ':' || static_cast<unsigned char>(c) < 0x20) {
        bad_uri(uri, "interface name contains '/', ':', a space or a control character");
      }
    }
  } else if (scheme == "candump") {
    out.kind = SinkUri::Kind::Candump;
  } else {
    bad_uri(uri, "unknown scheme '" + std::string(scheme) + "'");
  }
  return out;
}

std::unique_ptr<CanSink> open_sink(std::string_view uri, const SinkOptions& options) {
  const SinkUri u = parse_sink_uri(uri);
  if (u.kind == SinkUri::Kind::SocketCan) {
    return std::make_unique<SocketCanSink>(u.target, options.reopen_interval_ms);
  }
  return std::make_unique<CandumpSink>(u.target, options.candump_interface);
}

}  // namespace gvs::can
