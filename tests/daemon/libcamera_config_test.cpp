// gvsd's [libcamera] section and the libcamera source's settings made from it.
#include <gtest/gtest.h>

#include "gvs/daemon/config.hpp"
#include "gvs/daemon/source_factory.hpp"

namespace gvs::daemon {
namespace {

TEST(LibcameraConfig, ReadsTheLibcameraSectionAndChecksIt) {
  const DaemonConfig c = parse_config(
      "[libcamera]\nfps = 120\npixel_format = \"R8\"\nbuffer_count = 6\nexposure_min_us = 20\n"
      "gain_min = 1.5\ngain_max = 4\nstall_periods = 2\nretry_interval_ms = 250\n",
      "t.toml");
  EXPECT_DOUBLE_EQ(c.libcamera_fps, 120.0);
  EXPECT_EQ(c.libcamera_pixel_format, "R8");
  EXPECT_EQ(c.libcamera_buffer_count, 6);
  const drivers::LibcameraSettings s = libcamera_settings(c, "cam1");
  EXPECT_EQ(s.camera_id, "cam1");
  EXPECT_EQ(s.pixel_format, drivers::CameraPixelFormat::r8);
  const DaemonConfig defaults;  // a named object: GCC 12 misreads a temporary's strings as uninitialised
  EXPECT_EQ(libcamera_settings(defaults, "").pixel_format, drivers::CameraPixelFormat::yuv420) << "default";
  EXPECT_DOUBLE_EQ(s.gain_min, 1.5);
  EXPECT_DOUBLE_EQ(s.exposure_max_us, c.exposure_max_us);
  EXPECT_DOUBLE_EQ(s.retry_interval_ms, 250.0);
  EXPECT_THROW((void)parse_config("[libcamera]\npixel_format = \"RGB888\"\n", "t.toml"), ConfigError);
  EXPECT_THROW((void)parse_config("[libcamera]\ngain_min = 4\ngain_max = 2\n", "t.toml"), ConfigError);
  EXPECT_THROW((void)parse_config("[libcamera]\nexposure = 2\n", "t.toml"), ConfigError);
}

}  // namespace
}  // namespace gvs::daemon
