// Is there anything to measure in a frame? Dark, saturated and featureless
// frames give no estimate (quality 0, method names the reason).
#pragma once

#include <optional>

#include <opencv2/core/mat.hpp>

#include "gvs/dsp/vocabulary.hpp"

namespace gvs::dsp {

/// Grey-level statistics of one 8-bit frame (every 2nd pixel of every 2nd row).
struct FrameStats {
  double mean_grey = 0.0;
  double contrast_grey = 0.0;       ///< standard deviation of the unsaturated pixels
  double saturated_fraction = 0.0;  ///< pixels at 255
};

struct FrameCheckLimits {
  double dark_mean_grey = 2.0;         ///< below: "dark"
  double max_saturated_fraction = 0.6; ///< above: "saturated"
  double min_contrast_grey = 0.8;      ///< below: "no-texture" (or "dark" when the mean is low too)
};

FrameStats measure_frame(const cv::Mat& gray);

/// Nothing when the frame is usable, else the reason: Method::dark, Method::saturated or Method::no_texture.
std::optional<Method> frame_problem(const FrameStats& stats, const FrameCheckLimits& limits = {});

}  // namespace gvs::dsp
