// Pixel format names of the camera seam (gvs/drivers/camera_device.hpp).
#include "gvs/drivers/camera_device.hpp"

namespace gvs::drivers {

bool parse_camera_pixel_format(const std::string& text, CameraPixelFormat& out) {
  if (text == "R8") {
    out = CameraPixelFormat::r8;
    return true;
  }
  if (text == "YUV420") {
    out = CameraPixelFormat::yuv420;
    return true;
  }
  return false;
}

const char* camera_pixel_format_name(CameraPixelFormat f) {
  return f == CameraPixelFormat::r8 ? "R8" : "YUV420";
}

}  // namespace gvs::drivers
