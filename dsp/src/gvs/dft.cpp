// DftPlan (see dft.hpp) on FFTW single precision.
//
// FFTW's r2c of an R x C real image gives the half spectrum H(r, c) for
// c = 0 .. C/2 (C/2 + 1 columns); the other columns follow from the
// conjugate symmetry of a real signal's spectrum,
//   X(r, c) = conj(X((R - r) mod R, C - c)),
// and its c2r reads only that half (FFTW manual, 3.3.10, sections 4.3.4
// "Real-data DFT Array Format" and 4.8.2 "The 1d Real-data DFT"). FFTW's
// transforms are unnormalised in both directions, like cv::dft's; the inverse
// here is scaled by 1/(R C) like cv::dft's DFT_SCALE.
#include "gvs/dsp/dft.hpp"

#include <algorithm>
#include <complex>
#include <cstddef>
#include <mutex>
#include <stdexcept>
#include <string>

#include <fftw3.h>
#include <opencv2/core.hpp>

namespace gvs::dsp {

namespace {

// FFTW's planner (fftwf_plan_*, fftwf_destroy_plan) shares global state
// (wisdom, twiddle tables) and is not thread-safe; executing a plan is
// (FFTW manual, 5.4 "Thread safety"). Estimators are built on several
// threads (gvsd's processing thread, the tests), so the planner runs under
// this lock: at setup only, never on the real-time path. The one mutex in
// dsp/, for a library's global state, not for our own threads.
std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}

// FFTW_ESTIMATE, not FFTW_MEASURE: FFTW_MEASURE times candidate algorithms
// while planning, so two runs of the same program may pick different ones
// and round differently, and the same dataset would no longer replay to the
// same estimates (the tests compare replays byte for byte). It also takes
// about 1.2 s per size and direction here, in every process. FFTW_ESTIMATE
// plans in milliseconds and always the same way; its transforms cost about
// 1.3x FFTW_MEASURE's at 512x384 (docs/performance.md, "Estimator per frame
// kind and per stage").
constexpr unsigned kPlannerFlags = FFTW_ESTIMATE;

// FFTW_NO_BUFFERING (fftw3.h; not in the manual): FFTW's buffered solvers
// allocate their buffers on every execute (here 1 a transform at 256x192, 65
// at 128x96, 321 at 640x480), and the real-time path must not allocate
// (gvsd_alloc_tests). Without them the estimator's sizes (even, small
// factors) still plan (at 512x384 and 320x384 the very plans FFTW makes
// with them); a size that has no plan without buffering (e.g. 33x17) gets
// one with it, which may allocate.
constexpr unsigned kNoAllocation = FFTW_NO_BUFFERING;

struct FftwFree {
  void operator()(void* p) const { fftwf_free(p); }
};

}  // namespace

struct DftPlan::Fftw {
  cv::Size size;
  int half_cols = 0;  ///< C/2 + 1
  fftwf_plan plan = nullptr;
  std::unique_ptr<fftwf_complex[], FftwFree> half;  ///< the half spectrum, rows x half_cols
  /// The real image, for arrays FFTW cannot take in place of the planned
  /// ones (not continuous, or aligned otherwise than fftwf_malloc's SIMD
  /// alignment): made the first time one comes.
  std::unique_ptr<float[], FftwFree> real;

  ~Fftw() {
    if (plan != nullptr) {
      const std::lock_guard<std::mutex> lock(planner_mutex());
      fftwf_destroy_plan(plan);
    }
  }

  [[nodiscard]] std::size_t real_count() const { return static_cast<std::size_t>(size.area()); }
  [[nodiscard]] std::size_t half_count() const {
    return static_cast<std::size_t>(size.height) * static_cast<std::size_t>(half_cols);
  }
  float* real_buffer() {
    if (!real) real.reset(fftwf_alloc_real(real_count()));
    return real.get();
  }
};

namespace {

// Whether FFTW may read or write `m` directly with a plan made on
// fftwf_malloc'd arrays: one block, with their SIMD alignment (fftw3.h,
// fftwf_alignment_of; cv::Mat's buffers are 64-byte aligned).
bool fftw_can_use(const cv::Mat& m) {
  return m.isContinuous() && fftwf_alignment_of(const_cast<float*>(m.ptr<float>())) == 0;
}

}  // namespace

DftPlan::DftPlan(Direction direction) : direction_(direction) {}

DftPlan::DftPlan(Direction direction, cv::Size size) : direction_(direction) { plan(size); }

DftPlan::~DftPlan() = default;
DftPlan::DftPlan(DftPlan&&) noexcept = default;
DftPlan& DftPlan::operator=(DftPlan&&) noexcept = default;

void DftPlan::plan(cv::Size size) {
  if (size.width < 1 || size.height < 1) {
    throw std::invalid_argument("DftPlan: cannot plan a transform of an empty image");
  }
  auto f = std::make_unique<Fftw>();
  f->size = size;
  f->half_cols = size.width / 2 + 1;
  f->half.reset(fftwf_alloc_complex(f->half_count()));
  // Planned on a real array of our own; run() passes the caller's when it can
  // (same alignment: fftwf_execute_dft_r2c/c2r with new arrays).
  std::unique_ptr<float[], FftwFree> planning_real(fftwf_alloc_real(f->real_count()));
  if (!f->half || !planning_real) throw std::bad_alloc();
  const auto make = [&](unsigned flags) {
    return direction_ != Direction::inverse_complex_to_real
               ? fftwf_plan_dft_r2c_2d(size.height, size.width, planning_real.get(), f->half.get(),
                                       flags | FFTW_PRESERVE_INPUT)
               : fftwf_plan_dft_c2r_2d(size.height, size.width, f->half.get(), planning_real.get(),
                                       flags | FFTW_DESTROY_INPUT);
  };
  {
    const std::lock_guard<std::mutex> lock(planner_mutex());
    f->plan = make(kPlannerFlags | kNoAllocation);
    if (f->plan == nullptr) f->plan = make(kPlannerFlags);
  }
  if (f->plan == nullptr) {
    throw std::runtime_error("DftPlan: FFTW could not plan a " + std::to_string(size.width) + "x" +
                             std::to_string(size.height) + " transform");
  }
  fftw_ = std::move(f);
}

void DftPlan::run(const cv::Mat& in, cv::Mat& out) {
  const bool forward = direction_ != Direction::inverse_complex_to_real;
  CV_Assert(in.type() == (forward ? CV_32FC1 : CV_32FC2));
  if (!fftw_ || fftw_->size != in.size()) plan(in.size());
  Fftw& f = *fftw_;
  out.create(in.size(), forward ? CV_32FC2 : CV_32FC1);
  const int rows = in.rows;
  const int cols = in.cols;
  const int hc = f.half_cols;
  auto* half = reinterpret_cast<std::complex<float>*>(f.half.get());

  if (forward) {
    const float* src = in.ptr<float>();
    if (!fftw_can_use(in)) {
      float* real = f.real_buffer();
      for (int r = 0; r < rows; ++r) std::copy_n(in.ptr<float>(r), cols, real + static_cast<std::ptrdiff_t>(r) * cols);
      src = real;
    }
    // FFTW_PRESERVE_INPUT: the caller's image is only read.
    fftwf_execute_dft_r2c(f.plan, const_cast<float*>(src), f.half.get());
    // The half as it is, and for the full spectrum the rest its conjugate mirror.
    const bool full = direction_ == Direction::forward_real_to_complex;
    for (int r = 0; r < rows; ++r) {
      const std::complex<float>* h = half + static_cast<std::ptrdiff_t>(r) * hc;
      auto* o = out.ptr<std::complex<float>>(r);
      std::copy_n(h, hc, o);
      if (!full) continue;
      const std::complex<float>* mirror = half + static_cast<std::ptrdiff_t>((rows - r) % rows) * hc;
      for (int c = hc; c < cols; ++c) o[c] = std::conj(mirror[cols - c]);
    }
    return;
  }

  // Inverse: the half the c2r reads, scaled here (C/2 + 1 columns, not C).
  const float scale = 1.0f / static_cast<float>(static_cast<double>(rows) * cols);
  for (int r = 0; r < rows; ++r) {
    const auto* x = in.ptr<std::complex<float>>(r);
    std::complex<float>* h = half + static_cast<std::ptrdiff_t>(r) * hc;
    for (int c = 0; c < hc; ++c) h[c] = x[c] * scale;
  }
  if (fftw_can_use(out)) {
    fftwf_execute_dft_c2r(f.plan, f.half.get(), out.ptr<float>());
    return;
  }
  float* real = f.real_buffer();
  fftwf_execute_dft_c2r(f.plan, f.half.get(), real);
  for (int r = 0; r < rows; ++r) std::copy_n(real + static_cast<std::ptrdiff_t>(r) * cols, cols, out.ptr<float>(r));
}

}  // namespace gvs::dsp
