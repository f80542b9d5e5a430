// No heap allocation on the capture, processing and sender paths after
// start-up. This program replaces malloc and friends (and operator new); once
// armed, every allocation made on one of the three real-time threads is
// counted and its call stack kept. (operator new reaches these through
// libstdc++'s call to malloc.) Not for sanitizer builds (they own malloc):
// there it reports itself skipped with the reason.
#include <gtest/gtest.h>
#include <execinfo.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <thread>

#include "fake_camera_device.hpp"
#include "gvs/can/sink.hpp"
#include "gvs/drivers/clock.hpp"
#include "gvs/daemon/source_factory.hpp"
#include "gvs/drivers/libcamera_source.hpp"
#include "gvs/daemon/pipeline.hpp"
#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/simulator.hpp"
#include "gvs/dsp/dft.hpp"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define GVSD_ALLOC_HOOKS 0
#else
#define GVSD_ALLOC_HOOKS 1
#endif

namespace {

std::atomic<bool> g_armed{false};
std::atomic<std::uint64_t> g_allocations{0};
thread_local int t_role = -1;  // ThreadRole of an RT thread, -1 elsewhere
thread_local bool t_inside = false;

constexpr int kRoles = 3;
constexpr int kMaxTraces = 6;  // per thread
constexpr int kDepth = 20;
struct Trace {
  void* frames[kDepth];
  int depth;
};
Trace g_traces[kRoles][kMaxTraces];
std::atomic<std::uint64_t> g_by_role[kRoles];

void note_allocation() noexcept {
  if (t_role < 0 || t_inside || !g_armed.load(std::memory_order_relaxed)) return;
  t_inside = true;
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  const auto i = g_by_role[t_role].fetch_add(1, std::memory_order_relaxed);
  if (i < kMaxTraces) g_traces[t_role][i].depth = backtrace(g_traces[t_role][i].frames, kDepth);
  t_inside = false;
}

}  // namespace

#if GVSD_ALLOC_HOOKS
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);

void* malloc(std::size_t n) {
  note_allocation();
  return __libc_malloc(n);
}
void* calloc(std::size_t n, std::size_t size) {
  note_allocation();
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t n) {
  note_allocation();
  return __libc_realloc(p, n);
}
void* memalign(std::size_t align, std::size_t n) {
  note_allocation();
  return __libc_memalign(align, n);
}
void* aligned_alloc(std::size_t align, std::size_t n) {
  note_allocation();
  return __libc_memalign(align, n);
}
int posix_memalign(void** out, std::size_t align, std::size_t n) {
  note_allocation();
  *out = __libc_memalign(align, n);
  return *out != nullptr ? 0 : ENOMEM;
}
}

// operator new (libstdc++) allocates through malloc, so it lands above too.
#endif

namespace gvs::daemon {
namespace {

std::string describe_traces() {
  std::ostringstream out;
  for (int r = 0; r < kRoles; ++r) {
    out << role_name(static_cast<ThreadRole>(r)) << " thread: " << g_by_role[r].load() << " allocations\n";
  }
  for (int r = 0; r < kRoles; ++r) {
    const auto n = std::min<std::uint64_t>(g_by_role[r].load(), kMaxTraces);
    for (std::uint64_t i = 0; i < n; ++i) {
      const Trace& t = g_traces[r][i];
      out << "allocation " << i << " on the " << role_name(static_cast<ThreadRole>(r)) << " thread:\n";
      char** symbols = backtrace_symbols(t.frames, t.depth);
      for (int f = 1; f < t.depth && symbols != nullptr; ++f) out << "    " << symbols[f] << '\n';
      std::free(symbols);
    }
  }
  return out.str();
}

/// A replay dataset of `frames` simulated sine frames (made before counting).
std::string make_replay_dataset(int width_px, std::uint64_t frames) {
  const auto dir = std::filesystem::temp_directory_path() / ("gvsd_alloc_ds_" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  drivers::SimulatorConfig sc;
  sc.scenario = "sine";
  sc.loop = true;
  sc.camera.width_px = width_px;
  sc.camera.height_px = width_px * 3 / 4;
  drivers::Simulator sim(sc);
  drivers::CameraInfo cam;
  cam.geometry = sc.camera;
  drivers::DatasetWriter writer(dir, cam, /*with_truth=*/true);
  drivers::SimFrame f;
  for (std::uint64_t i = 0; i < frames && sim.next(f); ++i) {
    writer.write_frame(f.gray, f.record);
    writer.write_truth(f.truth);
  }
  return dir.string();
}

/// Runs `source_uri` through the whole pipeline, arms the counter after
/// `warmup` processed frames and counts over the next `frames`.
DaemonConfig alloc_config(const std::string& estimator, const std::string& source_uri, int width_px) {
  DaemonConfig c;
  c.source_uri = source_uri;
  c.estimator_method = estimator;
  c.camera.width_px = width_px;
  c.camera.height_px = width_px * 3 / 4;
  c.sim_fps = 60.0;
  c.capture_thread.priority = 0;
  c.processing_thread.priority = 0;
  c.sender_thread.priority = 0;
  return c;
}

void count_allocations(const DaemonConfig& c, std::unique_ptr<drivers::FrameSource> source, std::uint64_t frames);

void count_allocations(const std::string& estimator, const std::string& source_uri, int width_px,
                       std::uint64_t frames) {
#if !GVSD_ALLOC_HOOKS
  GTEST_SKIP() << "allocation counting replaces malloc, which the sanitizer runtime owns; "
                  "run gvsd_alloc_test in the release build";
#endif
  const DaemonConfig c = alloc_config(estimator, source_uri, width_px);
  count_allocations(c, make_frame_source(c), frames);
}

void count_allocations(const DaemonConfig& c, std::unique_ptr<drivers::FrameSource> source, std::uint64_t frames) {
  void* prime[2];
  (void)backtrace(prime, 2);  // loads libgcc's unwinder now, not while counting
  const std::string log =
      (std::filesystem::temp_directory_path() / ("gvsd_alloc_" + std::to_string(getpid()) + ".log")).string();
  auto est = make_frame_estimator(c.estimator_method, source->geometry());
  PipelineHooks hooks;
  hooks.on_loop_start = [](ThreadRole role) { t_role = static_cast<int>(role); };
  Pipeline p(c, std::move(source), std::move(est), can::open_sink("candump:" + log), hooks);
  g_allocations = 0;
  for (auto& n : g_by_role) n = 0;
  p.start();

  constexpr std::uint64_t kWarmup = 30;
  const std::int64_t deadline = drivers::mono_now_ns() + 600 * drivers::kNsPerS;
  while (p.counters().frames_processed.load() < kWarmup && !p.source_ended() && drivers::mono_now_ns() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  const std::uint64_t start = p.counters().frames_processed.load();
  const std::uint64_t sent_before = p.counters().frames_sent.load();
  g_armed = true;
  // A replayed source keeps its own pace and ends: on a loaded machine the
  // processing thread (normal scheduling here) skips frames, so the count
  // may end short of `frames`; what was processed is what is checked.
  while (p.counters().frames_processed.load() < start + frames && !p.source_ended() &&
         drivers::mono_now_ns() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (p.source_ended()) std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the ring's last frames
  g_armed = false;
  const std::uint64_t processed = p.counters().frames_processed.load() - start;
  const std::uint64_t sent = p.counters().frames_sent.load() - sent_before;
  p.request_stop();
  p.join();
  std::filesystem::remove(log);

  ASSERT_GE(processed, frames / 10) << "the run processed too few frames to show anything before the deadline";
  EXPECT_GT(sent, 0u);
  EXPECT_EQ(g_allocations.load(), 0u) << "over " << processed << " frames and " << sent << " CAN frames:\n"
                                      << describe_traces();
  ::testing::Test::RecordProperty("frames", static_cast<int>(processed));
  ::testing::Test::RecordProperty("can_frames", static_cast<int>(sent));
}

// The hooks themselves work: an allocation on a marked thread is counted.
TEST(AllocationCounter, CountsAnAllocationOnAMarkedThread) {
#if !GVSD_ALLOC_HOOKS
  GTEST_SKIP() << "allocation counting replaces malloc, which the sanitizer runtime owns";
#endif
  g_allocations = 0;
  for (auto& n : g_by_role) n = 0;
  std::thread t([] {
    t_role = 0;
    g_armed = true;
    auto* v = new std::vector<int>(100);
    void* m = std::malloc(10);
    g_armed = false;
    std::free(m);
    delete v;
  });
  t.join();
  EXPECT_EQ(g_allocations.load(), 3u);  // new vector object, its buffer, malloc
}

// Capture (a replayed dataset, decoded ahead by the source's own decoder
// thread, which is not a real-time thread, and copied into the ring),
// processing and sender with the "truth" estimator: the daemon's own paths.
// (The simulator source is a desk tool, not the car's capture path: it
// allocates while rendering; see docs/daemon.md.)
TEST(NoAllocation, DaemonPathsOver1000Frames) {
  count_allocations("truth", "replay:" + make_replay_dataset(128, 1100), 128, 1000);
}

// The libcamera source's capture path (camera buffer -> ring slot) on the
// fake camera at 200 fps: the capture thread's next() copies, never
// allocates. (The camera's own thread and the source's supervisor, which
// re-queues the buffers, are not RT threads of gvsd and are not counted.)
TEST(NoAllocation, LibcameraSourceOnAFakeCameraOver600Frames) {
#if !GVSD_ALLOC_HOOKS
  GTEST_SKIP() << "allocation counting replaces malloc, which the sanitizer runtime owns; "
                  "run gvsd_alloc_test in the release build";
#endif
  const DaemonConfig c = alloc_config("truth", "libcamera", 128);
  auto cam = std::make_shared<drivers::testing::FakeCamera>();
  cam->fps = 200.0;
  drivers::LibcameraSettings s = libcamera_settings(c, "");
  s.fps = 200.0;
  count_allocations(
      c, std::make_unique<drivers::LibcameraSource>(std::make_unique<drivers::testing::FakeCameraDevice>(cam), s), 600);
}

// The same with the real estimator "gvs": its FFTs run on plans made during
// the pipeline's warm-up (dsp::DftPlan; cv::dft would re-plan and allocate
// on every call), so estimation allocates nothing either.
TEST(NoAllocation, WithGvsEstimatorOver1000Frames) {
  count_allocations("gvs", "replay:" + make_replay_dataset(256, 1100), 256, 1000);
}

// dsp::DftPlan at the frame sizes a camera gives and the pair's half windows
// (5/8 of the width): FFTW's execute allocates for some plans (its buffered
// solvers), which DftPlan does not use (dft.cpp). The test above runs 256x192.
TEST(NoAllocation, DftPlanAtCameraSizes) {
#if !GVSD_ALLOC_HOOKS
  GTEST_SKIP() << "allocation counting replaces malloc, which the sanitizer runtime owns";
#endif
  for (auto& n : g_by_role) n = 0;
  std::string failures;
  std::thread t([&failures] {
    for (const cv::Size size : {cv::Size(512, 384), cv::Size(320, 384), cv::Size(128, 96), cv::Size(80, 96),
                                cv::Size(640, 480), cv::Size(400, 480), cv::Size(1280, 960), cv::Size(800, 960),
                                cv::Size(1920, 1080), cv::Size(1200, 1080)}) {
      dsp::DftPlan forward(dsp::DftPlan::Direction::forward_real_to_complex, size);
      dsp::DftPlan inverse(dsp::DftPlan::Direction::inverse_complex_to_real, size);
      const cv::Mat image(size, CV_32F, cv::Scalar(1.0));
      cv::Mat spectrum(size, CV_32FC2);
      cv::Mat back(size, CV_32F);
      g_allocations = 0;
      t_role = 1;
      g_armed = true;
      forward.run(image, spectrum);
      inverse.run(spectrum, back);
      g_armed = false;
      t_role = -1;
      if (g_allocations.load() != 0) {
        failures += std::to_string(size.width) + "x" + std::to_string(size.height) + ": " +
                    std::to_string(g_allocations.load()) + " allocations\n";
      }
    }
  });
  t.join();
  EXPECT_TRUE(failures.empty()) << failures;
}

}  // namespace
}  // namespace gvs::daemon
