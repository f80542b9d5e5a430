// libcamera's own log reaches the program's sink line by line, with its
// level and without the colour escapes it writes on a terminal.
#include <gtest/gtest.h>

#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "gvs/drivers/camera_device.hpp"

namespace gvs::drivers {
namespace {

TEST(CameraLibraryLog, LinesArriveWithTheirLevelAndWithoutColour) {
  if (!libcamera_available()) GTEST_SKIP() << "this build has no libcamera (libcamera-dev not found at configure)";
  std::mutex mutex;
  std::vector<std::pair<std::string, std::string>> lines;
  route_camera_library_log([&](std::string_view level, std::string_view message) {
    const std::lock_guard<std::mutex> lock(mutex);
    lines.emplace_back(level, message);
  });
  try {
    (void)make_libcamera_device();  // starts a CameraManager, which logs its version
  } catch (const std::exception&) {
    // no camera manager here: the lines before the failure still count
  }
  route_camera_library_log([](std::string_view, std::string_view) {});
  const std::lock_guard<std::mutex> lock(mutex);
  bool version = false;
  for (const auto& [level, message] : lines) {
    EXPECT_EQ(message.find('\x1b'), std::string::npos) << "colour escape in: " << message;
    EXPECT_TRUE(level == "DEBUG" || level == "INFO" || level == "WARN" || level == "ERROR" || level == "FATAL")
        << level;
    if (level == "INFO" && message.find("libcamera v") != std::string::npos) version = true;
  }
  EXPECT_TRUE(version) << lines.size() << " lines, none the INFO line with libcamera's version";
}

}  // namespace
}  // namespace gvs::drivers
