// CameraDevice over libcamera 0.0.3 (Debian 12). Names and types checked
// against /usr/include/libcamera/libcamera/{camera,request,framebuffer,
// control_ids}.h of 0.0.3: ExposureTime int32 us, AnalogueGain float,
// FrameDurationLimits Span<const int64_t, 2> us, SensorTimestamp int64 ns,
// AeEnable bool; ControlList::get returns std::optional.
#include <sys/mman.h>

#include <array>
#include <atomic>
#include <mutex>
#include <ostream>
#include <stdexcept>
#include <streambuf>
#include <string>
#include <string_view>

#include <libcamera/libcamera.h>

#include "gvs/drivers/camera_device.hpp"

namespace gvs::drivers {

namespace {

namespace lc = libcamera;

struct Mapping {
  void* base = MAP_FAILED;
  std::size_t length = 0;
  const std::uint8_t* luma = nullptr;
};

void set_controls(lc::ControlList& list, const CameraControls& c) {
  list.set(lc::controls::AeEnable, false);
  list.set(lc::controls::ExposureTime, c.exposure_us);
  list.set(lc::controls::AnalogueGain, c.analogue_gain);
  list.set(lc::controls::FrameDurationLimits, {c.frame_duration_us, c.frame_duration_us});
}

class LibcameraDevice final : public CameraDevice {
 public:
  LibcameraDevice() : manager_(std::make_unique<lc::CameraManager>()) {
    const int rc = manager_->start();
    if (rc != 0) {
      throw std::runtime_error("libcamera " + lc::CameraManager::version() +
                               ": the camera manager did not start (error " + std::to_string(rc) +
                               "); check that /dev/media* and /dev/video* are readable by this user");
    }
    manager_->cameraRemoved.connect(this, &LibcameraDevice::on_camera_removed);
  }
  ~LibcameraDevice() override {
    close();
    manager_->cameraRemoved.disconnect(this);
    manager_->stop();
  }

  std::string describe() const override { return "libcamera " + lc::CameraManager::version(); }

  std::vector<std::string> list_cameras() override {
    std::vector<std::string> ids;
    for (const auto& cam : manager_->cameras()) ids.push_back(cam->id());
    return ids;
  }

  void open(const std::string& id) override {
    close();
    camera_ = manager_->get(id);
    if (!camera_) throw std::runtime_error("libcamera: camera '" + id + "' is not present (unplugged?)");
    if (camera_->acquire() != 0) {
      camera_.reset();
      throw std::runtime_error("libcamera: camera '" + id +
                               "' is in use by another process; stop it (e.g. another gvsd or libcamera app)");
    }
    camera_->requestCompleted.connect(this, &LibcameraDevice::on_request_completed);
    camera_->disconnected.connect(this, &LibcameraDevice::on_disconnected);
  }

  CameraStreamInfo configure(const CameraStreamRequest& want) override {
    if (!camera_) throw std::runtime_error("libcamera: configure before open");
    const lc::PixelFormat format = want.pixel_format == CameraPixelFormat::r8 ? lc::formats::R8 : lc::formats::YUV420;
    const lc::StreamRole role =
        want.pixel_format == CameraPixelFormat::r8 ? lc::StreamRole::Raw : lc::StreamRole::VideoRecording;
    config_ = camera_->generateConfiguration({role});
    if (!config_ || config_->empty()) {
      throw std::runtime_error("libcamera: camera '" + camera_->id() + "' offers no stream for this role");
    }
    lc::StreamConfiguration& cfg = config_->at(0);
    const std::string offered = cfg.toString();
    cfg.pixelFormat = format;
    cfg.size = lc::Size(static_cast<unsigned>(want.width_px), static_cast<unsigned>(want.height_px));
    cfg.bufferCount = static_cast<unsigned>(want.buffer_count);
    const auto status = config_->validate();
    if (status == lc::CameraConfiguration::Invalid || cfg.pixelFormat != format ||
        cfg.size != lc::Size(static_cast<unsigned>(want.width_px), static_cast<unsigned>(want.height_px))) {
      throw std::runtime_error("libcamera: camera '" + camera_->id() + "' cannot stream " +
                               std::to_string(want.width_px) + "x" + std::to_string(want.height_px) + "-" +
                               camera_pixel_format_name(want.pixel_format) + " (it proposes " + cfg.toString() +
                               ", default " + offered +
                               "); set [camera] width_px/height_px and [libcamera] pixel_format to a mode it has");
    }
    if (camera_->configure(config_.get()) != 0) {
      throw std::runtime_error("libcamera: camera '" + camera_->id() + "' refused the configuration " + cfg.toString());
    }
    stream_ = cfg.stream();
    CameraStreamInfo info;
    info.width_px = static_cast<int>(cfg.size.width);
    info.height_px = static_cast<int>(cfg.size.height);
    info.stride_bytes = cfg.stride;
    info.buffer_count = static_cast<int>(cfg.bufferCount);
    return info;
  }

  void start(const CameraControls& controls, CameraEvents& events) override {
    if (!camera_ || stream_ == nullptr) throw std::runtime_error("libcamera: start before configure");
    allocator_ = std::make_unique<lc::FrameBufferAllocator>(camera_);
    if (allocator_->allocate(stream_) < 0) {
      throw std::runtime_error("libcamera: camera '" + camera_->id() + "': cannot allocate frame buffers");
    }
    const auto& buffers = allocator_->buffers(stream_);
    for (std::size_t i = 0; i < buffers.size(); ++i) {
      const lc::FrameBuffer::Plane& plane = buffers[i]->planes().at(0);
      Mapping m;
      m.length = plane.offset + plane.length;
      m.base = mmap(nullptr, m.length, PROT_READ, MAP_SHARED, plane.fd.get(), 0);
      if (m.base == MAP_FAILED) throw std::runtime_error("libcamera: camera '" + camera_->id() + "': mmap failed");
      m.luma = static_cast<const std::uint8_t*>(m.base) + plane.offset;
      mappings_.push_back(m);
      std::unique_ptr<lc::Request> request = camera_->createRequest(i);
      if (!request || request->addBuffer(stream_, buffers[i].get()) != 0) {
        throw std::runtime_error("libcamera: camera '" + camera_->id() + "': cannot create a request");
      }
      set_controls(request->controls(), controls);
      requests_.push_back(std::move(request));
    }
    stride_bytes_ = config_->at(0).stride;
    lc::ControlList start_controls(camera_->controls());
    set_controls(start_controls, controls);
    events_.store(&events, std::memory_order_release);
    if (camera_->start(&start_controls) != 0) {
      events_.store(nullptr, std::memory_order_release);
      throw std::runtime_error("libcamera: camera '" + camera_->id() + "' did not start");
    }
    started_.store(true, std::memory_order_release);
    for (auto& r : requests_) {
      if (camera_->queueRequest(r.get()) != 0) {
        throw std::runtime_error("libcamera: camera '" + camera_->id() + "' refused a request");
      }
    }
  }

  bool queue(std::uint32_t buffer_index, const CameraControls& controls) noexcept override {
    if (!started_.load(std::memory_order_acquire) || buffer_index >= requests_.size()) return false;
    try {
      lc::Request* r = requests_[buffer_index].get();
      r->reuse(lc::Request::ReuseBuffers);
      set_controls(r->controls(), controls);
      return camera_->queueRequest(r) == 0;
    } catch (...) {
      return false;
    }
  }

  void stop() noexcept override {
    if (started_.exchange(false) && camera_) camera_->stop();  // completes pending requests as cancelled
    events_.store(nullptr, std::memory_order_release);
  }

  void close() noexcept override {
    stop();
    requests_.clear();
    for (const Mapping& m : mappings_) munmap(m.base, m.length);
    mappings_.clear();
    allocator_.reset();
    config_.reset();
    stream_ = nullptr;
    if (camera_) {
      camera_->requestCompleted.disconnect(this);
      camera_->disconnected.disconnect(this);
      camera_->release();
      camera_.reset();
    }
  }

 private:
  // libcamera's thread: fill the plain record and hand it on.
  void on_request_completed(lc::Request* request) {
    CameraEvents* events = events_.load(std::memory_order_acquire);
    if (events == nullptr) return;
    CompletedRequest done;
    done.buffer_index = static_cast<std::uint32_t>(request->cookie());
    done.cancelled = request->status() == lc::Request::RequestCancelled;
    const lc::FrameBuffer* buffer = request->findBuffer(stream_);
    if (buffer != nullptr && done.buffer_index < mappings_.size()) {
      const lc::FrameMetadata& md = buffer->metadata();
      done.buffer_ok = md.status == lc::FrameMetadata::FrameSuccess;
      done.sequence = md.sequence;
      done.sensor_timestamp_ns = static_cast<std::int64_t>(md.timestamp);
      done.bytes_used = md.planes().empty() ? 0 : md.planes()[0].bytesused;
      done.luma = mappings_[done.buffer_index].luma;
      done.stride_bytes = stride_bytes_;
    } else {
      done.buffer_ok = false;
    }
    const lc::ControlList& meta = request->metadata();
    if (const auto ts = meta.get(lc::controls::SensorTimestamp)) done.sensor_timestamp_ns = *ts;
    if (const auto e = meta.get(lc::controls::ExposureTime)) done.exposure_us = *e;
    if (const auto g = meta.get(lc::controls::AnalogueGain)) done.analogue_gain = *g;
    events->request_completed(done);
  }

  void on_disconnected() {
    if (CameraEvents* events = events_.load(std::memory_order_acquire)) events->camera_disconnected();
  }
  void on_camera_removed(std::shared_ptr<lc::Camera> cam) {
    if (cam && cam == camera_) on_disconnected();
  }

  std::unique_ptr<lc::CameraManager> manager_;
  std::shared_ptr<lc::Camera> camera_;
  std::unique_ptr<lc::CameraConfiguration> config_;
  lc::Stream* stream_ = nullptr;
  std::unique_ptr<lc::FrameBufferAllocator> allocator_;
  std::vector<std::unique_ptr<lc::Request>> requests_;
  std::vector<Mapping> mappings_;
  std::size_t stride_bytes_ = 0;
  std::atomic<CameraEvents*> events_{nullptr};
  std::atomic<bool> started_{false};  ///< read by queue() on the camera thread and gvs's supervisor
};

/// libcamera writes its log to a std::ostream; this buffer hands each line
/// to the sink. A line reads "[0:12:34.567890123] [1234]  INFO Camera
/// camera_manager.cpp:299 libcamera v0.0.3": the level is the word after
/// the two bracketed fields.
class LogLines final : public std::streambuf {
 public:
  void set_sink(CameraLibraryLog sink) {
    const std::lock_guard<std::mutex> lock(mutex_);
    sink_ = std::move(sink);
  }

 protected:
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    const std::lock_guard<std::mutex> lock(mutex_);
    const char ch = traits_type::to_char_type(c);
    if (ch == '\n') {
      emit();
    } else {
      line_.push_back(ch);
    }
    return c;
  }

 private:
  void emit() {
    static constexpr std::array<std::string_view, 5> kLevels = {" DEBUG ", " INFO ", " WARN ", " ERROR ",
                                                                " FATAL "};
    const std::string_view line = line_;
    std::string_view level = "INFO";
    std::string_view message = line;
    for (const std::string_view word : kLevels) {
      const std::size_t at = line.find(word);
      if (at == std::string_view::npos) continue;
      level = word.substr(1, word.size() - 2);
      message = line.substr(at + word.size());
      break;
    }
    if (sink_) sink_(level, message);
    line_.clear();
  }

  std::mutex mutex_;
  std::string line_;
  CameraLibraryLog sink_;
};

LogLines& log_lines() {
  static LogLines lines;
  return lines;
}

}  // namespace

void route_camera_library_log(CameraLibraryLog sink) {
  if (!sink) return;
  static std::ostream stream(&log_lines());
  log_lines().set_sink(std::move(sink));
  lc::logSetStream(&stream, false);
}

bool libcamera_available() { return true; }

std::unique_ptr<CameraDevice> make_libcamera_device() { return std::make_unique<LibcameraDevice>(); }

}  // namespace gvs::drivers
