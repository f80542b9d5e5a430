// The dataset reader and writer: round trip, and a clear error naming the
// file and line or key for every kind of bad dataset.
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/estimates_csv.hpp"

namespace fs = std::filesystem;
using gvs::drivers::CameraInfo;
using gvs::drivers::DatasetError;
using gvs::drivers::DatasetReader;
using gvs::drivers::DatasetWriter;
using gvs::drivers::FrameRecord;
using gvs::drivers::TruthRecord;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("gvs-dataset-test-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

cv::Mat noise_image(int w, int h, unsigned seed) {
  cv::Mat m(h, w, CV_8UC1);
  cv::theRNG().state = seed;
  cv::randu(m, 0, 255);
  return m;
}

void write_text(const fs::path& file, const std::string& text) {
  std::ofstream out(file);
  out << text;
}

/// A small valid dataset written by hand, the way a third-party tool would.
fs::path handmade_dataset(const std::string& name) {
  const fs::path dir = fresh_dir(name);
  fs::create_directories(dir / "frames");
  write_text(dir / "camera.json",
             R"({"format": "gvs-dataset/1", "width": 64, "height": 48, "mm_per_px": 0.2, "mount_yaw_deg": 90,
                 "extra_key": "ignored"})");
  cv::imwrite((dir / "frames/a.png").string(), noise_image(64, 48, 1));
  cv::Mat colour(48, 64, CV_8UC3, cv::Scalar(10, 200, 30));
  cv::imwrite((dir / "frames/b.png").string(), colour);
  write_text(dir / "frames.csv",
             "index,file,t_ns,exposure_us,pulses\n"
             "0,frames/a.png,1000,2500.5,\n"
             "3,frames/b.png,50000000,40,0:10|30:10\n");
  return dir;
}

void expect_error(const fs::path& dir, const std::string& must_contain) {
  try {
    DatasetReader reader(dir);
    for (std::size_t i = 0; i < reader.frames().size(); ++i) (void)reader.load_gray(i);
    FAIL() << "no error; expected one containing '" << must_contain << "'";
  } catch (const DatasetError& e) {
    EXPECT_NE(std::string(e.what()).find(must_contain), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(Dataset, WriterAndReaderRoundTrip) {
  const fs::path dir = fresh_dir("roundtrip");
  CameraInfo cam;
  cam.geometry = {96, 64, 0.1, 12.5};
  cam.description = "round trip";
  gvs::core::ExposurePlan pulsed = gvs::drivers::parse_pulses("0:20|400:20", 500.0);
  {
    DatasetWriter w(dir, cam, true);
    for (int i = 0; i < 3; ++i) {
      FrameRecord r;
      r.index = i == 2 ? 5 : i;  // a gap: frame 2..4 dropped
      r.t_ns = 16666667LL * r.index;
      r.exposure.exposure_us = 3000.0;
      if (i == 1) r.exposure = pulsed;
      w.write_frame(noise_image(96, 64, static_cast<unsigned>(i + 1)), r);
      TruthRecord t;
      t.index = r.index;
      t.t_ns = r.t_ns + 1500000;
      t.vx_mps = 10.0 + i;
      t.vy_mps = -1.25;
      t.speed_mps = std::hypot(t.vx_mps, t.vy_mps);
      t.direction_deg = std::atan2(t.vy_mps, t.vx_mps) * 180.0 / M_PI;
      t.yaw_rate_dps = 3.5;
      w.write_truth(t);
    }
  }
  const DatasetReader r(dir);
  EXPECT_EQ(r.camera().geometry.width_px, 96);
  EXPECT_EQ(r.camera().geometry.height_px, 64);
  EXPECT_DOUBLE_EQ(r.camera().geometry.mount_yaw_deg, 12.5);
  ASSERT_EQ(r.frames().size(), 3U);
  EXPECT_EQ(r.frames()[2].index, 5);
  EXPECT_EQ(r.frames()[1].exposure.pulse_count, 2U);
  EXPECT_DOUBLE_EQ(r.frames()[1].exposure.pulses[1].start_us, 400.0);
  EXPECT_DOUBLE_EQ(r.frames()[1].exposure.lit_time_us(), 40.0);
  const cv::Mat img = r.load_gray(0);
  EXPECT_EQ(cv::norm(img, noise_image(96, 64, 1), cv::NORM_INF), 0.0);
  ASSERT_TRUE(r.has_truth());
  EXPECT_NEAR(r.truth()[2].vx_mps, 12.0, 1e-6);
  EXPECT_NEAR(*r.truth()[0].direction_deg, std::atan2(-1.25, 10.0) * 180.0 / M_PI, 1e-5);
  EXPECT_NEAR(r.truth()[1].yaw_rate_dps, 3.5, 1e-9);
}

TEST(Dataset, BodyPoseTruthRoundTripsWithEmptyFieldsAbsent) {
  // truth.csv's optional height_mm, pitch_deg, roll_deg (shared/spec/dataset-format.md).
  const fs::path dir = fresh_dir("body");
  CameraInfo cam;
  cam.geometry = {32, 24, 0.1, 0.0};
  cam.height_mm = 61.5;
  {
    DatasetWriter w(dir, cam, true, /*with_body_pose=*/true);
    for (int i = 0; i < 2; ++i) {
      FrameRecord r;
      r.index = i;
      r.t_ns = 1000 * (i + 1);
      r.exposure.exposure_us = 100.0;
      w.write_frame(noise_image(32, 24, 3), r);
      TruthRecord t;
      t.index = i;
      t.t_ns = r.t_ns;
      t.vx_mps = 5.0;
      if (i == 0) {
        t.height_mm = 57.123456;
        t.pitch_deg = -1.234567;
        t.roll_deg = 0.876543;
      } else {
        t.height_mm = 64.5;  // pitch and roll unknown: empty fields
      }
      w.write_truth(t);
    }
  }
  std::ifstream header_file(dir / "truth.csv");
  std::string header;
  std::getline(header_file, header);
  EXPECT_EQ(header, "index,t_ns,vx_mps,vy_mps,speed_mps,direction_deg,yaw_rate_dps,height_mm,pitch_deg,roll_deg");
  const DatasetReader r(dir);
  ASSERT_TRUE(r.camera().height_mm.has_value());
  EXPECT_DOUBLE_EQ(*r.camera().height_mm, 61.5);
  ASSERT_EQ(r.truth().size(), 2U);
  ASSERT_TRUE(r.truth()[0].height_mm && r.truth()[0].pitch_deg && r.truth()[0].roll_deg);
  EXPECT_NEAR(*r.truth()[0].height_mm, 57.123456, 1e-9);
  EXPECT_NEAR(*r.truth()[0].pitch_deg, -1.234567, 1e-9);
  EXPECT_NEAR(*r.truth()[0].roll_deg, 0.876543, 1e-9);
  ASSERT_TRUE(r.truth()[1].height_mm.has_value());
  EXPECT_NEAR(*r.truth()[1].height_mm, 64.5, 1e-9);
  EXPECT_FALSE(r.truth()[1].pitch_deg.has_value());
  EXPECT_FALSE(r.truth()[1].roll_deg.has_value());
}

TEST(Dataset, TruthWithoutBodyColumnsReadsAsBeforeAndUnknownColumnsAreIgnored) {
  // A writer without body motion writes the seven columns only, and camera.json without height_mm.
  const fs::path dir = fresh_dir("nobody");
  {
    CameraInfo cam;
    cam.geometry = {32, 24, 0.1, 0.0};
    DatasetWriter w(dir, cam, true);
    FrameRecord r;
    r.exposure.exposure_us = 100.0;
    w.write_frame(noise_image(32, 24, 3), r);
    TruthRecord t;
    t.vx_mps = 2.0;
    t.height_mm = 70.0;  // not written: the file has no such column
    w.write_truth(t);
  }
  {
    std::ifstream in(dir / "truth.csv");
    std::string header;
    std::getline(in, header);
    EXPECT_EQ(header, "index,t_ns,vx_mps,vy_mps,speed_mps,direction_deg,yaw_rate_dps");
    std::ifstream cam_in(dir / "camera.json");
    std::string json;
    for (std::string line; std::getline(cam_in, line);) json += line + '\n';
    EXPECT_EQ(json.find("height_mm"), std::string::npos) << json;
  }
  const DatasetReader old_style(dir);
  ASSERT_EQ(old_style.truth().size(), 1U);
  EXPECT_NEAR(old_style.truth()[0].vx_mps, 2.0, 1e-12);
  EXPECT_FALSE(old_style.truth()[0].height_mm.has_value());
  EXPECT_FALSE(old_style.truth()[0].pitch_deg.has_value());
  EXPECT_FALSE(old_style.truth()[0].roll_deg.has_value());
  EXPECT_FALSE(old_style.camera().height_mm.has_value());

  // A third party's file: the columns found by name, an unknown one in between ignored.
  write_text(dir / "truth.csv",
             "index,t_ns,vx_mps,vy_mps,speed_mps,direction_deg,yaw_rate_dps,lap,roll_deg,height_mm\n"
             "0,1500000,2,0,2,0,0,7,-0.25,59.5\n");
  const DatasetReader third(dir);
  ASSERT_EQ(third.truth().size(), 1U);
  EXPECT_NEAR(*third.truth()[0].height_mm, 59.5, 1e-12);
  EXPECT_NEAR(*third.truth()[0].roll_deg, -0.25, 1e-12);
  EXPECT_FALSE(third.truth()[0].pitch_deg.has_value());

  // Not a number, or a height that is not above the ground: named.
  write_text(dir / "truth.csv",
             "index,t_ns,vx_mps,vy_mps,speed_mps,direction_deg,yaw_rate_dps,height_mm,pitch_deg,roll_deg\n"
             "0,1500000,2,0,2,0,0,60,nose,0\n");
  expect_error(dir, "truth.csv:2: pitch_deg 'nose' is not a number");
  write_text(dir / "truth.csv",
             "index,t_ns,vx_mps,vy_mps,speed_mps,direction_deg,yaw_rate_dps,height_mm\n"
             "0,1500000,2,0,2,0,0,-3\n");
  expect_error(dir, "truth.csv:2: height_mm must be > 0");
}

TEST(Dataset, ReadsThirdPartyDatasetWithColourPngGapsAndPulses) {
  const fs::path dir = handmade_dataset("handmade");
  const DatasetReader r(dir);
  EXPECT_DOUBLE_EQ(r.camera().geometry.mm_per_px, 0.2);
  EXPECT_FALSE(r.has_truth());
  ASSERT_EQ(r.frames().size(), 2U);
  EXPECT_DOUBLE_EQ(r.frames()[0].exposure.exposure_us, 2500.5);
  EXPECT_EQ(r.frames()[0].exposure.pulse_count, 0U);
  EXPECT_DOUBLE_EQ(r.frames()[1].exposure.light_centre_us(), 20.0);  // pulses centred at 5 and 35 us
  const cv::Mat colour_as_gray = r.load_gray(1);
  EXPECT_EQ(colour_as_gray.type(), CV_8UC1);
  EXPECT_NEAR(colour_as_gray.at<unsigned char>(0, 0), 0.299 * 30 + 0.587 * 200 + 0.114 * 10, 1.0);
}

TEST(Dataset, LaserGeometryRoundTripsAndOldCameraJsonHasNone) {
  // camera.json's optional "lasers" (docs/simulator.md, "Laser dots"): written
  // only when there are lasers, read back exactly; a camera.json without it
  // (every dataset before the lasers) reads with none.
  const fs::path dir = handmade_dataset("lasers");
  EXPECT_FALSE(DatasetReader(dir).camera().lasers.enabled());
  const fs::path written = fresh_dir("lasers-written");
  CameraInfo cam;
  cam.geometry = {512, 384, 0.1, 0.0};
  cam.height_mm = 60.0;
  cam.lasers = gvs::core::design_laser_geometry(cam.geometry, 60.0);
  cam.lasers.beams[2].tilt_deg = 40.5;
  cam.lasers.spot_sigma_mm = 0.13;
  {
    DatasetWriter w(written, cam, false);
    FrameRecord r;
    r.exposure.exposure_us = 100.0;
    w.write_frame(noise_image(512, 384, 4), r);
  }
  const gvs::core::LaserGeometry back = DatasetReader(written).camera().lasers;
  ASSERT_EQ(back.count, 4U);
  EXPECT_DOUBLE_EQ(back.spot_sigma_mm, 0.13);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_DOUBLE_EQ(back.beams[k].x_mm, cam.lasers.beams[k].x_mm);
    EXPECT_DOUBLE_EQ(back.beams[k].y_mm, cam.lasers.beams[k].y_mm);
    EXPECT_DOUBLE_EQ(back.beams[k].z_mm, cam.lasers.beams[k].z_mm);
    EXPECT_DOUBLE_EQ(back.beams[k].azimuth_deg, cam.lasers.beams[k].azimuth_deg);
    EXPECT_DOUBLE_EQ(back.beams[k].tilt_deg, cam.lasers.beams[k].tilt_deg);
  }
  // A beam without its tilt: named.
  write_text(written / "camera.json",
             R"({"format": "gvs-dataset/1", "width": 512, "height": 384, "mm_per_px": 0.1,)"
             R"( "lasers": {"beams": [{"x_mm": 1, "y_mm": 2, "z_mm": -20, "azimuth_deg": 90}]}})");
  expect_error(written, "camera.json: key 'lasers': a beam lacks 'tilt_deg'");
}

TEST(Dataset, LaserGeometryLoadsFromCalibratesFileOrACameraJson) {
  // gvsd's [height] lasers_file: the "lasers" object gvs calibrate height
  // --out writes, or a whole camera.json; a file that cannot be used is named.
  const fs::path dir = fresh_dir("laser-files");
  const gvs::core::LaserGeometry design = gvs::core::design_laser_geometry({512, 384, 0.1, 0.0}, 60.0);
  write_text(dir / "lasers.json", gvs::drivers::laser_geometry_json_text(design));
  write_text(dir / "camera.json", R"({"format": "gvs-dataset/1", "width": 512, "height": 384, "mm_per_px": 0.1, "lasers": )" +
                                      gvs::drivers::laser_geometry_json_text(design) + "}");
  for (const char* name : {"lasers.json", "camera.json"}) {
    const gvs::core::LaserGeometry g = gvs::drivers::load_laser_geometry(dir / name);
    ASSERT_EQ(g.count, design.count) << name;
    EXPECT_DOUBLE_EQ(g.beams[3].azimuth_deg, design.beams[3].azimuth_deg) << name;
  }
  auto error_of = [](const fs::path& file) -> std::string {
    try {
      (void)gvs::drivers::load_laser_geometry(file);
    } catch (const DatasetError& e) {
      return e.what();
    }
    return "(no error)";
  };
  EXPECT_NE(error_of(dir / "none.json").find("none.json: cannot read the laser geometry"), std::string::npos);
  write_text(dir / "empty.json", R"({"beams": []})");
  EXPECT_NE(error_of(dir / "empty.json").find("empty.json: key 'lasers': 'beams' is empty"), std::string::npos);
  write_text(dir / "five.json", R"({"beams": [{}, {}, {}, {}, {}]})");
  EXPECT_NE(error_of(dir / "five.json").find("at most 4 beams"), std::string::npos);
  write_text(dir / "text.json", "not json");
  EXPECT_NE(error_of(dir / "text.json").find("text.json: not JSON"), std::string::npos);
}

TEST(Dataset, MissingCameraKeyIsNamed) {
  const fs::path dir = handmade_dataset("nokey");
  write_text(dir / "camera.json", R"({"format": "gvs-dataset/1", "width": 64, "height": 48})");
  expect_error(dir, "camera.json: missing required key 'mm_per_px'");
}

TEST(Dataset, TimeGoingBackwardsNamesTheLine) {
  const fs::path dir = handmade_dataset("backwards");
  write_text(dir / "frames.csv",
             "index,file,t_ns,exposure_us,pulses\n0,frames/a.png,1000,3000,\n1,frames/a.png,999,3000,\n");
  expect_error(dir, "frames.csv:3: t_ns 999 goes backwards");
}

TEST(Dataset, ZeroAndNegativeExposureAreRefused) {
  const fs::path dir = handmade_dataset("exposure");
  write_text(dir / "frames.csv", "index,file,t_ns,exposure_us,pulses\n0,frames/a.png,1000,0,\n");
  expect_error(dir, "frames.csv:2: exposure_us '0' must be a number > 0");
  write_text(dir / "frames.csv", "index,file,t_ns,exposure_us,pulses\n0,frames/a.png,1000,-5,\n");
  expect_error(dir, "frames.csv:2: exposure_us '-5'");
}

TEST(Dataset, BadPulsesAreRefused) {
  const fs::path dir = handmade_dataset("pulses");
  write_text(dir / "frames.csv", "index,file,t_ns,exposure_us,pulses\n0,frames/a.png,1000,100,0:10|5:10\n");
  expect_error(dir, "frames.csv:2: pulses: pulses overlap");
  write_text(dir / "frames.csv", "index,file,t_ns,exposure_us,pulses\n0,frames/a.png,1000,100,abc\n");
  expect_error(dir, "frames.csv:2: pulses:");
}

TEST(Dataset, TruncatedPngIsNamed) {
  const fs::path dir = handmade_dataset("truncated");
  const fs::path png = dir / "frames/a.png";
  const auto size = fs::file_size(png);
  fs::resize_file(png, size / 3);
  expect_error(dir, "frames/a.png: unreadable or truncated image");
}

TEST(Dataset, MissingImageAndWrongSizeAreNamed) {
  fs::path dir = handmade_dataset("missingpng");
  fs::remove(dir / "frames/b.png");
  expect_error(dir, "frames/b.png: missing");
  dir = handmade_dataset("wrongsize");
  cv::imwrite((dir / "frames/a.png").string(), noise_image(32, 48, 3));
  expect_error(dir, "is 32x48 px but camera.json says 64x48");
}

TEST(Dataset, MissingFolderAndHeaderColumnAreNamed) {
  expect_error(fs::temp_directory_path() / "gvs-no-such-dataset", "not a folder");
  const fs::path dir = handmade_dataset("header");
  write_text(dir / "frames.csv", "index,file,exposure_us\n0,frames/a.png,3000\n");
  expect_error(dir, "frames.csv:1: header lacks the column 't_ns'");
}

TEST(EstimatesCsv, RoundTripKeepsAbsentFieldsAbsent) {
  const fs::path dir = fresh_dir("estimates");
  gvs::core::VelocityEstimate full;
  full.index = 7;
  full.t_ns = 123;
  full.has_speed = full.has_direction = full.has_yaw_rate = true;
  full.speed_mps = 10.0;
  full.direction_deg = 30.0;
  full.vx_mps = 10.0 * std::cos(M_PI / 6);
  full.vy_mps = 5.0;
  full.yaw_rate_dps = -4.5;
  full.quality = 0.75;
  full.method = gvs::core::Method::pair;
  gvs::core::VelocityEstimate direction_only;
  direction_only.index = 8;
  direction_only.has_direction = true;
  direction_only.direction_deg = -3.25;
  direction_only.quality = 0.5;
  direction_only.method = gvs::core::Method::streak_fwd;
  {
    gvs::drivers::EstimatesCsvWriter w(dir / "e.csv");
    w.write(full);
    w.write(direction_only);
    w.write(gvs::core::no_estimate(9, 456, gvs::core::Method::dark));
  }
  const auto rows = gvs::drivers::read_estimates_csv(dir / "e.csv");
  ASSERT_EQ(rows.size(), 3U);
  EXPECT_TRUE(rows[0].estimate.has_speed && rows[0].estimate.has_direction && rows[0].estimate.has_yaw_rate);
  EXPECT_NEAR(rows[0].estimate.direction_deg, 30.0, 1e-4);
  EXPECT_EQ(rows[0].estimate.method, gvs::core::Method::pair);
  EXPECT_FALSE(rows[1].estimate.has_speed);
  EXPECT_TRUE(rows[1].estimate.has_direction);
  EXPECT_EQ(rows[1].estimate.method, gvs::core::Method::streak_fwd);
  EXPECT_FALSE(rows[2].estimate.has_speed || rows[2].estimate.has_direction || rows[2].estimate.has_yaw_rate);
  EXPECT_EQ(rows[2].estimate.quality, 0.0);
  EXPECT_EQ(rows[2].estimate.method, gvs::core::Method::dark);
  EXPECT_EQ(gvs::drivers::format_estimate_row(gvs::core::no_estimate(9, 456, gvs::core::Method::dark)),
            "9,456,,,,,,0.000,dark");
}

// Every method is written as its table word and read back as itself; a word
// from another estimator (the format allows any word) reads as `unknown`.
TEST(EstimatesCsv, MethodWordsRoundTripThroughTheTable) {
  const fs::path dir = fresh_dir("estimates-methods");
  {
    gvs::drivers::EstimatesCsvWriter w(dir / "e.csv");
    for (const gvs::core::MethodInfo& m : gvs::core::kMethods) {
      w.write(gvs::core::no_estimate(static_cast<std::int64_t>(m.method), 1000, m.method));
    }
  }
  const auto rows = gvs::drivers::read_estimates_csv(dir / "e.csv");
  ASSERT_EQ(rows.size(), gvs::core::kMethodCount);
  for (const auto& row : rows) {
    const gvs::core::MethodInfo& m = gvs::core::kMethods[static_cast<std::size_t>(row.estimate.index)];
    EXPECT_EQ(row.estimate.method, m.method) << m.word;
    EXPECT_EQ(gvs::drivers::format_estimate_row(row.estimate),
              std::to_string(row.estimate.index) + ",1000,,,,,,0.000," + m.word);
  }
  write_text(dir / "other.csv",
             "index,t_ns,vx_mps,vy_mps,speed_mps,direction_deg,yaw_rate_dps,quality,method\n"
             "0,1000,1.0,0.0,1.0,0.0,,0.900,optical-flow\n1,2000,,,,,,0.000,pair\n");
  const auto other = gvs::drivers::read_estimates_csv(dir / "other.csv");
  ASSERT_EQ(other.size(), 2U);
  EXPECT_EQ(other[0].estimate.method, gvs::core::Method::unknown);
  EXPECT_TRUE(other[0].estimate.has_speed);
  EXPECT_EQ(other[1].estimate.method, gvs::core::Method::pair);
}
