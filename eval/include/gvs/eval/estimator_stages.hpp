// The gvs estimator's stages, each run alone on prepared frames: one table
// that the Google Benchmark (tests/dsp/gvs_stage_bench.cpp) and
// `gvs replay --timing` both time, so they report the same breakdown
// (docs/performance.md, "Against FFTW's real-to-complex transform, per stage").
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "gvs/core/frame.hpp"
#include "gvs/core/laser_geometry.hpp"

namespace gvs::eval {

/// The head whose laser dots the frames show (the laser_dots stage).
struct LaserStageSetup {
  core::CameraGeometry camera;
  double nominal_height_mm = 60.0;
  core::LaserGeometry lasers;
};

/// Frames in consecutive pairs (0-1, 2-3, ...: the pair stages correlate
/// each pair), and what the stages start from.
struct StageInputs {
  cv::Size size;
  std::vector<cv::Mat> gray;      ///< CV_8U frames, an even count
  std::vector<cv::Mat> windowed;  ///< CV_32F, mean out, Tukey window (what WindowedSpectrum transforms)
  std::vector<cv::Mat> spectrum;  ///< CV_32FC2, WindowedSpectrum (Tukey, the full spectrum)
  std::optional<LaserStageSetup> lasers;  ///< set when the frames show laser dots
};

/// `pairs`: frame pairs (each two consecutive frames of one size, CV_8U).
/// `lasers`: the head, when the frames show its laser dots (one without
/// beams counts as none). Throws
/// std::invalid_argument when empty or of mixed sizes.
StageInputs make_stage_inputs(const std::vector<std::pair<cv::Mat, cv::Mat>>& pairs,
                              std::optional<LaserStageSetup> lasers = std::nullopt);

/// One stage: `prepare` builds its workspaces (not timed) and returns the
/// step to time, run on input i (0 .. steps(inputs) - 1); the step reads
/// the inputs it was prepared on, which must outlive it.
struct EstimatorStage {
  const char* name;         ///< e.g. "streak_axis"
  const char* kind;         ///< the benchmark's frame kind whose path runs it
  const char* description;  ///< what is timed, for tables
  std::function<std::function<void(std::size_t)>(const StageInputs&)> prepare;
  /// How many distinct steps the inputs give (frames, or pairs; 0: the
  /// stage does not run on them).
  std::function<std::size_t(const StageInputs&)> steps;
  /// Runs on frames that show the laser dots (StageInputs::lasers), none without.
  bool needs_lasers = false;
};

/// Every stage, in the frame's order: the laser dots (found and masked
/// before the estimator sees the frame), transforms, spectra, the pair,
/// the passes over one frame's spectrum.
const std::vector<EstimatorStage>& estimator_stages();

struct StageTime {
  std::string name;
  std::string description;
  double cpu_ms = 0.0;  ///< thread CPU time per step
  std::size_t steps = 0;
};

/// Each stage on `inputs`, round and round for at least `min_seconds` of
/// CPU time and 3 rounds: CPU time per step (the benchmark's CPU column).
std::vector<StageTime> time_estimator_stages(const StageInputs& inputs, double min_seconds = 0.2);

}  // namespace gvs::eval
