#include "gvs/dsp/method.hpp"

#include <ostream>

namespace gvs::dsp {

std::ostream& operator<<(std::ostream& out, Method m) { return out << method_word(m); }

}  // namespace gvs::dsp
