// gvs eval's arithmetic: band assignment, the wrap at +-180 deg, RMS and
// std, the constant-direction summary, standstill and unmatched rows.
#include <cmath>
#include <optional>

#include <gtest/gtest.h>

#include "gvs/eval/accuracy.hpp"
#include "gvs/eval/height_error.hpp"

using gvs::eval::evaluate_accuracy;
using gvs::drivers::EstimateRow;
using gvs::drivers::TruthRecord;

namespace {

TruthRecord truth(std::int64_t index, double speed_kmh, std::optional<double> dir_deg, double yaw_dps = 0.0) {
  TruthRecord t;
  t.index = index;
  t.speed_mps = speed_kmh / 3.6;
  const double d = dir_deg.value_or(0.0) * M_PI / 180.0;
  t.vx_mps = t.speed_mps * std::cos(d);
  t.vy_mps = t.speed_mps * std::sin(d);
  t.direction_deg = dir_deg;
  t.yaw_rate_dps = yaw_dps;
  return t;
}

EstimateRow estimate(std::int64_t index, std::optional<double> speed_kmh, std::optional<double> dir_deg,
                     std::optional<double> yaw_dps = std::nullopt) {
  EstimateRow r;
  r.estimate.index = index;
  r.estimate.has_speed = speed_kmh.has_value();
  r.estimate.speed_mps = speed_kmh.value_or(0.0) / 3.6;
  r.estimate.has_direction = dir_deg.has_value();
  r.estimate.direction_deg = dir_deg.value_or(0.0);
  r.estimate.has_yaw_rate = yaw_dps.has_value();
  r.estimate.yaw_rate_dps = yaw_dps.value_or(0.0);
  r.estimate.quality = 1.0;
  r.estimate.method = gvs::core::Method::pair;
  return r;
}

}  // namespace

TEST(Accuracy, ErrorStatsMatchTheDefinitions) {
  const auto s = gvs::eval::error_stats({1.0, -1.0, 3.0});
  EXPECT_EQ(s.count, 3U);
  EXPECT_DOUBLE_EQ(s.mean, 1.0);
  EXPECT_DOUBLE_EQ(s.rms, std::sqrt(11.0 / 3.0));
  EXPECT_DOUBLE_EQ(s.std, 2.0);  // sample std: sqrt((0+4+4)/2)
  EXPECT_DOUBLE_EQ(s.max_abs, 3.0);
}

TEST(Accuracy, DirectionErrorWrapsAtPlusMinus180) {
  // Truth 179 deg, estimate -179 deg: 2 deg off, not 358.
  const auto r = evaluate_accuracy({truth(0, 30.0, 179.0)}, {estimate(0, 30.0, -179.0)});
  ASSERT_EQ(r.bands[2].direction_deg.count, 1U);
  EXPECT_NEAR(r.bands[2].direction_deg.mean, 2.0, 1e-9);
  EXPECT_NEAR(r.all.direction_deg.max_abs, 2.0, 1e-9);
}

TEST(Accuracy, FramesLandInTheirSpeedBand) {
  const auto r = evaluate_accuracy(
      {truth(0, 2.0, 0.0), truth(1, 10.0, 0.0), truth(2, 30.0, 0.0), truth(3, 100.0, 0.0), truth(4, 250.0, 0.0)},
      {estimate(0, 2.2, 1.0), estimate(1, 10.0, 0.5), estimate(2, std::nullopt, 0.1), estimate(3, 99.0, -0.2),
       estimate(4, 250.0, 0.0)});
  ASSERT_EQ(r.bands.size(), 5U);
  for (const auto& b : r.bands) EXPECT_EQ(b.frames, 1U) << b.lo_kmh;
  EXPECT_NEAR(r.bands[0].speed_pct.mean, 10.0, 1e-9);
  EXPECT_NEAR(r.bands[3].speed_pct.mean, -1.0, 1e-9);
  EXPECT_EQ(r.bands[2].with_speed, 0U);
  EXPECT_EQ(r.bands[2].with_direction, 1U);
  EXPECT_EQ(r.all.frames, 5U);
  EXPECT_EQ(r.all.with_direction, 5U);
  EXPECT_EQ(r.all.with_speed, 4U);
}

TEST(Accuracy, StandstillCountsSpeedAndFlagsAnyDirection) {
  const auto r = evaluate_accuracy({truth(0, 0.0, std::nullopt), truth(1, 0.0, std::nullopt)},
                                   {estimate(0, 0.018, std::nullopt), estimate(1, 0.0, 45.0)});
  EXPECT_EQ(r.standstill_frames, 2U);
  EXPECT_EQ(r.standstill_with_speed, 2U);
  EXPECT_NEAR(r.standstill_speed_max_abs_mps, 0.005, 1e-9);
  EXPECT_EQ(r.standstill_with_direction, 1U);
  EXPECT_EQ(r.all.direction_deg.count, 0U);  // no truth direction to compare with
}

TEST(Accuracy, ConstantDirectionRunGetsTheThesisSummary) {
  std::vector<TruthRecord> t;
  std::vector<EstimateRow> e;
  const double est[] = {9.9, 10.0, 10.0, 10.1, 10.5};
  for (int i = 0; i < 5; ++i) {
    t.push_back(truth(i, 20.0, 10.0));
    e.push_back(estimate(i, 20.0, est[i]));
  }
  const auto r = evaluate_accuracy(t, e);
  ASSERT_TRUE(r.constant_direction.has_value());
  EXPECT_NEAR(r.constant_direction->mean, 10.1, 1e-9);
  EXPECT_NEAR(r.constant_direction->mode, 10.0, 1e-9);
  EXPECT_NEAR(r.constant_direction->min, 9.9, 1e-9);
  EXPECT_NEAR(r.constant_direction->max, 10.5, 1e-9);

  t.push_back(truth(5, 20.0, 12.0));
  e.push_back(estimate(5, 20.0, 12.0));
  EXPECT_FALSE(evaluate_accuracy(t, e).constant_direction.has_value());
}

TEST(Accuracy, UnmatchedRowsAreCountedNotMatchedByPosition) {
  const auto r = evaluate_accuracy({truth(0, 30.0, 0.0), truth(2, 30.0, 0.0)},
                                   {estimate(0, 30.0, 0.0), estimate(1, 30.0, 90.0)});
  EXPECT_EQ(r.truth_without_estimate, 1U);
  EXPECT_EQ(r.estimates_without_truth, 1U);
  EXPECT_NEAR(r.all.direction_deg.max_abs, 0.0, 1e-12);
}

TEST(Accuracy, YawRateErrorOnlyWhereBothExist) {
  const auto r = evaluate_accuracy({truth(0, 3.0, 0.0, 20.0), truth(1, 3.0, 0.0, 20.0)},
                                   {estimate(0, 3.0, 0.0, 21.0), estimate(1, 3.0, 0.0)});
  EXPECT_EQ(r.all.yaw_rate_dps.count, 1U);
  EXPECT_NEAR(r.all.yaw_rate_dps.rms, 1.0, 1e-9);
}

TEST(Accuracy, TableAndJsonCarryTheFigures) {
  const auto r = evaluate_accuracy({truth(0, 30.0, 1.0)}, {estimate(0, 33.0, 1.5)});
  const std::string table = gvs::eval::format_accuracy_table(r);
  EXPECT_NE(table.find("15-60"), std::string::npos) << table;
  EXPECT_NE(table.find("0.500"), std::string::npos) << table;  // direction error
  EXPECT_NE(table.find("10.00"), std::string::npos) << table;  // speed error %
  const std::string json = gvs::eval::format_accuracy_json(r);
  EXPECT_NE(json.find("\"direction_deg\""), std::string::npos);
}

TEST(Accuracy, SpeedsOffByMoreThanFivePercentAreCountedPerBand) {
  // 30 km/h read as 0 (a false standstill) and as 31.6 (5.3 % fast) count; 31.4
  // (4.7 %) does not, nor 0.8 km/h read as 0.5 (below 1 km/h).
  const auto r = evaluate_accuracy(
      {truth(0, 30.0, 0.0), truth(1, 30.0, 0.0), truth(2, 30.0, 0.0), truth(3, 0.8, 0.0)},
      {estimate(0, 0.0, std::nullopt), estimate(1, 31.6, 0.0), estimate(2, 31.4, 0.0), estimate(3, 0.5, 0.0)});
  EXPECT_EQ(r.bands[2].speed_off, 2U);
  EXPECT_EQ(r.bands[0].speed_off, 0U);
  EXPECT_EQ(r.all.speed_off, 2U);
  EXPECT_NE(gvs::eval::format_accuracy_table(r).find("off>5"), std::string::npos);
  EXPECT_NE(gvs::eval::format_accuracy_json(r).find("\"speed_off_5pct\": 2"), std::string::npos);
}

TEST(Accuracy, ValidOnTheBusCountsOnlyEstimatesAtTheBusQuality) {
  // Three moving frames with direction and speed: quality 1.0, 0.3 (the
  // bus's default bar, valid) and 0.29 (sent with its Valid bits 0).
  std::vector<EstimateRow> e = {estimate(0, 30.0, 0.0), estimate(1, 30.0, 0.0), estimate(2, 30.0, 0.0)};
  e[1].estimate.quality = 0.3;
  e[2].estimate.quality = 0.29;
  const auto r = evaluate_accuracy({truth(0, 30.0, 0.0), truth(1, 30.0, 0.0), truth(2, 30.0, 0.0)}, e);
  EXPECT_EQ(r.bands[2].with_speed, 3U);
  EXPECT_EQ(r.bands[2].valid_speed, 2U);
  EXPECT_EQ(r.bands[2].with_direction, 3U);
  EXPECT_EQ(r.bands[2].valid_direction, 2U);
  EXPECT_EQ(r.all.valid_speed, 2U);
  const std::string table = gvs::eval::format_accuracy_table(r);
  EXPECT_NE(table.find("valid on the bus (quality >= 0.30), direction/moving speed/all: 15-60 2/3 2/3; all 2/3 2/3"),
            std::string::npos)
      << table;
  EXPECT_NE(gvs::eval::format_accuracy_json(r).find("\"valid_speed\": 2"), std::string::npos);
}

TEST(SpeedVsHeight, BinsTheSpeedErrorByHeightErrorAndCorrectsTheScale) {
  // An estimator that assumes 60 mm reads 60/H of the speed; one frame
  // without a height counts as nominal; a frame without a speed and a
  // standing frame do not count.
  std::vector<TruthRecord> t;
  std::vector<EstimateRow> e;
  const double heights[] = {55.0, 60.0, 65.0, 65.0};
  for (int i = 0; i < 4; ++i) {
    t.push_back(truth(i, 36.0, 0.0));
    t.back().height_mm = heights[i];
    e.push_back(estimate(i, 36.0 * 60.0 / heights[i] * (i == 3 ? 1.01 : 1.0), 0.0));
  }
  t.push_back(truth(4, 36.0, 0.0));  // no height: nominal
  e.push_back(estimate(4, 36.0, 0.0));
  t.push_back(truth(5, 36.0, 0.0));
  t.back().height_mm = 70.0;
  e.push_back(estimate(5, std::nullopt, 0.0));  // no speed
  t.push_back(truth(6, 0.0, std::nullopt));
  t.back().height_mm = 70.0;
  e.push_back(estimate(6, 0.0, std::nullopt));  // standing

  const auto r = gvs::eval::evaluate_speed_vs_height(t, e, 60.0);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->all.speed_pct.count, 5U);
  const auto& edges = gvs::eval::height_bin_edges_mm();
  auto bin_of = [&](double dh) {
    for (std::size_t i = 0; i + 1 < edges.size(); ++i)
      if (dh >= edges[i] && dh < edges[i + 1]) return i;
    return edges.size();
  };
  const auto& up = r->bins[bin_of(5.0)];
  ASSERT_EQ(up.speed_pct.count, 2U);
  EXPECT_NEAR(up.height_error_mm.mean, 5.0, 1e-12);
  EXPECT_NEAR(up.scale_pct.mean, (60.0 / 65.0 - 1.0) * 100.0, 1e-9);
  EXPECT_NEAR(up.speed_pct.mean, ((60.0 / 65.0) * 1.005 - 1.0) * 100.0, 1e-9);
  // Corrected with the true height: exact, and 1 % off for the frame that was.
  EXPECT_NEAR(up.corrected_pct.max_abs, 1.0, 1e-9);
  const auto& down = r->bins[bin_of(-5.0)];
  ASSERT_EQ(down.speed_pct.count, 1U);
  EXPECT_NEAR(down.speed_pct.mean, (60.0 / 55.0 - 1.0) * 100.0, 1e-9);
  EXPECT_NEAR(down.corrected_pct.max_abs, 0.0, 1e-9);
  EXPECT_EQ(r->bins[bin_of(0.0)].speed_pct.count, 2U);
  // About -100/60 % per mm.
  EXPECT_NEAR(r->slope_pct_per_mm, -1.66, 0.15);
  EXPECT_NE(gvs::eval::format_height_table(*r).find("slope"), std::string::npos);

  // No heights in the truth: no report.
  EXPECT_FALSE(gvs::eval::evaluate_speed_vs_height({truth(0, 36.0, 0.0)}, {estimate(0, 36.0, 0.0)}, 60.0));
}
