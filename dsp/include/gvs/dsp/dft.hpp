// The discrete Fourier transform, planned once.
//
// FFTW single precision (fftw3f) underneath: the forward transform of a
// 512x384 frame takes less than half of cv::dft's time here
// (docs/performance.md, "Estimator per frame kind and per stage"). The
// layout stays OpenCV's: the forward transform gives the full complex
// spectrum (CV_32FC2, every bin), filled from FFTW's half spectrum by
// conjugate symmetry, so every consumer reads the spectrum as before;
// consumers that read only the columns 0 .. cols/2 ask for those alone.
//
// A plan and its buffers are made at construction (with a size) or on the
// first run, and again only if the size changes: every later run allocates
// nothing, which is what the daemon's processing thread needs.
#pragma once

#include <memory>

#include <opencv2/core/mat.hpp>

namespace gvs::dsp {

class DftPlan {
 public:
  enum class Direction {
    forward_real_to_complex,  ///< CV_32FC1 image -> CV_32FC2 full complex spectrum
    /// CV_32FC1 image -> CV_32FC2 of the image's size with only the columns
    /// 0 .. cols/2 written (the rest is their mirror, which the inverse and
    /// the phase correlation never read): FFTW's r2c output, copied once.
    forward_real_to_half_complex,
    inverse_complex_to_real,  ///< CV_32FC2 spectrum -> CV_32FC1, scaled by 1/(rows cols)
  };

  /// Plans on the first run().
  explicit DftPlan(Direction direction);
  /// Plans for images of `size` now (at setup, not on the first frame).
  DftPlan(Direction direction, cv::Size size);
  ~DftPlan();
  DftPlan(const DftPlan&) = delete;
  DftPlan& operator=(const DftPlan&) = delete;
  DftPlan(DftPlan&&) noexcept;
  DftPlan& operator=(DftPlan&&) noexcept;

  /// out = DFT(in) (or its scaled inverse). `out` is created on the first run
  /// (and again only if the size changes); so is the plan.
  ///
  /// The inverse reads only the columns 0 .. cols/2 of `in` and takes the
  /// rest to be their conjugate mirror, X(-k) = X(k)*, the spectrum of a
  /// real image, as cv::dft's DFT_REAL_OUTPUT does (dft_test compares them).
  /// The spectra the estimator inverts (power, cross-power) are such spectra.
  void run(const cv::Mat& in, cv::Mat& out);

 private:
  struct Fftw;  // dft.cpp: keeps fftw3.h out of this header
  Direction direction_;
  std::unique_ptr<Fftw> fftw_;

  void plan(cv::Size size);
};

}  // namespace gvs::dsp
