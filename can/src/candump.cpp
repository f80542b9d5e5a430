#include "gvs/can/candump.hpp"

#include <linux/can.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <stdexcept>

namespace gvs::can {

namespace {

constexpr char kHex[] = "0123456789ABCDEF";

std::int64_t realtime_ns() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

std::int64_t monotonic_ns() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

/// Appends `value` as `digits` decimal digits (zero padded, at least `digits`).
std::size_t put_decimal(char* out, std::uint64_t value, int min_digits) noexcept {
  char tmp[24];
  int n = 0;
  do {
    tmp[n++] = static_cast<char>('0' + value % 10);
    value /= 10;
  } while (value != 0 && n < 24);
  while (n < min_digits && n < 24) tmp[n++] = '0';
  for (int i = 0; i < n; ++i) out[i] = tmp[n - 1 - i];
  return static_cast<std::size_t>(n);
}

int hex_value(char c) noexcept {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

bool is_space(char c) noexcept { return c == ' ' || c == '\t'; }

}  // namespace

std::size_t format_candump_line(const CanFrame& frame, std::int64_t t_ns, std::string_view iface, char* out,
                                std::size_t out_size) noexcept {
  char buf[kCandumpLineMax + 1];
  std::size_t n = 0;
  const std::uint64_t t = t_ns < 0 ? 0 : static_cast<std::uint64_t>(t_ns);
  buf[n++] = '(';
  n += put_decimal(buf + n, t / 1'000'000'000u, 10);
  buf[n++] = '.';
  n += put_decimal(buf + n, (t % 1'000'000'000u) / 1000u, 6);
  buf[n++] = ')';
  buf[n++] = ' ';
  const std::size_t iface_len = iface.size() > 15 ? 15 : iface.size();
  std::memcpy(buf + n, iface.data(), iface_len);
  n += iface_len;
  buf[n++] = ' ';

  std::uint32_t id = 0;
  int id_digits = 3;
  if (frame.error) {
    id = CAN_ERR_FLAG | (frame.id & CAN_ERR_MASK);
    id_digits = 8;
  } else if (frame.extended) {
    id = frame.id & CAN_EFF_MASK;
    id_digits = 8;
  } else {
    id = frame.id & CAN_SFF_MASK;
  }
  for (int i = id_digits - 1; i >= 0; --i) buf[n++] = kHex[(id >> (4 * i)) & 0xFu];
  buf[n++] = '#';
  const std::uint8_t len = frame.len > 8 ? 8 : frame.len;
  if (frame.remote) {
    buf[n++] = 'R';
    if (len > 0) buf[n++] = static_cast<char>('0' + len);
  } else {
    for (std::size_t i = 0; i < len; ++i) {
      buf[n++] = kHex[frame.data[i] >> 4];
      buf[n++] = kHex[frame.data[i] & 0xFu];
    }
  }
  buf[n++] = '\n';
  if (n + 1 > out_size) return 0;
  std::memcpy(out, buf, n);
  out[n] = '\0';
  return n;
}

std::optional<LoggedFrame> parse_candump_line(std::string_view line) noexcept {
  std::size_t i = 0;
  const std::size_t end = line.size();
  auto at = [&](std::size_t k) -> char { return k < end ? line[k] : '\0'; };

  LoggedFrame out;
  // (seconds.fraction)
  if (at(i) != '(') return std::nullopt;
  ++i;
  std::uint64_t sec = 0;
  std::size_t digits = 0;
  while (at(i) >= '0' && at(i) <= '9') {
    if (++digits > 12) return std::nullopt;
    sec = sec * 10 + static_cast<std::uint64_t>(at(i) - '0');
    ++i;
  }
  if (digits == 0 || at(i) != '.') return std::nullopt;
  ++i;
  std::uint64_t frac_ns = 0;
  std::uint64_t place = 100'000'000;
  digits = 0;
  while (at(i) >= '0' && at(i) <= '9') {
    if (++digits > 9) return std::nullopt;
    frac_ns += static_cast<std::uint64_t>(at(i) - '0') * place;
    place /= 10;
    ++i;
  }
  if (digits == 0 || at(i) != ')') return std::nullopt;
  ++i;
  out.t_ns = static_cast<std::int64_t>(sec * 1'000'000'000u + frac_ns);

  // interface
  if (!is_space(at(i))) return std::nullopt;
  while (is_space(at(i))) ++i;
  const std::size_t iface_start = i;
  while (i < end && !is_space(line[i])) ++i;
  const std::size_t iface_len = i - iface_start;
  if (iface_len == 0 || iface_len > 15) return std::nullopt;
  out.iface = line.substr(iface_start, iface_len);
  if (!is_space(at(i))) return std::nullopt;
  while (is_space(at(i))) ++i;

  // ID
  std::uint32_t id = 0;
  std::size_t id_digits = 0;
  while (hex_value(at(i)) >= 0) {
    if (++id_digits > 8) return std::nullopt;
    id = (id << 4) | static_cast<std::uint32_t>(hex_value(at(i)));
    ++i;
  }
  if (at(i) != '#') return std::nullopt;
  ++i;
  CanFrame& f = out.frame;
  if (id_digits == 3) {
    if (id > CAN_SFF_MASK) return std::nullopt;
    f.id = id;
  } else if (id_digits == 8) {
    if ((id & CAN_ERR_FLAG) != 0) {
      if ((id & ~(CAN_ERR_FLAG | CAN_ERR_MASK)) != 0) return std::nullopt;
      f.error = true;
      f.id = id & CAN_ERR_MASK;
    } else {
      if (id > CAN_EFF_MASK) return std::nullopt;
      f.extended = true;
      f.id = id;
    }
  } else {
    return std::nullopt;
  }

  // data
  if (at(i) == '#') return std::nullopt;  // CAN FD: not a classical frame
  if (at(i) == 'R' || at(i) == 'r') {
    f.remote = true;
    ++i;
    if (at(i) >= '0' && at(i) <= '8') {
      f.len = static_cast<std::uint8_t>(at(i) - '0');
      ++i;
    }
  } else {
    while (true) {
      if (at(i) == '.') ++i;  // optional byte separators
      const int hi = hex_value(at(i));
      if (hi < 0) break;
      const int lo = hex_value(at(i + 1));
      if (lo < 0 || f.len >= 8) return std::nullopt;
      f.data[f.len++] = static_cast<std::uint8_t>((hi << 4) | lo);
      i += 2;
    }
    if (at(i) == '_') {  // len8_dlc suffix: "_D" (DLC 9..F); the data is what counts
      if (hex_value(at(i + 1)) < 0) return std::nullopt;
      i += 2;
    }
  }
  // Only trailing whitespace (or a CR/LF) may follow.
  while (i < end) {
    const char c = line[i];
    if (!is_space(c) && c != '\r' && c != '\n') return std::nullopt;
    ++i;
  }
  return out;
}

CandumpSink::CandumpSink(const std::string& path, std::string iface, Clock clock)
    : iface_(std::move(iface)), description_("candump:" + path), clock_(clock) {
  if (iface_.empty() || iface_.size() > 15 || iface_.find_first_of(" \t/") != std::string::npos) {
    throw std::invalid_argument("candump interface name '" + iface_ +
                                "' must be 1..15 characters without spaces or '/', e.g. can0");
  }
  if (path == "-") {
    file_ = stdout;
  } else {
    file_ = std::fopen(path.c_str(), "w");
    if (file_ == nullptr) {
      throw std::runtime_error("cannot open candump log '" + path + "' for writing: " + std::strerror(errno) +
                               "; check that the directory exists and is writable, or use candump:- for stdout");
    }
    owns_file_ = true;
    // Full buffering in a buffer allocated now (setup), not by stdio on the first send.
    buffer_ = std::make_unique<char[]>(kBufferSize);
    std::setvbuf(file_, buffer_.get(), _IOFBF, kBufferSize);
  }
}

CandumpSink::~CandumpSink() {
  if (file_ == nullptr) return;
  std::fflush(file_);
  if (owns_file_) std::fclose(file_);
}

SendResult CandumpSink::send(const CanFrame& frame) noexcept {
  char line[kCandumpLineMax + 1];
  const std::int64_t t = clock_ != nullptr ? clock_() : realtime_ns();
  const std::size_t n = format_candump_line(frame, t, iface_, line, sizeof line);
  SendResult r = SendResult::Ok;
  int err = 0;
  if (n == 0 || std::fwrite(line, 1, n, file_) != n) {
    r = SendResult::Error;
    err = n == 0 ? EINVAL : errno;
  }
  health_.on_send(r, err, monotonic_ns());
  return r;
}

std::size_t CandumpSink::poll_events(std::span<SinkEvent> out) noexcept {
  if (std::fflush(file_) != 0) health_.on_send(SendResult::Error, errno, monotonic_ns());
  return health_.events.drain(out);
}

}  // namespace gvs::can
