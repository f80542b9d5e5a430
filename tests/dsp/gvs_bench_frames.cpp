#include "gvs_bench_frames.hpp"

#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>

#include "gvs/dsp/gvs_estimator.hpp"

namespace gvs::bench {

namespace {

std::string photo_path(const char* file) {
  const char* env = std::getenv("GVS_SHARED_DIR");
  const std::string path = std::string(env != nullptr ? env : GVS_BENCH_SHARED_DIR) + "/testdata/real-asphalt/" + file;
  if (!std::filesystem::exists(path)) {
    throw std::runtime_error(path + " not found: set GVS_SHARED_DIR to the shared/ folder");
  }
  return path;
}

std::vector<dsp::FrameView> render(const FrameKind& kind, bool lasers) {
  drivers::SimulatorConfig cfg;
  cfg.seconds = 1.5;
  cfg.light = kind.light;
  if (kind.photo != nullptr) cfg.ground = "photo:" + photo_path(kind.photo);
  cfg.camera_height_mm = kLaserHeightMm;
  if (lasers) cfg.lasers = core::design_laser_geometry(cfg.camera, kLaserHeightMm);
  drivers::Simulator sim(cfg, drivers::sim::constant_motion_scenario(kind.vx_mps, kind.vy_mps, 0.0, 1.5));
  dsp::EstimatorConfig ec;
  ec.method = "gvs";
  ec.camera = cfg.camera;
  dsp::GvsEstimator est(ec);
  const dsp::ExposureLimits limits = dsp::exposure_limits_for(cfg.camera, cfg.fps);
  dsp::ExposurePlan plan;
  std::vector<dsp::FrameView> frames;
  drivers::SimFrame f;
  // The first 0.5 s let the exposure loop settle; the last second is kept.
  const std::size_t settle = sim.frame_count() - kFrames;
  for (std::size_t i = 0; sim.next(f); ++i) {
    const dsp::FrameView view{f.gray, f.record.index, f.record.t_ns, f.record.exposure};
    const dsp::VelocityEstimate e = est.estimate(view);
    if (i >= settle) frames.push_back({f.gray.clone(), f.record.index, f.record.t_ns, f.record.exposure});
    if (kind.mode != dsp::ExposureMode::fixed) {
      plan = dsp::next_exposure(e, plan, kind.mode, limits);
      sim.set_exposure(plan);
    }
  }
  return frames;
}

}  // namespace

const std::vector<dsp::FrameView>& frames_of(const FrameKind& kind) {
  static std::map<std::string, std::vector<dsp::FrameView>> cache;
  auto it = cache.find(kind.name);
  if (it == cache.end()) it = cache.emplace(kind.name, render(kind, /*lasers=*/false)).first;
  return it->second;
}

const std::vector<dsp::FrameView>& laser_frames_of(const FrameKind& kind) {
  static std::map<std::string, std::vector<dsp::FrameView>> cache;
  auto it = cache.find(kind.name);
  if (it == cache.end()) it = cache.emplace(kind.name, render(kind, /*lasers=*/true)).first;
  return it->second;
}

const FrameKind& kind_named(const char* name) {
  for (const FrameKind& k : kKinds) {
    if (std::strcmp(k.name, name) == 0) return k;
  }
  throw std::invalid_argument(std::string("no frame kind ") + name);
}

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

FftwR2c::FftwR2c(cv::Size size) : size_(size) {
  const auto n = static_cast<std::size_t>(size.area());
  const auto half = static_cast<std::size_t>(size.height) * static_cast<std::size_t>(size.width / 2 + 1);
  in_ = fftwf_alloc_real(n);
  out_ = fftwf_alloc_complex(half);
  plan_ = fftwf_plan_dft_r2c_2d(size.height, size.width, in_, out_, FFTW_MEASURE);
  if (plan_ == nullptr) throw std::runtime_error("FFTW could not plan the reference r2c");
}

FftwR2c::~FftwR2c() {
  fftwf_destroy_plan(plan_);
  fftwf_free(out_);
  fftwf_free(in_);
}

void FftwR2c::load(const cv::Mat& gray) {
  cv::Mat as_float(size_, CV_32F, in_);
  gray.convertTo(as_float, CV_32F);
}

double FftwR2c::ms_per_frame(const std::vector<dsp::FrameView>& frames, int laps) {
  double cpu_s = 0.0;
  int n = 0;
  for (int lap = 0; lap < laps; ++lap) {
    for (const dsp::FrameView& f : frames) {
      load(f.gray);
      const double t0 = thread_cpu_s();
      run();
      cpu_s += thread_cpu_s() - t0;
      ++n;
    }
  }
  return n > 0 ? 1e3 * cpu_s / n : 0.0;
}

}  // namespace gvs::bench
