// PNG reading and writing with libpng. The read transforms are the ones
// OpenCV 4.6's PNG decoder (modules/imgcodecs/src/grfmt_png.cpp) asks libpng
// for, in the same order, so the pixels equal cv::imread's
// (tests/drivers/png_file_test.cpp compares them).
//
// libpng reports errors by longjmp to the setjmp in the function that called
// it: the functions holding a setjmp keep only plain locals, and every C++
// object they touch lives in their caller.
#include "gvs/drivers/png_file.hpp"

#include <png.h>

#include <bit>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>

namespace gvs::drivers {
namespace {

/// libpng's error and warning sink: the error's text is kept for the caller.
struct PngMessages {
  char error[160] = {};
};

void on_png_error(png_structp png, png_const_charp message) {
  auto* m = static_cast<PngMessages*>(png_get_error_ptr(png));
  std::snprintf(m->error, sizeof m->error, "%s", message);
  png_longjmp(png, 1);
}

void on_png_warning(png_structp /*png*/, png_const_charp /*message*/) {
  // Benign (an unknown ancillary chunk, a bad sRGB profile): OpenCV reads on, so do we.
}

/// Header: size and the cv::Mat type cv::imread would give for `pixels`.
struct PngHeader {
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  int bit_depth = 0;
  int color_type = 0;
  int mat_type = 0;
  int passes = 1;  ///< 7 for an interlaced file
};

/// cv::imread's limit (CV_IO_MAX_IMAGE_PIXELS): larger files are refused, not allocated.
constexpr double kMaxPixels = 1 << 30;

/// Reads the header of the open `png` and the transforms that turn its rows
/// into `pixels`. false: libpng reported an error (in `messages`).
bool read_header(png_structp png, png_infop info, std::FILE* f, PngPixels pixels, PngHeader& h) {
  if (setjmp(png_jmpbuf(png)) != 0) return false;
  png_init_io(png, f);
  png_set_sig_bytes(png, 8);
  png_read_info(png, info);
  png_get_IHDR(png, info, &h.width, &h.height, &h.bit_depth, &h.color_type, nullptr, nullptr, nullptr);

  // The Mat type (OpenCV's PngDecoder::readHeader, then imread's flags).
  int channels = 1;
  if (pixels == PngPixels::unchanged) {
    switch (h.color_type) {
      case PNG_COLOR_TYPE_RGB:
      case PNG_COLOR_TYPE_PALETTE: {
        png_bytep trans = nullptr;
        int num_trans = 0;
        png_color_16p trans_values = nullptr;
        png_get_tRNS(png, info, &trans, &num_trans, &trans_values);
        channels = num_trans > 0 ? 4 : 3;
        break;
      }
      case PNG_COLOR_TYPE_GRAY_ALPHA:
      case PNG_COLOR_TYPE_RGB_ALPHA: channels = 4; break;
      default: channels = 1;
    }
  }
  const bool sixteen = pixels == PngPixels::unchanged && h.bit_depth == 16;
  h.mat_type = CV_MAKETYPE(sixteen ? CV_16U : CV_8U, channels);

  // The transforms (OpenCV's PngDecoder::readData).
  if (!sixteen && h.bit_depth == 16) {
    png_set_strip_16(png);
  } else if constexpr (std::endian::native == std::endian::little) {
    png_set_swap(png);  // 16-bit samples in the host's order
  }
  if (channels < 4) {
    png_set_strip_alpha(png);
  } else {
    png_set_tRNS_to_alpha(png);
  }
  if (h.color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if ((h.color_type & PNG_COLOR_MASK_COLOR) == 0 && h.bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  const bool colour_out = channels > 1;
  if ((h.color_type & PNG_COLOR_MASK_COLOR) != 0 && colour_out) {
    png_set_bgr(png);
  } else if (colour_out) {
    png_set_gray_to_rgb(png);
  } else {
    png_set_rgb_to_gray(png, 1, 0.299, 0.587);
  }
  h.passes = png_set_interlace_handling(png);
  png_read_update_info(png, info);
  return true;
}

/// Reads the rows into `out` (already sized by the header), every interlace
/// pass over the same rows. false: libpng reported an error.
bool read_rows(png_structp png, png_infop info, int passes, cv::Mat& out) {
  if (setjmp(png_jmpbuf(png)) != 0) return false;
  for (int pass = 0; pass < passes; ++pass) {
    for (int r = 0; r < out.rows; ++r) png_read_row(png, out.ptr<png_byte>(r), nullptr);
  }
  png_read_end(png, info);
  return true;
}

bool write_rows(png_structp png, png_infop info, std::FILE* f, const cv::Mat& image, int compression_level) {
  if (setjmp(png_jmpbuf(png)) != 0) return false;
  png_init_io(png, f);
  png_set_compression_level(png, compression_level);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.cols), static_cast<png_uint_32>(image.rows), 8,
               image.channels() == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (image.channels() == 3) png_set_bgr(png);
  for (int r = 0; r < image.rows; ++r) png_write_row(png, image.ptr<png_byte>(r));
  png_write_end(png, info);
  return true;
}

}  // namespace

PngRead read_png(const std::string& file, PngPixels pixels) {
  PngRead result;
  std::FILE* f = std::fopen(file.c_str(), "rb");
  if (f == nullptr) {
    result.error = std::string("cannot be opened: ") + std::strerror(errno);
    return result;
  }
  png_byte signature[8] = {};
  if (std::fread(signature, 1, sizeof signature, f) != sizeof signature || png_sig_cmp(signature, 0, 8) != 0) {
    std::fclose(f);
    result.error = "not a PNG file";
    return result;
  }
  PngMessages messages;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &messages, &on_png_error, &on_png_warning);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  PngHeader header;
  bool ok = info != nullptr && read_header(png, info, f, pixels, header);
  const bool too_large = ok && static_cast<double>(header.width) * header.height > kMaxPixels;
  if (ok && !too_large) {
    result.pixels.create(static_cast<int>(header.height), static_cast<int>(header.width), header.mat_type);
    ok = read_rows(png, info, header.passes, result.pixels);
  }
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(f);
  if (too_large) {
    result.error = "is " + std::to_string(header.width) + "x" + std::to_string(header.height) +
                   " px, more than the 2^30 pixels an image may have";
  } else if (!ok) {
    result.pixels.release();
    result.error = std::string("unreadable PNG: ") + (messages.error[0] != '\0' ? messages.error : "out of memory");
  }
  return result;
}

std::string write_png(const std::string& file, const cv::Mat& image, int compression_level) {
  if (image.empty() || (image.type() != CV_8UC1 && image.type() != CV_8UC3)) {
    return "write_png: only 8-bit grey or BGR images are written";
  }
  if (compression_level < 0 || compression_level > 9) return "write_png: compression level must be 0-9";
  std::FILE* f = std::fopen(file.c_str(), "wb");
  if (f == nullptr) return std::string("cannot be created: ") + std::strerror(errno);
  PngMessages messages;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &messages, &on_png_error, &on_png_warning);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  const bool ok = info != nullptr && write_rows(png, info, f, image, compression_level);
  png_destroy_write_struct(&png, &info);
  const bool closed = std::fclose(f) == 0;
  if (!ok) return std::string("PNG not written: ") + (messages.error[0] != '\0' ? messages.error : "out of memory");
  if (!closed) return std::string("PNG not written: ") + std::strerror(errno);
  return {};
}

}  // namespace gvs::drivers
