#include "gvs/eval/replay.hpp"

#include <algorithm>
#include <chrono>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

namespace gvs::eval {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

ReplayStats replay_dataset(const drivers::DatasetReader& dataset, dsp::FrameProcessorConfig config,
                           const std::function<void(const core::VelocityEstimate&)>& sink,
                           const ReplayOptions& options) {
  config.estimator.camera = dataset.camera().geometry;
  // The dataset's lasers, unless the caller turned them off (count 0 and
  // use_dataset_lasers false) or brought its own.
  if (options.use_dataset_lasers && !config.lasers.enabled()) config.lasers = dataset.camera().lasers;
  config.nominal_height_mm = dataset.camera().height_mm.value_or(60.0);
  dsp::FrameProcessor processor(config);
  ReplayStats stats;
  cv::Mat as_float;
  cv::Mat spectrum;
  for (std::size_t i = 0; i < dataset.frames().size(); ++i) {
    const drivers::FrameRecord& record = dataset.frames()[i];
    auto t0 = std::chrono::steady_clock::now();
    core::FrameView frame;
    frame.gray = dataset.load_gray(i);
    frame.index = record.index;
    frame.t_ns = record.t_ns;
    frame.exposure = record.exposure;
    stats.decode_s += seconds_since(t0);

    t0 = std::chrono::steady_clock::now();
    const core::VelocityEstimate e = processor.process(frame);
    stats.estimate_s += seconds_since(t0);

    if (options.time_reference_dft) {
      t0 = std::chrono::steady_clock::now();
      frame.gray.convertTo(as_float, CV_32F);
      cv::dft(as_float, spectrum, cv::DFT_COMPLEX_OUTPUT);
      stats.dft_s += seconds_since(t0);
    }
    ++stats.frames;
    if (e.quality > 0.0) ++stats.with_estimate;
    sink(e);
    if (options.dots_sink) options.dots_sink(e, processor.last_dots());
  }
  const std::size_t n = dataset.frames().size();
  if (options.stage_pairs > 0 && n >= 2) {
    // Pairs (i, i + 1) spread evenly over the run, so every kind of frame
    // the run holds is in the breakdown about as often as in the run.
    const std::size_t count = std::min(options.stage_pairs, n / 2);
    std::vector<std::pair<cv::Mat, cv::Mat>> pairs;
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t i = k * (n - 1) / count;
      pairs.emplace_back(dataset.load_gray(i), dataset.load_gray(i + 1));
    }
    // The laser_dots stage runs where the processor found dots (make_stage_inputs drops a head without beams).
    const LaserStageSetup head{config.estimator.camera, config.nominal_height_mm, config.lasers};
    stats.stages = time_estimator_stages(make_stage_inputs(pairs, head));
    stats.stage_pairs = count;
  }
  return stats;
}

}  // namespace gvs::eval
