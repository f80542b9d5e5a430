// The words dsp shares with the rest of gvs (frames, exposure plans,
// estimates, geometry, why a frame is rejected; library gvs::core): used in
// dsp without core::.
#pragma once

#include "gvs/core/estimate.hpp"
#include "gvs/core/frame.hpp"
#include "gvs/core/geometry.hpp"
#include "gvs/core/method.hpp"
#include "gvs/core/reject_reason.hpp"

namespace gvs::dsp {
using namespace gvs::core;
}  // namespace gvs::dsp
