// The estimator's stages, run alone (see estimator_stages.hpp).
#include "gvs/eval/estimator_stages.hpp"

#include <ctime>
#include <memory>
#include <stdexcept>
#include <utility>

#include <opencv2/core.hpp>

#include "gvs/dsp/blur_analysis.hpp"
#include "gvs/dsp/dft.hpp"
#include "gvs/dsp/gvs_analysis.hpp"
#include "gvs/dsp/gvs_settings.hpp"
#include "gvs/dsp/laser_dots.hpp"
#include "gvs/dsp/phase_correlation.hpp"
#include "gvs/dsp/spectrum.hpp"

namespace gvs::eval {

namespace {

// Results go here so that the compiler keeps the work that made them.
volatile double g_sink = 0.0;

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

using Step = std::function<void(std::size_t)>;

std::size_t frames(const StageInputs& in) { return in.gray.size(); }
std::size_t pairs(const StageInputs& in) { return in.gray.size() / 2; }

// The half the estimator's spectra hold (BlurAnalyzer and the phase
// correlation read no more).
constexpr auto kHalf = dsp::DftPlan::Direction::forward_real_to_half_complex;

std::vector<EstimatorStage> make_stages() {
  const dsp::GvsEstimatorSettings set;
  std::vector<EstimatorStage> s;
  // --- the laser dots, as dsp::FrameProcessor: the frame copied, the dots
  // found in the copy and masked there (each frame on its own: no step 5) ---
  s.push_back({"laser_dots", "double_pulse", "laser dots: frame copied, dots found and masked",
               [](const StageInputs& in) -> Step {
                 const LaserStageSetup& head = *in.lasers;
                 auto finder = std::make_shared<dsp::LaserDotFinder>(head.camera, head.nominal_height_mm, head.lasers);
                 auto copy = std::make_shared<cv::Mat>(in.size, CV_8UC1);
                 return [&in, finder, copy](std::size_t i) {
                   g_sink = finder->find_and_mask(in.gray[i], *copy).ride.height_mm;
                 };
               },
               [](const StageInputs& in) { return in.lasers ? frames(in) : std::size_t{0}; }, true});
  // --- the transforms ---
  s.push_back({"dft_plan_forward", "blurred", "`DftPlan` forward: FFTW_ESTIMATE r2c and the mirrored half",
               [](const StageInputs& in) -> Step {
                 auto plan = std::make_shared<dsp::DftPlan>(dsp::DftPlan::Direction::forward_real_to_complex, in.size);
                 auto out = std::make_shared<cv::Mat>();
                 return [&in, plan, out](std::size_t i) { plan->run(in.windowed[i], *out); };
               },
               frames});
  s.push_back({"dft_plan_forward_half", "blurred", "`DftPlan` forward, columns 0 .. cols/2 only (the estimator's)",
               [](const StageInputs& in) -> Step {
                 auto plan = std::make_shared<dsp::DftPlan>(kHalf, in.size);
                 auto out = std::make_shared<cv::Mat>();
                 return [&in, plan, out](std::size_t i) { plan->run(in.windowed[i], *out); };
               },
               frames});
  s.push_back({"dft_plan_inverse", "blurred", "`DftPlan` inverse, c2r",
               [](const StageInputs& in) -> Step {
                 auto plan = std::make_shared<dsp::DftPlan>(dsp::DftPlan::Direction::inverse_complex_to_real, in.size);
                 auto out = std::make_shared<cv::Mat>();
                 return [&in, plan, out](std::size_t i) { plan->run(in.spectrum[i], *out); };
               },
               frames});
  // --- spectra: window, mean and forward DFT ---
  s.push_back({"windowed_spectrum", "blurred", "windowed spectrum: mean out, Tukey window, forward",
               [](const StageInputs& in) -> Step {
                 auto tukey = std::make_shared<dsp::WindowedSpectrum>(in.size, dsp::kWindowTaper, kHalf);
                 auto out = std::make_shared<cv::Mat>();
                 return [&in, tukey, out](std::size_t i) { tukey->compute(in.gray[i], *out); };
               },
               frames});
  s.push_back({"windowed_spectrum_pixel_pattern", "dark", "windowed spectrum with the pixel pattern out",
               [](const StageInputs& in) -> Step {
                 auto tukey = std::make_shared<dsp::WindowedSpectrum>(in.size, dsp::kWindowTaper, kHalf);
                 auto offsets = std::make_shared<cv::Mat>(in.size, CV_32F, cv::Scalar(1.0));
                 auto out = std::make_shared<cv::Mat>();
                 return [&in, tukey, offsets, out](std::size_t i) { tukey->compute(in.gray[i], *out, *offsets); };
               },
               frames});
  // --- frame pair: two half-window spectra and two phase correlations ---
  s.push_back({"pair_half_spectra", "sharp_pair", "the pair's two half-window spectra",
               [](const StageInputs& in) -> Step {
                 auto ws = std::make_shared<dsp::PairWorkspace>(in.size);
                 return [&in, ws](std::size_t i) {
                   ws->half_spectrum.compute(in.gray[i](ws->left), ws->current.left);
                   ws->half_spectrum.compute(in.gray[i](ws->right), ws->current.right);
                 };
               },
               frames});
  s.push_back({"pair_phase_correlation", "sharp_pair", "the pair's two phase correlations",
               [set](const StageInputs& in) -> Step {
                 auto ws = std::make_shared<dsp::PairWorkspace>(in.size);
                 auto halves = std::make_shared<std::vector<dsp::HalfSpectra>>(in.gray.size());
                 for (std::size_t i = 0; i < in.gray.size(); ++i) {
                   ws->half_spectrum.compute(in.gray[i](ws->left), (*halves)[i].left);
                   ws->half_spectrum.compute(in.gray[i](ws->right), (*halves)[i].right);
                 }
                 return [ws, halves, set](std::size_t i) {
                   const dsp::HalfSpectra& a = (*halves)[2 * i];
                   const dsp::HalfSpectra& b = (*halves)[2 * i + 1];
                   g_sink = ws->correlator.correlate(a.left, b.left, set.pair_exclude_px, set.pair_max_shift_px).peak +
                            ws->correlator.correlate(a.right, b.right, set.pair_exclude_px, set.pair_max_shift_px).peak;
                 };
               },
               pairs});
  // --- one frame: passes over the power spectrum ---
  s.push_back({"noise_floor", "blurred", "noise floor",
               [](const StageInputs& in) -> Step {
                 auto blur = std::make_shared<dsp::BlurAnalyzer>(in.size);
                 return [&in, blur](std::size_t i) { g_sink = blur->noise_floor(in.spectrum[i]); };
               },
               frames});
  s.push_back({"ring_gain", "dark", "ring gain",
               [](const StageInputs& in) -> Step {
                 auto blur = std::make_shared<dsp::BlurAnalyzer>(in.size);
                 auto gain = std::make_shared<dsp::BlurAnalyzer::RingGain>();
                 return [&in, blur, gain](std::size_t i) {
                   blur->ring_gain(in.spectrum[i], nullptr, 0.0, *gain);
                   g_sink = (*gain)[0];
                 };
               },
               frames});
  s.push_back({"streak_axis", "blurred", "streak axis",
               [](const StageInputs& in) -> Step {
                 auto blur = std::make_shared<dsp::BlurAnalyzer>(in.size);
                 return [&in, blur](std::size_t i) { g_sink = blur->streak_axis(in.spectrum[i]).u_row; };
               },
               frames});
  s.push_back({"refine_axis", "blurred", "axis refinement (from the streak axis, not timed)",
               [set](const StageInputs& in) -> Step {
                 auto blur = std::make_shared<dsp::BlurAnalyzer>(in.size);
                 auto axes = std::make_shared<std::vector<dsp::StreakAxis>>();
                 for (const cv::Mat& sp : in.spectrum) axes->push_back(blur->streak_axis(sp));
                 return [&in, blur, axes, set](std::size_t i) {
                   g_sink = blur->refine_axis(in.spectrum[i], (*axes)[i], set.refine_sigma, 2, true).u_row;
                 };
               },
               frames});
  s.push_back({"streak_length", "strobed", "streak length",
               [set](const StageInputs& in) -> Step {
                 auto blur = std::make_shared<dsp::BlurAnalyzer>(in.size);
                 auto axes = std::make_shared<std::vector<dsp::StreakAxis>>();
                 for (const cv::Mat& sp : in.spectrum) axes->push_back(blur->streak_axis(sp));
                 return [&in, blur, axes, set](std::size_t i) {
                   g_sink = blur->streak_length(in.spectrum[i], (*axes)[i], set.min_streak_search_px, 300.0).length_px;
                 };
               },
               frames});
  s.push_back({"streak_length_cepstral", "strobed", "streak length from the power cepstrum (faint or rival ends)",
               [set](const StageInputs& in) -> Step {
                 auto blur = std::make_shared<dsp::BlurAnalyzer>(in.size);
                 auto axes = std::make_shared<std::vector<dsp::StreakAxis>>();
                 for (const cv::Mat& sp : in.spectrum) axes->push_back(blur->streak_axis(sp));
                 return [&in, blur, axes, set](std::size_t i) {
                   g_sink =
                       blur->streak_length_cepstral(in.spectrum[i], (*axes)[i], set.min_streak_search_px, 300.0).length_px;
                 };
               },
               frames});
  s.push_back({"streak_anisotropy", "strobed", "the anisotropy a streak would give this ground (cold ends)",
               [](const StageInputs& in) -> Step {
                 auto blur = std::make_shared<dsp::BlurAnalyzer>(in.size);
                 auto axes = std::make_shared<std::vector<dsp::StreakAxis>>();
                 for (const cv::Mat& sp : in.spectrum) axes->push_back(blur->streak_axis(sp));
                 return [&in, blur, axes](std::size_t i) {
                   g_sink = blur->streak_anisotropy(in.spectrum[i], (*axes)[i], 60.0);
                 };
               },
               frames});
  s.push_back({"double_image", "double_pulse", "double image",
               [](const StageInputs& in) -> Step {
                 auto blur = std::make_shared<dsp::BlurAnalyzer>(in.size);
                 return [&in, blur](std::size_t i) {
                   g_sink = blur->double_image(in.spectrum[i], 4.0, 200.0).d_row_px;
                 };
               },
               frames});
  s.push_back({"double_image_asymmetry", "double_pulse", "double image asymmetry",
               [](const StageInputs& in) -> Step {
                 dsp::BlurAnalyzer blur(in.size);
                 auto found = std::make_shared<std::vector<dsp::DoubleImage>>();
                 for (const cv::Mat& sp : in.spectrum) found->push_back(blur.double_image(sp, 4.0, 200.0));
                 return [&in, found](std::size_t i) {
                   dsp::double_image_asymmetry(in.gray[i], (*found)[i]);
                   g_sink = (*found)[i].asymmetry;
                 };
               },
               frames});
  return s;
}

}  // namespace

StageInputs make_stage_inputs(const std::vector<std::pair<cv::Mat, cv::Mat>>& frame_pairs,
                              std::optional<LaserStageSetup> lasers) {
  if (frame_pairs.empty()) throw std::invalid_argument("estimator stages: no frames to time the stages on");
  StageInputs in;
  in.size = frame_pairs.front().first.size();
  if (lasers && lasers->lasers.enabled()) in.lasers = std::move(lasers);
  dsp::WindowedSpectrum tukey(in.size);
  const cv::Mat window = dsp::spectrum_window(in.size, CV_32F);
  for (const auto& [a, b] : frame_pairs) {
    for (const cv::Mat* g : {&a, &b}) {
      if (g->size() != in.size || g->type() != CV_8UC1) {
        throw std::invalid_argument("estimator stages: frames of mixed sizes or not 8-bit grey");
      }
      in.gray.push_back(*g);
      cv::Mat f;
      g->convertTo(f, CV_32F);
      f -= cv::mean(f);
      in.windowed.push_back(f.mul(window));
      cv::Mat s;
      tukey.compute(*g, s);
      in.spectrum.push_back(s);
    }
  }
  return in;
}

const std::vector<EstimatorStage>& estimator_stages() {
  static const std::vector<EstimatorStage> stages = make_stages();
  return stages;
}

std::vector<StageTime> time_estimator_stages(const StageInputs& inputs, double min_seconds) {
  std::vector<StageTime> out;
  for (const EstimatorStage& stage : estimator_stages()) {
    const std::size_t n = stage.steps(inputs);
    if (n == 0) continue;
    const auto step = stage.prepare(inputs);
    step(0);  // first touch of the workspaces, not timed
    const double t0 = thread_cpu_s();
    std::size_t done = 0;
    for (int round = 0; round < 3 || thread_cpu_s() - t0 < min_seconds; ++round) {
      for (std::size_t i = 0; i < n; ++i) step(i);
      done += n;
    }
    out.push_back({stage.name, stage.description, (thread_cpu_s() - t0) / static_cast<double>(done) * 1e3, n});
  }
  return out;
}

}  // namespace gvs::eval
