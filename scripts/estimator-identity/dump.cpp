// Prints every field of every estimate of a dataset's replay at full
// precision (hex floats), including those estimates.csv leaves out
// (texture_snr, tracking): the estimator-identity check compares these.
#include <cstdio>
#include <exception>

#include "gvs/eval/replay.hpp"
#include "gvs/drivers/dataset.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DATASET\n", argv[0]);
    return 2;
  }
  try {
    const gvs::drivers::DatasetReader dataset(argv[1]);
    gvs::dsp::FrameProcessorConfig config;
    gvs::eval::replay_dataset(dataset, config, [](const gvs::core::VelocityEstimate& e) {
      std::printf("%lld %lld %d%d%d %a %a %a %a %a %a %a %d %s\n", static_cast<long long>(e.index),
                  static_cast<long long>(e.t_ns), e.has_speed, e.has_direction, e.has_yaw_rate, e.vx_mps,
                  e.vy_mps, e.speed_mps, e.direction_deg, e.yaw_rate_dps, e.quality, e.texture_snr,
                  e.tracking, gvs::core::method_word(e.method));
    });
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "%s\n", ex.what());
    return 1;
  }
  return 0;
}
