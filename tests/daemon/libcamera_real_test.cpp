// Against Debian's real libcamera 0.0.3 on this machine (which has no
// camera): the camera manager starts and gvsd's libcamera source refuses to
// start with a message saying what to check.
#include <gtest/gtest.h>

#include "gvs/daemon/config.hpp"
#include "gvs/daemon/source_factory.hpp"
#include "gvs/drivers/camera_device.hpp"

namespace gvs::daemon {
namespace {

TEST(LibcameraReal, ManagerStartsAndNoCameraSaysWhatToDo) {
  if (!drivers::libcamera_available()) GTEST_SKIP() << "built without libcamera: install libcamera-dev and rebuild";
  std::vector<std::string> ids;
  {
    const auto device = drivers::make_libcamera_device();  // throws if the CameraManager does not start
    EXPECT_EQ(device->describe().rfind("libcamera ", 0), 0u) << device->describe();
    ids = device->list_cameras();
  }  // one CameraManager per process: gone before the source makes its own
  if (!ids.empty()) {
    GTEST_SKIP() << "this machine has a camera (" << ids.front() << "): the no-camera message cannot be checked";
  }
  DaemonConfig c;
  c.source_uri = "libcamera";
  try {
    (void)make_frame_source(c);
    FAIL() << "no camera: the source must not start";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("source 'libcamera'"), std::string::npos) << m;
    EXPECT_NE(m.find("no camera found"), std::string::npos) << m;
    EXPECT_NE(m.find("/dev/video"), std::string::npos) << m;
  }
  c.source_uri = "libcamera:/base/nothing";
  EXPECT_THROW((void)make_frame_source(c), std::runtime_error);
}

}  // namespace
}  // namespace gvs::daemon
