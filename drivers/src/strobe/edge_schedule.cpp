// One frame's ExposurePlan as a time-ordered list of output edges.
#include <algorithm>

#include "gvs/drivers/strobe.hpp"

namespace gvs::drivers {

namespace {

std::int64_t us_to_ns(double us) noexcept { return static_cast<std::int64_t>(us * 1000.0 + 0.5); }

void add(EdgeSchedule& s, StrobeOutput output, bool on, std::int64_t t_ns) noexcept {
  if (s.count >= EdgeSchedule::kMaxEdges) return;
  s.edges[s.count++] = StrobeEdge{output, on, t_ns, 0};
}

/// Stable insertion sort of the first `n` items (at most 18 here).
template <typename T, std::size_t N, typename Less>
void insertion_sort(std::array<T, N>& a, std::size_t n, Less less) noexcept {
  for (std::size_t i = 1; i < n && i < N; ++i) {
    const T item = a[i];
    std::size_t j = i;
    for (; j > 0 && less(item, a[j - 1]); --j) a[j] = a[j - 1];
    a[j] = item;
  }
}

}  // namespace

EdgeSchedule make_edge_schedule(const core::ExposurePlan& plan, std::int64_t start_ns, bool with_trigger,
                                std::int64_t trigger_pulse_ns) noexcept {
  EdgeSchedule s;
  if (with_trigger) {
    add(s, StrobeOutput::trigger, true, start_ns);
    add(s, StrobeOutput::trigger, false, start_ns + std::max<std::int64_t>(trigger_pulse_ns, 0));
  }

  // LED intervals [on, off) in ns after start, sorted and merged.
  struct Interval {
    std::int64_t on_ns, off_ns;
  };
  std::array<Interval, core::ExposurePlan::kMaxPulses> lit{};
  std::size_t n = 0;
  if (plan.pulse_count == 0) {
    lit[n++] = {0, us_to_ns(plan.exposure_us)};
  } else {
    const std::size_t count = std::min(plan.pulse_count, core::ExposurePlan::kMaxPulses);
    for (std::size_t i = 0; i < count; ++i) {
      const std::int64_t on = us_to_ns(std::max(plan.pulses[i].start_us, 0.0));
      const std::int64_t off = on + us_to_ns(std::max(plan.pulses[i].duration_us, 0.0));
      if (off > on) lit[n++] = {on, off};
    }
  }
  insertion_sort(lit, n, [](const Interval& a, const Interval& b) { return a.on_ns < b.on_ns; });
  std::size_t merged = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (merged > 0 && lit[i].on_ns <= lit[merged - 1].off_ns) {
      lit[merged - 1].off_ns = std::max(lit[merged - 1].off_ns, lit[i].off_ns);
    } else {
      lit[merged++] = lit[i];
    }
  }
  for (std::size_t i = 0; i < merged; ++i) {
    add(s, StrobeOutput::led, true, start_ns + lit[i].on_ns);
    add(s, StrobeOutput::led, false, start_ns + lit[i].off_ns);
  }

  // Time order; at the same time the trigger goes first (it starts the exposure).
  insertion_sort(s.edges, s.count, [](const StrobeEdge& a, const StrobeEdge& b) { return a.target_ns < b.target_ns; });
  return s;
}

std::size_t led_intervals(std::span<const StrobeEdge> edges, std::span<LitInterval> out) noexcept {
  std::size_t n = 0;
  std::int64_t on_ns = -1;
  for (const StrobeEdge& e : edges) {
    if (e.output != StrobeOutput::led) continue;
    if (e.on) {
      on_ns = e.achieved_ns;
    } else if (on_ns >= 0 && n < out.size()) {
      out[n++] = {on_ns, e.achieved_ns};
      on_ns = -1;
    }
  }
  return n;
}

bool light_in_exposure(std::span<const LitInterval> lit, std::int64_t start_ns, double exposure_us,
                       core::ExposurePlan& plan) noexcept {
  const auto end_ns = start_ns + static_cast<std::int64_t>(exposure_us * 1000.0);
  plan = core::ExposurePlan{};
  plan.exposure_us = exposure_us;
  std::int64_t covered_ns = 0;
  for (const LitInterval& l : lit) {
    const std::int64_t a = std::max(l.on_ns, start_ns);
    const std::int64_t b = std::min(l.off_ns, end_ns);
    if (b <= a) continue;
    if (plan.pulse_count == core::ExposurePlan::kMaxPulses) return false;
    plan.pulses[plan.pulse_count++] = {static_cast<double>(a - start_ns) / 1000.0, static_cast<double>(b - a) / 1000.0};
    covered_ns += b - a;
  }
  if (plan.pulse_count == 0) return false;
  if (covered_ns >= end_ns - start_ns) plan.pulse_count = 0;  // lit all through: a continuous exposure
  return true;
}

}  // namespace gvs::drivers
