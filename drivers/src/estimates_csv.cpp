// The estimates CSV of a replay run (shared/spec/dataset-format.md).
#include "gvs/drivers/estimates_csv.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "csv_line.hpp"
#include "gvs/drivers/dataset.hpp"

namespace gvs::drivers {

namespace fs = std::filesystem;

namespace {
constexpr const char* kHeader = "index,t_ns,vx_mps,vy_mps,speed_mps,direction_deg,yaw_rate_dps,quality,method";

void append(std::string& s, bool present, double v, int decimals) {
  s += ',';
  if (!present) return;
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  s += buf;
}
}  // namespace

std::string format_estimate_row(const core::VelocityEstimate& e) {
  std::string s = std::to_string(e.index) + ',' + std::to_string(e.t_ns);
  const bool xy = e.has_velocity_xy();
  append(s, xy, e.has_direction ? e.vx_mps : 0.0, 5);
  append(s, xy, e.has_direction ? e.vy_mps : 0.0, 5);
  append(s, e.has_speed, e.speed_mps, 5);
  append(s, e.has_direction, e.direction_deg, 4);
  append(s, e.has_yaw_rate, e.yaw_rate_dps, 4);
  append(s, true, e.quality, 3);
  s += ',';
  s += core::method_word(e.method);
  return s;
}

EstimatesCsvWriter::EstimatesCsvWriter(const fs::path& file) : file_(file), out_(file, std::ios::trunc) {
  if (!out_) throw DatasetError(file.string() + ": cannot create the estimates file");
  out_ << kHeader << '\n';
}

void EstimatesCsvWriter::write(const core::VelocityEstimate& e) {
  out_ << format_estimate_row(e) << '\n';
  if (!out_) throw DatasetError(file_.string() + ": write failed (disk full?)");
}

void EstimatesCsvWriter::close() {
  if (out_.is_open()) out_.close();
}

std::vector<EstimateRow> read_estimates_csv(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw DatasetError(file.string() + ": cannot open the estimates file");
  std::string line;
  if (!std::getline(in, line)) throw DatasetError(file.string() + ": empty; expected the header '" + std::string(kHeader) + "'");
  const detail::Columns cols = detail::parse_header(line);
  const char* names[] = {"index", "t_ns", "vx_mps", "vy_mps", "speed_mps", "direction_deg", "yaw_rate_dps", "quality", "method"};
  int c[9];
  for (int i = 0; i < 9; ++i) {
    c[i] = cols.find(names[i]);
    if (c[i] < 0) throw DatasetError(file.string() + ":1: header lacks the column '" + names[i] + "'");
  }
  std::vector<EstimateRow> rows;
  std::size_t line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line == "\r") continue;
    const auto fields = detail::split_csv(line);
    auto field = [&](int i) -> std::string_view {
      const auto pos = static_cast<std::size_t>(c[i]);
      return pos < fields.size() ? fields[pos] : std::string_view{};
    };
    EstimateRow r;
    core::VelocityEstimate& e = r.estimate;
    if (!detail::parse_int(field(0), e.index)) {
      throw DatasetError(file.string() + ":" + std::to_string(line_no) + ": index is not a whole number");
    }
    detail::parse_int(field(1), e.t_ns);
    const bool has_vx = detail::parse_double(field(2), e.vx_mps);
    const bool has_vy = detail::parse_double(field(3), e.vy_mps);
    e.has_speed = detail::parse_double(field(4), e.speed_mps);
    e.has_direction = detail::parse_double(field(5), e.direction_deg);
    e.has_yaw_rate = detail::parse_double(field(6), e.yaw_rate_dps);
    if (!e.has_speed && has_vx && has_vy) {
      e.speed_mps = std::hypot(e.vx_mps, e.vy_mps);
      e.has_speed = true;
    }
    if (!detail::parse_double(field(7), e.quality)) e.quality = 0.0;
    e.method = core::method_from_word(field(8)).value_or(core::Method::unknown);
    rows.push_back(std::move(r));
  }
  return rows;
}

}  // namespace gvs::drivers
