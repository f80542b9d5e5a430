// read_png / write_png (libpng) against OpenCV's cv::imread / cv::imwrite:
// the same pixels, bit for bit, for the files gvs reads (simulator frames,
// the photographs in ../shared/testdata) and for the PNG kinds a third-party
// dataset may hold (colour, alpha, 16-bit, palette, 1-bit, interlaced).
#include <png.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/png_file.hpp"
#include "gvs/drivers/simulator.hpp"

namespace fs = std::filesystem;
using gvs::drivers::PngPixels;
using gvs::drivers::read_png;
using gvs::drivers::write_png;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("gvs-png-test-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// Same type, same size, every element equal.
::testing::AssertionResult same_pixels(const cv::Mat& a, const cv::Mat& b) {
  if (a.type() != b.type()) return ::testing::AssertionFailure() << "type " << a.type() << " vs " << b.type();
  if (a.size() != b.size()) return ::testing::AssertionFailure() << "size " << a.size() << " vs " << b.size();
  if (a.empty()) return ::testing::AssertionFailure() << "both empty";
  const cv::Mat diff = a.reshape(1) != b.reshape(1);
  const int differing = cv::countNonZero(diff);
  if (differing != 0) return ::testing::AssertionFailure() << differing << " samples differ";
  return ::testing::AssertionSuccess();
}

/// read_png in both modes equals cv::imread with the matching flag.
void expect_as_imread(const fs::path& file) {
  SCOPED_TRACE(file.string());
  const auto grey = read_png(file.string(), PngPixels::grey);
  EXPECT_TRUE(grey.error.empty()) << grey.error;
  EXPECT_TRUE(same_pixels(grey.pixels, cv::imread(file.string(), cv::IMREAD_GRAYSCALE)));
  const auto unchanged = read_png(file.string(), PngPixels::unchanged);
  EXPECT_TRUE(unchanged.error.empty()) << unchanged.error;
  EXPECT_TRUE(same_pixels(unchanged.pixels, cv::imread(file.string(), cv::IMREAD_UNCHANGED)));
}

cv::Mat noise(int rows, int cols, int type, unsigned seed) {
  cv::Mat m(rows, cols, type);
  cv::theRNG().state = seed;
  cv::randu(m, cv::Scalar::all(0), cv::Scalar::all(CV_MAT_DEPTH(type) == CV_16U ? 65536 : 256));
  return m;
}

/// Writes rows of raw PNG samples with libpng directly: the kinds cv::imwrite
/// cannot make (palette, grey + alpha, interlaced, 2-bit).
void write_raw_png(const fs::path& file, int width, int height, int bit_depth, int colour_type, bool interlaced,
                   const std::vector<std::vector<png_byte>>& rows, int palette_size = 0) {
  std::FILE* f = std::fopen(file.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  ASSERT_EQ(setjmp(png_jmpbuf(png)), 0);
  png_init_io(png, f);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), bit_depth, colour_type,
               interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  std::vector<png_color> palette(static_cast<std::size_t>(palette_size));
  std::vector<png_byte> alpha(static_cast<std::size_t>(palette_size));
  for (int i = 0; i < palette_size; ++i) {
    palette[static_cast<std::size_t>(i)] = {static_cast<png_byte>(i * 7), static_cast<png_byte>(255 - i),
                                            static_cast<png_byte>(i * 3 + 1)};
    alpha[static_cast<std::size_t>(i)] = static_cast<png_byte>(i * 11);
  }
  if (palette_size > 0) {
    png_set_PLTE(png, info, palette.data(), palette_size);
    png_set_tRNS(png, info, alpha.data(), palette_size / 2, nullptr);  // half the entries carry alpha
  }
  png_write_info(png, info);
  std::vector<png_bytep> pointers;
  for (const auto& r : rows) pointers.push_back(const_cast<png_bytep>(r.data()));
  png_write_image(png, pointers.data());
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

std::vector<std::vector<png_byte>> raw_rows(int height, std::size_t bytes_per_row, unsigned seed) {
  std::vector<std::vector<png_byte>> rows(static_cast<std::size_t>(height), std::vector<png_byte>(bytes_per_row));
  unsigned x = seed;
  for (auto& r : rows) {
    for (auto& b : r) {
      x = x * 1103515245U + 12345U;
      b = static_cast<png_byte>(x >> 16);
    }
  }
  return rows;
}

}  // namespace

// The photographs the simulator's photo ground and the thesis tests read.
TEST(PngFile, ReadsTheSharedPhotographsAsImreadDoes) {
  const char* shared = std::getenv("GVS_SHARED_DIR");
  ASSERT_NE(shared, nullptr) << "GVS_SHARED_DIR is not set (ctest sets it to ../shared)";
  int files = 0;
  for (const char* folder : {"testdata/real-asphalt", "testdata/thesis-frames"}) {
    const fs::path dir = fs::path(shared) / folder;
    ASSERT_TRUE(fs::is_directory(dir)) << dir << " is missing";
    for (const auto& entry : fs::directory_iterator(dir)) {
      if (entry.path().extension() != ".png") continue;
      expect_as_imread(entry.path());
      ++files;
    }
  }
  EXPECT_GE(files, 15) << "expected the 5 asphalt photos and 10 thesis frames";
}

// Frames as `gvs sim` writes them (DatasetWriter, now libpng): read back as
// cv::imread reads them, and equal to the rendered frame (PNG is lossless).
TEST(PngFile, SimulatorFramesReadBackExactly) {
  const fs::path dir = fresh_dir("sim");
  gvs::drivers::SimulatorConfig config;
  config.scenario = "sine";
  config.seconds = 0.05;
  gvs::drivers::Simulator sim(config);
  gvs::drivers::CameraInfo camera;
  camera.geometry = config.camera;
  std::vector<cv::Mat> rendered;
  {
    gvs::drivers::DatasetWriter writer(dir, camera, false);
    gvs::drivers::SimFrame frame;
    while (sim.next(frame) && rendered.size() < 3) {
      writer.write_frame(frame.gray, frame.record);
      rendered.push_back(frame.gray.clone());
    }
  }
  ASSERT_EQ(rendered.size(), 3U);
  const gvs::drivers::DatasetReader reader(dir);
  ASSERT_EQ(reader.frames().size(), 3U);
  for (std::size_t i = 0; i < rendered.size(); ++i) {
    const fs::path file = dir / reader.frames()[i].file;
    expect_as_imread(file);
    EXPECT_TRUE(same_pixels(read_png(file.string(), PngPixels::grey).pixels, rendered[i]));
    EXPECT_TRUE(same_pixels(reader.load_gray(i), rendered[i]));
  }
  fs::remove_all(dir);
}

// What cv::imwrite makes: grey, colour, colour + alpha, 16-bit, 1-bit.
TEST(PngFile, ReadsOpenCvsPngKindsAsImreadDoes) {
  const fs::path dir = fresh_dir("kinds");
  struct Kind {
    const char* name;
    cv::Mat image;
    std::vector<int> params;
  };
  const Kind kinds[] = {
      {"grey8", noise(37, 53, CV_8UC1, 1), {}},
      {"bgr8", noise(37, 53, CV_8UC3, 2), {}},
      {"bgra8", noise(37, 53, CV_8UC4, 3), {}},
      {"grey16", noise(37, 53, CV_16UC1, 4), {}},
      {"bgr16", noise(37, 53, CV_16UC3, 5), {}},
      {"bgra16", noise(37, 53, CV_16UC4, 6), {}},
      {"bilevel", noise(37, 53, CV_8UC1, 7) > 128, {cv::IMWRITE_PNG_BILEVEL, 1}},
  };
  for (const Kind& k : kinds) {
    const fs::path file = dir / (std::string(k.name) + ".png");
    ASSERT_TRUE(cv::imwrite(file.string(), k.image, k.params)) << k.name;
    expect_as_imread(file);
  }
  fs::remove_all(dir);
}

// Kinds only other tools make: palette with tRNS, grey + alpha, 2-bit grey,
// interlaced grey and colour.
TEST(PngFile, ReadsPaletteAlphaLowDepthAndInterlacedAsImreadDoes) {
  const fs::path dir = fresh_dir("raw");
  const int w = 29;
  const int h = 17;
  write_raw_png(dir / "palette.png", w, h, 8, PNG_COLOR_TYPE_PALETTE, false, raw_rows(h, w, 1), 256);
  write_raw_png(dir / "grey_alpha.png", w, h, 8, PNG_COLOR_TYPE_GRAY_ALPHA, false, raw_rows(h, 2 * w, 2));
  write_raw_png(dir / "grey2.png", w, h, 2, PNG_COLOR_TYPE_GRAY, false, raw_rows(h, (2 * w + 7) / 8, 3));
  write_raw_png(dir / "grey_interlaced.png", w, h, 8, PNG_COLOR_TYPE_GRAY, true, raw_rows(h, w, 4));
  write_raw_png(dir / "rgb_interlaced.png", w, h, 8, PNG_COLOR_TYPE_RGB, true, raw_rows(h, 3 * w, 5));
  for (const char* name : {"palette", "grey_alpha", "grey2", "grey_interlaced", "rgb_interlaced"}) {
    expect_as_imread(dir / (std::string(name) + ".png"));
  }
  // Interlaced rows land in place: the interlaced file reads as the plain one.
  write_raw_png(dir / "grey_plain.png", w, h, 8, PNG_COLOR_TYPE_GRAY, false, raw_rows(h, w, 4));
  EXPECT_TRUE(same_pixels(read_png((dir / "grey_interlaced.png").string(), PngPixels::grey).pixels,
                          read_png((dir / "grey_plain.png").string(), PngPixels::grey).pixels));
  fs::remove_all(dir);
}

TEST(PngFile, WritesWhatImreadReadsBack) {
  const fs::path dir = fresh_dir("write");
  for (const cv::Mat& image : {noise(41, 67, CV_8UC1, 11), noise(41, 67, CV_8UC3, 12)}) {
    for (int level : {0, 1, 9}) {
      const fs::path file = dir / ("w" + std::to_string(image.channels()) + "_" + std::to_string(level) + ".png");
      ASSERT_EQ(write_png(file.string(), image, level), "");
      EXPECT_TRUE(same_pixels(cv::imread(file.string(), cv::IMREAD_UNCHANGED), image)) << file;
      EXPECT_TRUE(same_pixels(read_png(file.string(), PngPixels::unchanged).pixels, image)) << file;
    }
  }
  EXPECT_NE(write_png((dir / "x.png").string(), noise(4, 4, CV_16UC1, 1)), "");
  EXPECT_NE(write_png((dir / "x.png").string(), noise(4, 4, CV_8UC1, 1), 10), "");
  EXPECT_NE(write_png((dir / "no-such-folder" / "x.png").string(), noise(4, 4, CV_8UC1, 1)), "");
  fs::remove_all(dir);
}

TEST(PngFile, BadFilesGiveAnEmptyImageAndSayWhy) {
  const fs::path dir = fresh_dir("bad");
  const auto missing = read_png((dir / "missing.png").string(), PngPixels::grey);
  EXPECT_TRUE(missing.pixels.empty());
  EXPECT_NE(missing.error.find("cannot be opened"), std::string::npos) << missing.error;

  std::ofstream(dir / "text.png") << "not a picture at all";
  const auto text = read_png((dir / "text.png").string(), PngPixels::unchanged);
  EXPECT_TRUE(text.pixels.empty());
  EXPECT_EQ(text.error, "not a PNG file");

  // A valid file cut short inside its image data, and one with a flipped byte in it.
  const cv::Mat image = noise(64, 64, CV_8UC1, 5);
  ASSERT_EQ(write_png((dir / "whole.png").string(), image), "");
  std::string bytes(static_cast<std::size_t>(fs::file_size(dir / "whole.png")), '\0');
  std::ifstream(dir / "whole.png", std::ios::binary).read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  ASSERT_GT(bytes.size(), 1000U);
  std::ofstream(dir / "cut.png", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  const auto cut = read_png((dir / "cut.png").string(), PngPixels::grey);
  EXPECT_TRUE(cut.pixels.empty());
  EXPECT_NE(cut.error.find("unreadable PNG"), std::string::npos) << cut.error;
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x55);
  std::ofstream(dir / "flipped.png", std::ios::binary) << bytes;
  const auto flipped = read_png((dir / "flipped.png").string(), PngPixels::grey);
  EXPECT_TRUE(flipped.pixels.empty());
  EXPECT_NE(flipped.error.find("unreadable PNG"), std::string::npos) << flipped.error;
  fs::remove_all(dir);
}
