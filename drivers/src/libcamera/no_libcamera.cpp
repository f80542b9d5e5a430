// Built instead of libcamera_device.cpp when CMake found no libcamera.
#include <stdexcept>

#include "gvs/drivers/camera_device.hpp"

namespace gvs::drivers {

bool libcamera_available() { return false; }

void route_camera_library_log(CameraLibraryLog sink) { (void)sink; }

std::unique_ptr<CameraDevice> make_libcamera_device() {
  throw std::runtime_error(
      "this gvs was built without libcamera: install libcamera-dev (apt-get install libcamera-dev, or "
      "scripts/install-deps) and rebuild, or use source sim:SCENARIO / replay:DIR");
}

}  // namespace gvs::drivers
