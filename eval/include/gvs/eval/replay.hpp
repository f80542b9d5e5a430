// Replay: every frame of a dataset, in order, through the daemon's
// dsp::FrameProcessor (what `gvs replay` runs).
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "gvs/dsp/frame_processor.hpp"
#include "gvs/drivers/dataset.hpp"
#include "gvs/core/estimate.hpp"
#include "gvs/eval/estimator_stages.hpp"

namespace gvs::eval {

struct ReplayStats {
  std::size_t frames = 0;
  std::size_t with_estimate = 0;  ///< quality > 0
  double decode_s = 0.0;          ///< reading and decoding the PNGs
  double estimate_s = 0.0;        ///< dsp::FrameProcessor::process
  double dft_s = 0.0;             ///< the reference cost: one forward DFT per frame (if asked)
  /// Each estimator stage alone on pairs of the dataset's frames (if asked):
  /// the breakdown the benchmark gives (estimator_stages.hpp).
  std::vector<StageTime> stages;
  std::size_t stage_pairs = 0;  ///< how many frame pairs the stages ran on
};

struct ReplayOptions {
  bool time_reference_dft = false;  ///< also time one cv::dft per frame, in the same run
  /// After the run, time each estimator stage alone on up to this many
  /// pairs of consecutive frames spread over the dataset (0: not at all).
  std::size_t stage_pairs = 0;
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
