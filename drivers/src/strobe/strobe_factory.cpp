#include <stdexcept>

#include "gvs/drivers/gpio_strobe.hpp"
#include "gvs/drivers/pwm_strobe.hpp"

namespace gvs::drivers {

std::unique_ptr<StrobeDriver> make_strobe_driver(const StrobeConfig& config) {
  if (config.driver == "none") return nullptr;
  if (config.driver == "gpio") return std::make_unique<GpioStrobe>(config);
  if (config.driver == "pwm") return std::make_unique<PwmStrobe>(config);
  throw std::runtime_error("[light] driver = \"" + config.driver + "\" is unknown (one of: none, gpio, pwm)");
}

}  // namespace gvs::drivers
