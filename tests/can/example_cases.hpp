// Example messages with their physical values by DBC signal name: the worked
// example in docs/can-interface.md and the cases the independent-tool check
// (check_dbc_canmatrix.py) decodes.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "gvs/can/codec.hpp"

namespace gvs::can::test {

struct ExampleCase {
  std::string message;                   ///< DBC message name
  CanFrame frame;                        ///< as the codec encodes it
  std::map<std::string, double> expect;  ///< physical value per DBC signal (all signals)
};

/// The worked example of the docs: GVS_Velocity, counter 5, default base ID.
inline VelocityMsg worked_example_velocity() {
  return VelocityMsg{true, true, true, true, 12.34, -5.67, 15.2, 92.0};
}
inline constexpr std::uint8_t kWorkedExampleCounter = 5;

std::vector<ExampleCase> example_cases();

}  // namespace gvs::can::test
