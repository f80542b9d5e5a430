// The seam at libcamera's interface: what gvsd's camera source needs of a
// camera and nothing more. One implementation drives libcamera 0.0.3
// (make_libcamera_device, built when libcamera is found); the tests drive a
// fake with the same behaviour (tests/drivers/fake_camera_device.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace gvs::drivers {

/// Pixel formats the source takes. Both start with one 8-bit luminance plane.
enum class CameraPixelFormat {
  r8,     ///< libcamera formats::R8 (monochrome sensor, 8 bit)
  yuv420  ///< libcamera formats::YUV420 (its Y plane)
};

/// Parses "R8" / "YUV420"; false for anything else.
bool parse_camera_pixel_format(const std::string& text, CameraPixelFormat& out);
const char* camera_pixel_format_name(CameraPixelFormat f);

/// The stream gvsd asks for.
struct CameraStreamRequest {
  int width_px = 512;
  int height_px = 384;
  CameraPixelFormat pixel_format = CameraPixelFormat::r8;
  int buffer_count = 4;
};

/// What the camera actually configured.
struct CameraStreamInfo {
  int width_px = 0;
  int height_px = 0;
  std::size_t stride_bytes = 0;
  int buffer_count = 0;
};

/// Controls sent with every request (manual exposure: AeEnable off).
/// libcamera 0.0.3 types: ExposureTime int32 us, AnalogueGain float,
/// FrameDurationLimits int64[2] us (min = max fixes the frame rate).
struct CameraControls {
  std::int32_t exposure_us = 3000;
  float analogue_gain = 1.0F;
  std::int64_t frame_duration_us = 16667;
};

/// One completed request, as libcamera's requestCompleted delivers it. Its
/// buffer (`luma`) stays the application's, unchanged and mapped, until it
/// is queued again or the camera is closed.
/// Optional metadata is -1 (timestamp, exposure) or negative (gain) when
/// the request's metadata did not carry it.
struct CompletedRequest {
  std::uint32_t buffer_index = 0;  ///< which mapped buffer (and reusable request)
  bool cancelled = false;          ///< Request::RequestCancelled (camera stopping / gone)
  bool buffer_ok = true;           ///< FrameMetadata::FrameSuccess
  std::uint32_t sequence = 0;      ///< the sensor's frame counter
  std::int64_t sensor_timestamp_ns = -1;  ///< controls::SensorTimestamp (start of exposure)
  std::int32_t exposure_us = -1;          ///< controls::ExposureTime actually applied
  float analogue_gain = -1.0F;            ///< controls::AnalogueGain actually applied
  const std::uint8_t* luma = nullptr;     ///< first plane, mapped once at start()
  std::size_t stride_bytes = 0;
  std::size_t bytes_used = 0;
};

/// Receives completions and disconnection on the camera library's thread:
/// implementations must be short, never block for long, never allocate,
/// never throw.
class CameraEvents {
 public:
  virtual ~CameraEvents() = default;
  virtual void request_completed(const CompletedRequest& done) noexcept = 0;
  virtual void camera_disconnected() noexcept = 0;
};

/// A camera library. Setup calls (list, open, configure, start) throw
/// std::runtime_error with a message naming the camera and what to do;
/// queue(), stop() and close() do not throw.
class CameraDevice {
 public:
  CameraDevice() = default;
  CameraDevice(const CameraDevice&) = delete;
  CameraDevice& operator=(const CameraDevice&) = delete;
  virtual ~CameraDevice() = default;

  /// "libcamera 0.0.3" — for messages.
  [[nodiscard]] virtual std::string describe() const = 0;
  /// Ids of the cameras present now, in the library's order.
  [[nodiscard]] virtual std::vector<std::string> list_cameras() = 0;
  /// Acquires the camera with this id (exclusive use).
  virtual void open(const std::string& id) = 0;
  /// Configures one stream; throws when the camera cannot give exactly the
  /// size and format asked for (the estimator's geometry depends on it).
  virtual CameraStreamInfo configure(const CameraStreamRequest& request) = 0;
  /// Allocates and maps the buffers once, creates one request per buffer,
  /// starts the camera and queues every request with `controls`. Events go
  /// to `events` until stop().
  virtual void start(const CameraControls& controls, CameraEvents& events) = 0;
  /// Re-queues the request of `buffer_index` (Request::reuse(ReuseBuffers))
  /// with new controls, once the buffer's pixels have been read. Called from
  /// CameraEvents::request_completed or from another thread (libcamera's
  /// Camera::queueRequest is thread-safe), never for one buffer from two
  /// threads at once, never concurrently with stop() or close() from
  /// outside request_completed. False when the camera refused it (stopping,
  /// gone).
  virtual bool queue(std::uint32_t buffer_index, const CameraControls& controls) noexcept = 0;
  /// Stops streaming; pending requests complete as cancelled before it returns.
  virtual void stop() noexcept = 0;
  /// Unmaps, frees and releases the camera (open() may follow again).
  virtual void close() noexcept = 0;
};

/// One of libcamera's own log lines: `level` is its word (DEBUG, INFO, WARN,
/// ERROR, FATAL), `message` the rest after the category, without colours.
/// libcamera calls it from its own threads.
using CameraLibraryLog = std::function<void(std::string_view level, std::string_view message)>;
/// Sends libcamera's log (by default coloured lines on stderr) to `sink`,
/// line by line; call it before make_libcamera_device. Without libcamera
/// in the build it does nothing.
void route_camera_library_log(CameraLibraryLog sink);

/// True when this build has the libcamera implementation.
bool libcamera_available();
/// The libcamera 0.0.3 implementation (starts a CameraManager). Throws when
/// the build has no libcamera or the manager cannot start.
std::unique_ptr<CameraDevice> make_libcamera_device();

}  // namespace gvs::drivers
