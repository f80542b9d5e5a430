// The laser-dot finder and a FrameProcessor with lasers allocate nothing
// per frame once set up (docs/performance.md, "No allocation on the
// real-time paths"). This program replaces malloc and friends; counting is
// armed only around the calls under test, on this thread. Not for
// sanitizer builds (they own malloc): skipped there, saying so.
#include <gtest/gtest.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <vector>

#include "gvs/core/laser_geometry.hpp"
#include "gvs/drivers/simulator.hpp"
#include "gvs/dsp/frame_processor.hpp"
#include "gvs/dsp/laser_dots.hpp"
#include "laser_scene.hpp"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define GVS_ALLOC_HOOKS 0
#else
#define GVS_ALLOC_HOOKS 1
#endif

namespace {
std::atomic<std::uint64_t> g_allocations{0};
thread_local bool t_armed = false;
void note_allocation() noexcept {
  if (t_armed) g_allocations.fetch_add(1, std::memory_order_relaxed);
}
}  // namespace

#if GVS_ALLOC_HOOKS
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
#endif

namespace gvs::dsp {
namespace {

std::vector<drivers::SimFrame> double_pulse_frames(const drivers::SimulatorConfig& c, int count) {
  drivers::Simulator sim(c);
  core::ExposurePlan p;
  p.exposure_us = 340.0;
  p.pulse_count = 2;
  p.pulses[0] = {0.0, 6.667};
  p.pulses[1] = {333.333, 6.667};
  std::vector<drivers::SimFrame> frames(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) sim.render(i, p, frames[static_cast<std::size_t>(i)]);
  return frames;
}

TEST(LaserDotsAllocation, NoneOnTheFramePath) {
#if !GVS_ALLOC_HOOKS
  GTEST_SKIP() << "allocation counting replaces malloc, which the sanitizer runtime owns";
#endif
  drivers::SimulatorConfig c;
  c.scenario = "brake";
  c.body = "ride";
  c.lasers = core::design_laser_geometry(c.camera, 60.0);
  const auto frames = double_pulse_frames(c, 40);
  FrameProcessorConfig pc;
  pc.estimator.camera = c.camera;
  pc.lasers = c.lasers;
  FrameProcessor processor(pc);
  LaserDotFinder finder(c.camera, 60.0, c.lasers);
  cv::Mat copy = frames[0].gray.clone();
  auto view = [](const drivers::SimFrame& f) {
    return core::FrameView{f.gray, f.record.index, f.record.t_ns, f.record.exposure};
  };
  for (int i = 0; i < 20; ++i) (void)processor.process(view(frames[static_cast<std::size_t>(i)]));  // warm-up
  int with_height = 0;
  std::uint64_t finder_allocations = 0, processor_allocations = 0;
  for (std::size_t i = 20; i < frames.size(); ++i) {
    frames[i].gray.copyTo(copy);
    g_allocations = 0;
    t_armed = true;
    const LaserDotResult r = finder.find(copy);
    finder.mask(r, copy);
    t_armed = false;
    finder_allocations += g_allocations.load();
    g_allocations = 0;
    t_armed = true;
    const core::VelocityEstimate e = processor.process(view(frames[i]));
    t_armed = false;
    processor_allocations += g_allocations.load();
    if (e.ride.has_height) ++with_height;
  }
  EXPECT_EQ(finder_allocations, 0U);
  EXPECT_EQ(processor_allocations, 0U);
  EXPECT_GE(with_height, 10) << "the frames must hold dots the finder finds";

  // Step 5 against the last plane's frame scaled by the heave: a standing
  // car's faint dots (laser_scene.hpp).
  const laser_test::HeavedStandingPair pair;
  LaserDotFinder standing(pair.c.camera, laser_test::kNominalMm, pair.c.lasers);
  (void)standing.find(pair.frame0, pair.t_mid(pair.f0), pair.plan.exposure_us);
  g_allocations = 0;
  t_armed = true;
  const LaserDotResult scaled = standing.find(pair.frame1, pair.t_mid(pair.f1), pair.plan.exposure_us);
  t_armed = false;
  EXPECT_EQ(g_allocations.load(), 0U);
  EXPECT_TRUE(scaled.ride.has_height) << "the scene must reach the scaled frame";
#if GVS_ALLOC_HOOKS
  // The counter works: an allocation while armed is counted.
  g_allocations = 0;
  t_armed = true;
  std::vector<int>* v = new std::vector<int>(10);
  t_armed = false;
  delete v;
  EXPECT_GE(g_allocations.load(), 2U);
#endif
}

}  // namespace
}  // namespace gvs::dsp
