// Replay: every frame of a dataset, in order, through the daemon's
// dsp::FrameProcessor (what `gvs replay` runs).
#pragma once

#include <cstddef>
#include <functional>

#include "gvs/dsp/frame_processor.hpp"
#include "gvs/drivers/dataset.hpp"
#include "gvs/core/estimate.hpp"

namespace gvs::eval {

struct ReplayStats {
  std::size_t frames = 0;
  std::size_t with_estimate = 0;  ///< quality > 0
  double decode_s = 0.0;          ///< reading and decoding the PNGs
  double estimate_s = 0.0;        ///< dsp::FrameProcessor::process
  double dft_s = 0.0;             ///< the reference cost: one forward DFT per frame (if asked)
};

struct ReplayOptions {
  bool time_reference_dft = false;  ///< also time one cv::dft per frame, in the same run
  /// Find the laser dots of camera.json's "lasers" (if any).
  bool use_dataset_lasers = true;
  /// Called after `sink` with each frame's laser dots (if set).
  std::function<void(const core::VelocityEstimate&, const dsp::LaserDotResult&)> dots_sink;
};

/// Runs the processor over every frame in `dataset`; `sink` gets each estimate
/// in frame order. The processor takes its camera geometry from the dataset.
/// Throws drivers::DatasetError for unreadable frames.
ReplayStats replay_dataset(const drivers::DatasetReader& dataset, dsp::FrameProcessorConfig config,
                           const std::function<void(const core::VelocityEstimate&)>& sink,
                           const ReplayOptions& options = {});

}  // namespace gvs::eval
