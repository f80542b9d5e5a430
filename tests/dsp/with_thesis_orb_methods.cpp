// Linked into the test programs that run the thesis's ORB methods (thesis,
// thesis-orb): adds them before any test runs, as the `gvs` tool's main does.
#include "gvs/dsp/thesis_orb_methods.hpp"

namespace {
const bool kAdded = (gvs::dsp::add_thesis_orb_estimators(), true);
}  // namespace
