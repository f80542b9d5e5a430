#include "gvs/eval/replay.hpp"

#include <chrono>

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
  return stats;
}

}  // namespace gvs::eval
