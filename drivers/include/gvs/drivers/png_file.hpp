// PNG files through libpng, so that neither gvsd nor gvs links OpenCV's
// imgcodecs (which brings GDAL, Poppler, HDF5 and a hundred more libraries,
// see docs/performance.md). Reading gives exactly the pixels cv::imread gives
// with the matching flag: the same libpng transforms, in the same order.
// Set-up and desk code: it allocates, and reports failure by return value.
#pragma once

#include <string>

#include <opencv2/core/mat.hpp>

namespace gvs::drivers {

/// Which pixels read_png returns, named after the cv::imread flag it matches.
enum class PngPixels {
  /// cv::IMREAD_GRAYSCALE: always CV_8UC1; colour is turned grey by libpng
  /// (0.299 R + 0.587 G + 0.114 B), 16-bit keeps its high byte, alpha is dropped.
  grey,
  /// cv::IMREAD_UNCHANGED: CV_8U or CV_16U; 1 channel (grey), 3 (BGR) or
  /// 4 (BGRA: the file has alpha or a tRNS chunk). Grey with alpha becomes BGRA.
  unchanged,
};

/// The outcome of read_png: `pixels` is empty when the file could not be
/// read, and `error` then says why (missing, not a PNG, truncated, corrupt).
struct PngRead {
  cv::Mat pixels;
  std::string error;
};

/// Reads the PNG file `file`.
[[nodiscard]] PngRead read_png(const std::string& file, PngPixels pixels);

/// Writes `image` to `file` as a PNG: CV_8UC1 as 8-bit grey, CV_8UC3 (BGR)
/// as 8-bit RGB. `compression_level` is zlib's 0 (none) to 9 (smallest); 1,
/// the fastest, is what the dataset writer uses. Returns an empty string on
/// success, else what went wrong.
[[nodiscard]] std::string write_png(const std::string& file, const cv::Mat& image, int compression_level = 1);

}  // namespace gvs::drivers
