// Row-strip parallelism that can be switched off: the exact render uses both
// cores through cv::parallel_for_; the live fast render runs on the calling
// (real-time capture) thread alone, so it never waits on a worker thread the
// estimator's thread has preempted (docs/simulator.md, "Live source").
// Every body computes each index independently, so results do not depend
// on the choice.
#pragma once

#include <opencv2/core/utility.hpp>

namespace gvs::drivers::sim {

template <class Body>
void for_strips(bool parallel, const cv::Range& range, const Body& body, double nstripes = -1.0) {
  if (parallel) {
    cv::parallel_for_(range, body, nstripes);
  } else {
    body(range);
  }
}

}  // namespace gvs::drivers::sim
