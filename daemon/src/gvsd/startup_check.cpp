#include "gvs/daemon/startup_check.hpp"

#include <stdexcept>

#include "gvs/can/sink.hpp"
#include "gvs/daemon/config.hpp"
#include "gvs/daemon/frame_estimator.hpp"
#include "gvs/daemon/slot_phase_lock.hpp"
#include "gvs/daemon/source_factory.hpp"

namespace gvs::daemon {

std::string check_startup(const DaemonConfig& config) {
  const CheckedSource source = check_frame_source(config);
  if (config.align_to_frames) {
    if (const std::string refusal = slot_alignment_refusal(config.period_ms, source.fps); !refusal.empty()) {
      throw std::runtime_error(refusal);
    }
  }
  const std::string estimator = make_frame_estimator(config.estimator_method, source.geometry, config.height)->name();
  (void)can::parse_sink_uri(config.can_uri);  // the form open_sink checks before it opens anything
  return estimator;
}

}  // namespace gvs::daemon
