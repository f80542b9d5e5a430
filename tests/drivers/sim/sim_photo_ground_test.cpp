// The photographed ground (`photo:FILE[:MM_PER_PIXEL]`): loading and its
// errors, the grey-to-reflectance mapping, determinism per seed, no exact
// repeat one photo apart, no visible seam at the tile borders, and the
// simulator's random access on it. Most tests use a small seamless image
// they make themselves; the shared real-asphalt photos where they are the point.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "asphalt.hpp"
#include "gvs/drivers/sim/ground_spec.hpp"
#include "gvs/drivers/simulator.hpp"
#include "photo_ground.hpp"

namespace gvs::drivers::sim {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kPhotos = {"ph_asphalt_04_1024.png", "acg_Asphalt025C_1024.png",
                                          "torcs_wheel1_asphalt2_1024.png", "torcs_etrack2_asphalt_tile_1024.png",
                                          "torcs_etrack3_asphalt2_1024.png"};

/// A shared real-asphalt photo; the test fails (not skips) when it is absent.
fs::path shared_photo(const std::string& name) {
  const char* shared = std::getenv("GVS_SHARED_DIR");
  const fs::path p = fs::path(shared != nullptr ? shared : "../shared") / "testdata" / "real-asphalt" / name;
  EXPECT_TRUE(fs::exists(p)) << "real-asphalt photo missing: " << p
                             << " (set GVS_SHARED_DIR to the shared/ folder)";
  return p;
}

/// A seamless n x n grey image: white noise blurred with wrap-around borders
/// (grain of about 2 px, mean about 128).
cv::Mat seamless_noise(int n, std::uint64_t seed) {
  cv::Mat noise(n, n, CV_32F);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
  // Blurred with wrap-around (GaussianBlur has no BORDER_WRAP): pad, blur, crop.
  cv::Mat padded, padded_blur;
  cv::copyMakeBorder(noise, padded, 8, 8, 8, 8, cv::BORDER_WRAP);
  cv::GaussianBlur(padded, padded_blur, cv::Size(0, 0), 1.0);
  const cv::Mat blurred = padded_blur(cv::Rect(8, 8, n, n)).clone();
  cv::Scalar mean, sd;
  cv::meanStdDev(blurred, mean, sd);
  cv::Mat grey;
  blurred.convertTo(grey, CV_8U, 35.0 / sd[0], 128.0 - 35.0 * mean[0] / sd[0]);
  return grey;
}

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() /
                     ("gvs_photo_ground_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
  fs::create_directories(d);
  return d;
}

RasterGrid world_grid(double spacing_mm, double x0_mm, double y0_mm, int rows, int cols) {
  RasterGrid g;
  g.spacing_mm = spacing_mm;
  g.spacing_u_mm = spacing_mm;
  g.u0 = std::round(x0_mm / spacing_mm);
  g.v0 = std::round(y0_mm / spacing_mm);
  g.rows = rows;
  g.cols = cols;
  return g;
}

cv::Mat render(const Ground& ground, const RasterGrid& g) {
  cv::Mat out(g.rows, g.cols, CV_32F);
  ground.render_rows(g, 0, g.rows, out.ptr<float>());
  return out;
}

double correlation(const cv::Mat& a, const cv::Mat& b) {
  cv::Scalar ma, sa, mb, sb;
  cv::meanStdDev(a, ma, sa);
  cv::meanStdDev(b, mb, sb);
  const cv::Mat prod = (a - ma[0]).mul(b - mb[0]);
  return cv::mean(prod)[0] / (sa[0] * sb[0]);
}

/// Std of the fine texture: the image minus its 3 px Gaussian blur.
double fine_std(const cv::Mat& img) {
  cv::Mat blur;
  cv::GaussianBlur(img, blur, cv::Size(0, 0), 3.0);
  cv::Scalar m, s;
  cv::meanStdDev(img - blur, m, s);
  return s[0];
}

TEST(SimPhotoGround, ParsesTheGroundSyntax) {
  EXPECT_EQ(parse_ground("procedural").kind, GroundSpec::Kind::procedural);
  const GroundSpec a = parse_ground("photo:a.png");
  EXPECT_EQ(a.kind, GroundSpec::Kind::photo);
  EXPECT_EQ(a.photo_file, "a.png");
  EXPECT_DOUBLE_EQ(a.photo_mm_per_pixel, 0.2);
  const GroundSpec b = parse_ground("photo:/x:y/b.png:0.15");
  EXPECT_EQ(b.photo_file, "/x:y/b.png");
  EXPECT_DOUBLE_EQ(b.photo_mm_per_pixel, 0.15);
  EXPECT_EQ(ground_text(b), "photo:/x:y/b.png:0.15");
  EXPECT_EQ(ground_text(parse_ground(ground_text(a))), "photo:a.png:0.2");
  EXPECT_THROW(parse_ground("gravel"), std::invalid_argument);
  EXPECT_THROW(parse_ground("photo:"), std::invalid_argument);
}

TEST(SimPhotoGround, BadScaleThrowsNamingTheFile) {
  for (const std::string scale : {"abc", "0", "-0.2", "7", "0.2mm", ""}) {
    try {
      (void)parse_ground("photo:asphalt.png:" + scale);
      ADD_FAILURE() << "scale '" << scale << "' accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("asphalt.png"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("millimetres per photo pixel"), std::string::npos) << e.what();
    }
  }
  const cv::Mat grey = seamless_noise(64, 1);
  try {
    const PhotoGround g(grey, 0.0, 1, "mine.png");
    ADD_FAILURE() << "mm per pixel 0 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mine.png"), std::string::npos) << e.what();
  }
}

TEST(SimPhotoGround, MissingUnreadableOrNonSquarePhotoThrowsNamingTheFile) {
  const fs::path dir = temp_dir();
  auto expect_named = [](const std::string& file, const auto& make) {
    try {
      make();
      ADD_FAILURE() << file << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    }
  };
  const std::string missing = (dir / "no_such_photo.png").string();
  expect_named(missing, [&] { PhotoGround g(missing, 0.2, 1); });
  const std::string garbage = (dir / "garbage.png").string();
  std::ofstream(garbage) << "this is not a PNG";
  expect_named(garbage, [&] { PhotoGround g(garbage, 0.2, 1); });
  const std::string oblong = (dir / "oblong.png").string();
  ASSERT_TRUE(cv::imwrite(oblong, cv::Mat(64, 96, CV_8U, cv::Scalar(100))));
  expect_named(oblong, [&] { PhotoGround g(oblong, 0.2, 1); });
  // Through the simulator, as `gvs sim --ground` and gvsd's sim_ground see it.
  SimulatorConfig c;
  c.ground = "photo:" + missing;
  expect_named(missing, [&] { Simulator sim(c); });
  fs::remove_all(dir);
}

TEST(SimPhotoGround, TheSharedPhotosLoadWithTheProceduralMeanReflectance) {
  for (const std::string& name : kPhotos) {
    const fs::path p = shared_photo(name);
    const PhotoGround g(p.string(), 0.2, 1);
    EXPECT_NEAR(g.period_mm(), 204.8, 1e-9) << name;
    const cv::Mat r = render(g, world_grid(0.1, 3.0, 5.0, 1000, 1000));  // 100 x 100 mm inside one tile
    cv::Scalar m, s;
    cv::meanStdDev(r, m, s);
    EXPECT_NEAR(m[0], PhotoGround::kProceduralMeanReflectance, 0.15 * PhotoGround::kProceduralMeanReflectance)
        << name;
    EXPECT_GT(s[0], 0.01) << name << ": the photo's texture must show";
  }
}

TEST(SimPhotoGround, ProceduralMeanReflectanceIsTheConstant) {
  // The photo is scaled to this mean; it must be the procedural asphalt's.
  double sum = 0.0;
  int patches = 0;
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const AsphaltTexture t(seed);
    for (const double x0 : {0.0, 1000.0}) {
      sum += cv::mean(render(t, world_grid(0.05, x0, -500.0, 800, 800)))[0];
      ++patches;
    }
  }
  EXPECT_NEAR(sum / patches, PhotoGround::kProceduralMeanReflectance, 0.03 * PhotoGround::kProceduralMeanReflectance);
}

TEST(SimPhotoGround, GreyMapsToReflectanceKeepingRelativeContrast) {
  const cv::Mat grey = seamless_noise(128, 4);  // 25.6 mm tiles, 1.6 mm half band
  const PhotoGround g(grey, 0.2, 9, "noise");
  // On the photo's pixel centres inside a tile (x = 6.1 .. 18.7 mm, no blend)
  // a tile shows photo pixels: reflectance = grey x procedural mean / mean grey.
  RasterGrid grid = world_grid(0.2, 0.0, 0.0, 64, 64);
  grid.u0 = 30.5;
  grid.v0 = 30.5;
  const cv::Mat r = render(g, grid);
  const double mean_grey = cv::mean(grey)[0];
  const double to_grey = mean_grey / PhotoGround::kProceduralMeanReflectance;
  double worst = 0.0;
  for (int i = 0; i < r.rows; ++i)
    for (int j = 0; j < r.cols; ++j) {
      const double level = static_cast<double>(r.at<float>(i, j)) * to_grey;
      worst = std::max(worst, std::abs(level - std::round(level)));
    }
  EXPECT_LT(worst, 1e-3) << "samples are not photo grey levels times one scale";
  cv::Scalar rm, rs, gm, gs;
  cv::meanStdDev(r, rm, rs);
  cv::meanStdDev(grey, gm, gs);
  EXPECT_NEAR(rs[0] / rm[0], gs[0] / gm[0], 0.15 * gs[0] / gm[0]);
  double lo = 0.0, hi = 0.0;
  cv::minMaxLoc(r, &lo, &hi);
  EXPECT_GE(lo, 0.0);
  EXPECT_LE(hi, 1.0);
}

TEST(SimPhotoGround, DeterministicPerSeedAndDifferentBetweenSeeds) {
  const cv::Mat grey = seamless_noise(128, 5);  // 25.6 mm tiles
  const RasterGrid grid = world_grid(0.1, -30.0, 12.0, 400, 600);
  const cv::Mat a = render(PhotoGround(grey, 0.2, 1, "noise"), grid);
  const cv::Mat b = render(PhotoGround(grey, 0.2, 1, "noise"), grid);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  const cv::Mat c = render(PhotoGround(grey, 0.2, 2, "noise"), grid);
  EXPECT_LT(std::abs(correlation(a, c)), 0.3);
}

TEST(SimPhotoGround, NoExactRepeatOnePhotoApart) {
  const cv::Mat grey = seamless_noise(128, 6);
  const PhotoGround g(grey, 0.2, 3, "noise");
  const double p = g.period_mm();
  // Patches inside tiles (away from the blend), one period apart along x, y and both.
  for (int k = 0; k < 8; ++k) {
    const double x0 = 4.0 + k * 3.0 * p;
    const double y0 = -4.0 * p + 5.0;
    const cv::Mat base = render(g, world_grid(0.1, x0, y0, 100, 100));
    for (const auto& [dx, dy] : {std::pair{1.0, 0.0}, std::pair{0.0, 1.0}, std::pair{1.0, 1.0}}) {
      const cv::Mat other = render(g, world_grid(0.1, x0 + dx * p, y0 + dy * p, 100, 100));
      EXPECT_LT(correlation(base, other), 0.5) << "tile " << k << " shift " << dx << ", " << dy;
    }
  }
}

TEST(SimPhotoGround, TileBordersKeepTheStatisticsAndShowNoEdge) {
  // 64 tile borders (vertical seams, and the corners where four tiles meet)
  // against 64 tile centres: mean, fine-texture std and the step between
  // neighbouring samples across the seam line.
  const cv::Mat grey = seamless_noise(128, 7);
  const PhotoGround g(grey, 0.2, 11, "noise");
  const double p = g.period_mm();
  const double h = 0.1;
  const int side = 64;  // 6.4 mm patches, inside the 3.2 mm half band of the seam +- some
  double m_seam = 0.0, m_corner = 0.0, m_centre = 0.0, f_seam = 0.0, f_corner = 0.0, f_centre = 0.0;
  double step_seam = 0.0, step_centre = 0.0;
  const int n = 64;
  auto step_at = [&](const cv::Mat& img, int col) {  // mean |difference| between columns col-1 and col
    return cv::mean(cv::abs(img.col(col) - img.col(col - 1)))[0];
  };
  for (int k = 0; k < n; ++k) {
    const double tx = (k % 8) - 4;
    const double ty = (k / 8) - 4;
    const cv::Mat seam = render(g, world_grid(h, tx * p - side / 2 * h, (ty + 0.5) * p, side, side));
    const cv::Mat corner = render(g, world_grid(h, tx * p - side / 2 * h, ty * p - side / 2 * h, side, side));
    const cv::Mat centre = render(g, world_grid(h, (tx + 0.5) * p - side / 2 * h, (ty + 0.5) * p, side, side));
    m_seam += cv::mean(seam)[0] / n;
    m_corner += cv::mean(corner)[0] / n;
    m_centre += cv::mean(centre)[0] / n;
    f_seam += fine_std(seam) / n;
    f_corner += fine_std(corner) / n;
    f_centre += fine_std(centre) / n;
    step_seam += step_at(seam, side / 2) / n;  // the seam lies between these columns
    step_centre += step_at(centre, side / 2) / n;
  }
  EXPECT_NEAR(m_seam, m_centre, 0.02 * m_centre);
  EXPECT_NEAR(m_corner, m_centre, 0.02 * m_centre);
  EXPECT_NEAR(f_seam, f_centre, 0.08 * f_centre);
  EXPECT_NEAR(f_corner, f_centre, 0.08 * f_centre);
  EXPECT_NEAR(step_seam, step_centre, 0.08 * step_centre);
}

TEST(SimPhotoGround, RandomAccessEqualsTheSequentialRun) {
  const fs::path dir = temp_dir();
  const fs::path photo = dir / "noise.png";
  ASSERT_TRUE(cv::imwrite(photo.string(), seamless_noise(256, 8)));
  SimulatorConfig c;
  c.scenario = "const";
  c.seconds = 0.15;
  c.fps = 60.0;
  c.camera.width_px = 128;
  c.camera.height_px = 96;
  c.ground = "photo:" + photo.string() + ":0.1";
  Simulator seq(c);
  EXPECT_EQ(seq.config().ground, "photo:" + photo.string() + ":0.1");
  std::vector<cv::Mat> frames;
  SimFrame f;
  while (seq.next(f)) frames.push_back(f.gray.clone());
  ASSERT_EQ(frames.size(), 9u);
  Simulator random(c);
  for (const int k : {7, 2, 5, 0}) {
    SimFrame r;
    random.render(k, random.exposure(), r);
    EXPECT_EQ(cv::norm(r.gray, frames[static_cast<std::size_t>(k)], cv::NORM_INF), 0.0) << "frame " << k;
  }
  // Another seed lays other tiles: other frames.
  c.seed = 2;
  Simulator other(c);
  SimFrame o;
  other.render(0, other.exposure(), o);
  EXPECT_GT(cv::norm(o.gray, frames[0], cv::NORM_L1) / static_cast<double>(o.gray.total()), 5.0);
  fs::remove_all(dir);
}

TEST(SimPhotoGround, LiveConfigurationSamplesThePhotoDirectly) {
  // gvsd's sim: source sets periodic_texture; a photo ground ignores it (no
  // tile), so the live camera sees the same ground as a dataset of the seed.
  const fs::path dir = temp_dir();
  const fs::path photo = dir / "noise.png";
  ASSERT_TRUE(cv::imwrite(photo.string(), seamless_noise(256, 9)));
  SimulatorConfig c;
  c.scenario = "sine";
  c.seconds = 0.2;
  c.camera.width_px = 128;
  c.camera.height_px = 96;
  c.ground = "photo:" + photo.string();
  Simulator dataset(c);
  c.periodic_texture = true;
  Simulator live(c);
  SimFrame a, b;
  dataset.render(4, dataset.exposure(), a);
  live.render(4, live.exposure(), b);
  EXPECT_EQ(cv::norm(a.gray, b.gray, cv::NORM_INF), 0.0);
  fs::remove_all(dir);
}

TEST(SimPhotoGround, RealPhotoIsAsBrightAsTheProceduralAsphaltUnderTheSameLight) {
  // The run's gain is set from frame 0's mean signal: a photo mapped to the
  // procedural mean reflectance needs about the same gain.
  SimulatorConfig c;
  c.scenario = "const";
  c.seconds = 0.1;
  const double procedural = Simulator(c).run_gain_dn_per_e();
  c.ground = "photo:" + shared_photo("ph_asphalt_04_1024.png").string();
  const double photo = Simulator(c).run_gain_dn_per_e();
  EXPECT_NEAR(photo, procedural, 0.2 * procedural);
}

}  // namespace
}  // namespace gvs::drivers::sim
