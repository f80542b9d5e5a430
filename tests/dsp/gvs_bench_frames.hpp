// The frames the estimator benchmark feeds (gvs_estimator_bench.cpp,
// gvs_stage_bench.cpp), and the yardstick it measures them against: FFTW's
// real-to-complex transform of the same frames (issue #22: "at most 3x").
#pragma once

#include <vector>

#include <fftw3.h>
#include <opencv2/core/mat.hpp>

#include "gvs/drivers/simulator.hpp"
#include "gvs/dsp/estimator.hpp"
#include "gvs/dsp/exposure_control.hpp"

namespace gvs::bench {

struct FrameKind {
  const char* name;
  double vx_mps;
  double vy_mps;
  dsp::ExposureMode mode;  ///< fixed: 3 ms continuous light
  drivers::LightLevel light = drivers::LightLevel::normal;
  /// A photograph of ../shared/testdata/real-asphalt for the ground (its
  /// file name), or null for the procedural asphalt.
  const char* photo = nullptr;
};

// sharp pair: 1.8 km/h, consecutive frames overlap (pair correlation);
// blurred: 54 km/h with 3 ms, the streak is longer than the frame (direction only);
// strobed: 108 km/h, one strobe keeping the streak 10-80 px;
// double pulse: 108 km/h, two short pulses;
// dark: blurred, under-exposed (the spectrum with the pixel pattern out and
// the ring gain's passes, docs/estimator.md "Dark frames");
// blurred photo: as blurred, on the photograph ph_asphalt_04 (its streak
// ends and spectra take the longer paths: docs/performance.md).
inline constexpr FrameKind kKinds[] = {
    {"sharp_pair", 0.5, 0.02, dsp::ExposureMode::fixed},
    {"blurred", 15.0, 0.8, dsp::ExposureMode::fixed},
    {"strobed", 30.0, 1.5, dsp::ExposureMode::adaptive},
    {"double_pulse", 30.0, 1.5, dsp::ExposureMode::double_pulse},
    {"dark", 15.0, 0.8, dsp::ExposureMode::fixed, drivers::LightLevel::under},
    {"blurred_photo", 15.0, 0.8, dsp::ExposureMode::fixed, drivers::LightLevel::normal, "ph_asphalt_04_1024.png"},
};

inline constexpr int kFrames = 60;
/// The height the frames are rendered at (drivers::SimulatorConfig's
/// default camera_height_mm), nominal for the laser dots' finder.
inline constexpr double kLaserHeightMm = 60.0;

/// The last kFrames frames (512x384) of 1.5 s of the simulator at the kind's
/// constant velocity, with the exposure the gvs closed loop chose; rendered
/// on the first call and kept. A kind on a photograph reads it from
/// $GVS_SHARED_DIR (default: the build's GVS_SHARED_DIR, ../shared beside
/// the checkout) and throws std::runtime_error naming the file when it is
/// not there.
const std::vector<dsp::FrameView>& frames_of(const FrameKind& kind);
/// The same with the design's four laser dots lit (gvs sim --lasers).
const std::vector<dsp::FrameView>& laser_frames_of(const FrameKind& kind);
const FrameKind& kind_named(const char* name);

/// CPU time of the calling thread (what Google Benchmark's "CPU" column counts).
double thread_cpu_s();

/// FFTW single-precision r2c of a whole frame, planned once with
/// FFTW_MEASURE (Debian's libfftw3): the reference cost.
class FftwR2c {
 public:
  explicit FftwR2c(cv::Size size);
  ~FftwR2c();
  FftwR2c(const FftwR2c&) = delete;
  FftwR2c& operator=(const FftwR2c&) = delete;

  /// Half spectrum of `gray` (CV_8UC1 of the planned size), converted to float first (untimed).
  void load(const cv::Mat& gray);
  void run() { fftwf_execute(plan_); }
  /// Mean CPU ms per transform over every frame of `frames`, `laps` times.
  double ms_per_frame(const std::vector<dsp::FrameView>& frames, int laps);

 private:
  cv::Size size_;
  float* in_ = nullptr;
  fftwf_complex* out_ = nullptr;
  fftwf_plan plan_ = nullptr;
};

}  // namespace gvs::bench
