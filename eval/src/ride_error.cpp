#include "gvs/eval/ride_error.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include <fmt/format.h>

namespace gvs::eval {

namespace {

const char* source_word(core::ScaleSource s) {
  switch (s) {
    case core::ScaleSource::laser_dots:
      return "laser_dots";
    case core::ScaleSource::external:
      return "external";
    case core::ScaleSource::nominal:
      break;
  }
  return "nominal";
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) out.push_back(field);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

}  // namespace

RideCsvWriter::RideCsvWriter(const std::filesystem::path& file) : file_(file), out_(file) {
  if (!out_) throw std::runtime_error(file.string() + ": cannot write the ride-height CSV");
  out_ << "index,t_ns,height_mm,pitch_deg,roll_deg,dots_found,scale_source\n";
}

void RideCsvWriter::write(const core::VelocityEstimate& e, int dots_found) {
  out_ << e.index << ',' << e.t_ns << ',';
  if (e.ride.has_height) out_ << fmt::format("{:.4f}", e.ride.height_mm);
  out_ << ',';
  if (e.ride.has_pitch) out_ << fmt::format("{:.4f}", e.ride.pitch_deg);
  out_ << ',';
  if (e.ride.has_roll) out_ << fmt::format("{:.4f}", e.ride.roll_deg);
  out_ << ',' << dots_found << ',' << source_word(e.scale_source) << '\n';
}

void RideCsvWriter::close() {
  out_.close();
  if (!out_) throw std::runtime_error(file_.string() + ": writing failed");
}

std::vector<RideRow> read_ride_csv(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open (write it with gvs replay --ride)");
  std::string line;
  std::getline(in, line);
  if (line.rfind("index,t_ns,height_mm,pitch_deg,roll_deg", 0) != 0)
    throw std::runtime_error(file.string() + ":1: not a ride-height CSV (header index,t_ns,height_mm,pitch_deg,roll_deg,...)");
  std::vector<RideRow> rows;
  std::size_t n = 1;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty()) continue;
    const auto f = split(line);
    if (f.size() < 7) throw std::runtime_error(file.string() + ":" + std::to_string(n) + ": expected 7 fields");
    try {
      RideRow r;
      r.index = std::stoll(f[0]);
      r.t_ns = std::stoll(f[1]);
      if (!f[2].empty()) {
        r.ride.has_height = true;
        r.ride.height_mm = std::stod(f[2]);
      }
      if (!f[3].empty()) {
        r.ride.has_pitch = true;
        r.ride.pitch_deg = std::stod(f[3]);
      }
      if (!f[4].empty()) {
        r.ride.has_roll = true;
        r.ride.roll_deg = std::stod(f[4]);
      }
      r.dots_found = std::stoi(f[5]);
      r.scale_source = f[6] == "laser_dots" ? core::ScaleSource::laser_dots
                       : f[6] == "external" ? core::ScaleSource::external
                                            : core::ScaleSource::nominal;
      rows.push_back(r);
    } catch (const std::exception&) {
      throw std::runtime_error(file.string() + ":" + std::to_string(n) + ": a field is not a number");
    }
  }
  return rows;
}

RideReport evaluate_ride(const std::vector<drivers::TruthRecord>& truth, const std::vector<RideRow>& rides,
                         const std::vector<drivers::EstimateRow>& estimates, double nominal_mm) {
  std::unordered_map<std::int64_t, const RideRow*> by_index;
  for (const RideRow& r : rides) by_index[r.index] = &r;
  std::unordered_map<std::int64_t, const core::VelocityEstimate*> estimate_of;
  for (const drivers::EstimateRow& e : estimates) estimate_of[e.estimate.index] = &e.estimate;
  RideReport rep;
  std::vector<double> dh, dp, dr, sd, sn;
  for (const drivers::TruthRecord& t : truth) {
    ++rep.frames;
    const auto it = by_index.find(t.index);
    if (it == by_index.end()) continue;
    const core::RideHeight& m = it->second->ride;
    const auto est = estimate_of.find(t.index);
    if (est != estimate_of.end() && est->second->has_speed && t.speed_mps * 3.6 >= kMovingKmh) {
      const double pct = (est->second->speed_mps - t.speed_mps) / t.speed_mps * 100.0;
      (it->second->scale_source == core::ScaleSource::laser_dots ? sd : sn).push_back(pct);
    }
    if (m.has_height) {
      ++rep.with_height;
      dh.push_back(m.height_mm - t.height_mm.value_or(nominal_mm));
    }
    bool wrong = m.has_height && std::abs(m.height_mm - t.height_mm.value_or(nominal_mm)) > RideReport::kWrongHeightMm;
    if (m.has_pitch) {
      ++rep.with_pitch;
      dp.push_back(m.pitch_deg - t.pitch_deg.value_or(0.0));
      wrong = wrong || std::abs(dp.back()) > RideReport::kWrongTiltDeg;
    }
    if (m.has_roll) {
      ++rep.with_roll;
      dr.push_back(m.roll_deg - t.roll_deg.value_or(0.0));
      wrong = wrong || std::abs(dr.back()) > RideReport::kWrongTiltDeg;
    }
    if (wrong) ++rep.wrong;
  }
  rep.height_mm = error_stats(dh);
  rep.pitch_deg = error_stats(dp);
  rep.roll_deg = error_stats(dr);
  rep.speed_pct_dots = error_stats(sd);
  rep.speed_pct_nominal = error_stats(sn);
  return rep;
}

std::string format_ride_table(const RideReport& r) {
  std::string s = "\nRide height from the laser dots (measured - truth):\n";
  s += fmt::format("  frames {}, with height {} ({:.2f} %), with pitch {} ({:.2f} %), with roll {} ({:.2f} %)\n",
                   r.frames, r.with_height, 100.0 * r.coverage(), r.with_pitch, 100.0 * r.coverage(r.with_pitch),
                   r.with_roll, 100.0 * r.coverage(r.with_roll));
  s += fmt::format("  wrong (off by more than {} mm or {} deg): {} frames\n", RideReport::kWrongHeightMm,
                   RideReport::kWrongTiltDeg, r.wrong);
  s += fmt::format("  {:<10} {:>10} {:>10} {:>10}\n", "", "mean", "RMS", "max |e|");
  s += fmt::format("  {:<10} {:>10.4f} {:>10.4f} {:>10.4f}\n", "height mm", r.height_mm.mean, r.height_mm.rms,
                   r.height_mm.max_abs);
  s += fmt::format("  {:<10} {:>10.4f} {:>10.4f} {:>10.4f}\n", "pitch deg", r.pitch_deg.mean, r.pitch_deg.rms,
                   r.pitch_deg.max_abs);
  s += fmt::format("  {:<10} {:>10.4f} {:>10.4f} {:>10.4f}\n", "roll deg", r.roll_deg.mean, r.roll_deg.rms,
                   r.roll_deg.max_abs);
  s += fmt::format("  speed error (%), moving frames: scaled by the dots {} frames, mean {:.3f} RMS {:.3f} max {:.3f}; "
                   "nominal scale (dots not found) {} frames, RMS {:.3f} max {:.3f}\n",
                   r.speed_pct_dots.count, r.speed_pct_dots.mean, r.speed_pct_dots.rms, r.speed_pct_dots.max_abs,
                   r.speed_pct_nominal.count, r.speed_pct_nominal.rms, r.speed_pct_nominal.max_abs);
  return s;
}

}  // namespace gvs::eval
