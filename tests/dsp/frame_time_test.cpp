// dsp::mid_exposure_ns: the one instant a frame describes (exposure start +
// the light's centre), rounded to the nearest nanosecond.
#include <gtest/gtest.h>

#include "gvs/dsp/vocabulary.hpp"

namespace gvs::dsp {
namespace {

ExposurePlan continuous(double exposure_us) {
  ExposurePlan p;
  p.exposure_us = exposure_us;
  return p;
}

TEST(MidExposure, ContinuousExposureIsHalfTheExposureAfterTheStart) {
  EXPECT_EQ(mid_exposure_ns(1'000'000'000, continuous(3000.0)), 1'001'500'000);
  EXPECT_EQ(mid_exposure_ns(0, continuous(1.0)), 500);
}

TEST(MidExposure, RoundsToTheNearestNanosecondNotDown) {
  // Exposures chosen exact in binary: 1000 + 2^-9 us has its centre at
  // 500000.9765625 ns, 1000 + 2^-10 us at 500000.48828125 ns.
  EXPECT_EQ(mid_exposure_ns(7, continuous(1000.0 + 1.0 / 512.0)), 7 + 500'001) << "0.98 ns rounds up";
  EXPECT_EQ(mid_exposure_ns(7, continuous(1000.0 + 1.0 / 1024.0)), 7 + 500'000) << "0.49 ns rounds down";
  EXPECT_EQ(mid_exposure_ns(0, continuous(1.0 / 512.0)), 1) << "0.98 ns after the start is 1 ns, not 0";
}

TEST(MidExposure, PulsesUseTheLightsEnergyWeightedCentre) {
  ExposurePlan p = continuous(5000.0);
  p.pulse_count = 2;
  p.pulses[0] = {5.0, 10.0};   // centre 10 us, weight 10
  p.pulses[1] = {30.0, 30.0};  // centre 45 us, weight 30
  // (10 * 10 + 45 * 30) / 40 = 36.25 us
  EXPECT_EQ(mid_exposure_ns(2'000'000'000, p), 2'000'036'250);
}

}  // namespace
}  // namespace gvs::dsp
