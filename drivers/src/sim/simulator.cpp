// gvs::drivers::Simulator: scenario -> trajectory -> exposure integral of the
// asphalt -> sensor. See docs/simulator.md.
#include "gvs/drivers/simulator.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "asphalt.hpp"
#include "exposure.hpp"
#include "gvs/drivers/sim/ground_spec.hpp"
#include "gvs/core/frame.hpp"
#include "gvs/core/geometry.hpp"
#include "hash.hpp"
#include "laser_dots.hpp"
#include "photo_ground.hpp"
#include "sensor.hpp"
#include "texture_tile.hpp"

namespace gvs::drivers {
namespace {

void check_config(const SimulatorConfig& c) {
  auto fail = [](const std::string& what) {
    throw std::invalid_argument("simulator: " + what);
  };
  if (!(c.fps > 0.0 && c.fps <= 10000.0)) fail("fps must be in (0, 10000], got " + std::to_string(c.fps));
  if (!(c.exposure_us > 0.0 && c.exposure_us <= 1e6 / c.fps))
    fail("exposure_us must be in (0, 1e6/fps], got " + std::to_string(c.exposure_us));
  if (!(c.seconds >= 0.0 && c.seconds <= 3600.0))
    fail("seconds must be in [0, 3600], got " + std::to_string(c.seconds));
  if (c.camera.width_px < 16 || c.camera.height_px < 16 || c.camera.width_px > 8192 ||
      c.camera.height_px > 8192)
    fail("camera size must be 16..8192 px");
  if (!(c.camera.mm_per_px > 0.001 && c.camera.mm_per_px < 10.0))
    fail("camera mm_per_px must be in (0.001, 10)");
  if (!std::isfinite(c.camera.mount_yaw_deg)) fail("camera mount_yaw_deg must be finite");
  if (c.lasers.count > core::LaserGeometry::kMaxBeams) fail("at most 3 lasers");
  if (c.lasers.enabled() && !(c.laser_peak_relative >= 0.0 && c.laser_speckle_grain_mm > 0.0))
    fail("laser_peak_relative must be >= 0 and laser_speckle_grain_mm > 0");
  if (!(c.camera_height_mm >= 5.0 && c.camera_height_mm <= 10000.0))
    fail("camera_height_mm must be in [5, 10000], got " + std::to_string(c.camera_height_mm));
}

void check_plan(const core::ExposurePlan& p, double fps) {
  auto fail = [](const std::string& what) {
    throw std::invalid_argument("simulator: exposure plan: " + what);
  };
  if (!(p.exposure_us > 0.0 && p.exposure_us <= 1e6 / fps))
    fail("exposure_us must be in (0, frame period], got " + std::to_string(p.exposure_us));
  if (p.pulse_count > core::ExposurePlan::kMaxPulses) fail("more than kMaxPulses pulses");
  double end = 0.0;
  for (std::size_t i = 0; i < p.pulse_count; ++i) {
    const auto& q = p.pulses[i];
    if (!(q.duration_us > 0.0) || !(q.start_us >= end - 1e-9) ||
        q.start_us + q.duration_us > p.exposure_us + 1e-9)
      fail("pulse " + std::to_string(i) +
           " must have a positive duration, start after the previous one and end within the exposure");
    end = q.start_us + q.duration_us;
  }
}

}  // namespace

std::vector<std::string> scenario_names() { return sim::builtin_scenario_names(); }
std::vector<std::string> body_motion_names() { return sim::body_motion_names(); }

struct Simulator::Impl {
  Impl(const SimulatorConfig& c, sim::Scenario s)
      : config(c),
        period_s(c.seconds > 0.0 ? c.seconds : s.length_s),
        trajectory(std::move(s), period_s, c.loop),
        sensor(c.sensor, c.camera, c.sensor_seed) {
    config.scenario = trajectory.scenario().name;
    const sim::GroundSpec spec = sim::parse_ground(c.ground);
    config.ground = sim::ground_text(spec);
    make_ground(spec);
    renderer.set_coarse_min_blur_px(c.coarse_raster_min_blur_px);
    renderer.set_live_fast(c.live_fast_render, tile && tile->psf_sigma_mm() > 0.0);
    plan.exposure_us = c.exposure_us;
    frames = static_cast<std::size_t>(std::floor(period_s * c.fps + 1e-9));
    calibrate();
  }

  /// LED drive (relative to continuous) times lit time, microseconds. Each
  /// pulse is overdriven up to the energy of a rated pulse at full overdrive
  /// (SensorModel::strobe_rated_pulse_us), and never dimmer than continuous.
  [[nodiscard]] double light_dose(const core::ExposurePlan& p) const {
    if (p.pulse_count == 0) return p.exposure_us;
    const sim::SensorModel& m = config.sensor;
    double dose_us = 0.0;
    for (std::size_t i = 0; i < std::min(p.pulse_count, core::ExposurePlan::kMaxPulses); ++i) {
      const double t = p.pulses[i].duration_us;
      dose_us += std::max(t, std::min(m.strobe_overdrive * t, m.strobe_overdrive * m.strobe_rated_pulse_us));
    }
    return dose_us;
  }

  void light_intervals(std::int64_t index, const core::ExposurePlan& p,
                       std::vector<sim::LightInterval>& out) const {
    const double t0 = static_cast<double>(index) / config.fps;
    out.clear();
    if (p.pulse_count == 0) {
      out.push_back({t0, t0 + p.exposure_us * 1e-6});
    } else {
      for (std::size_t i = 0; i < p.pulse_count; ++i)
        out.push_back({t0 + p.pulses[i].start_us * 1e-6,
                       t0 + (p.pulses[i].start_us + p.pulses[i].duration_us) * 1e-6});
    }
  }

  /// Sets the run's gain from frame 0 at the configured exposure (noise-free):
  /// normal -> mean target_mean_dn; under/over scale the light.
  void calibrate() {
    const sim::SensorModel& m = config.sensor;
    light_intervals(0, plan, light);
    renderer.render(rendered_ground(), trajectory, config.camera, config.camera_height_mm, light, reflectance);
    cv::Mat e;
    sensor.electrons(reflectance, m.led_flux_e_per_us * light_dose(plan), e);
    const double mean_e = cv::mean(e)[0];
    gain = (m.target_mean_dn - m.black_level_dn) / mean_e;
    switch (config.light) {
      case LightLevel::normal:
        light_level = 1.0;
        break;
      case LightLevel::under:
        light_level = (m.under_mean_dn - m.black_level_dn) / (m.target_mean_dn - m.black_level_dn);
        break;
      case LightLevel::over: {
        std::vector<float> v(e.begin<float>(), e.end<float>());
        const auto q = static_cast<std::ptrdiff_t>(
            std::clamp(1.0 - m.over_saturated_fraction, 0.0, 1.0) * static_cast<double>(v.size() - 1));
        std::nth_element(v.begin(), v.begin() + q, v.end());
        light_level = (255.0 - m.black_level_dn) / (gain * static_cast<double>(v[static_cast<std::size_t>(q)]));
        break;
      }
    }
  }

  void render(std::int64_t index, const core::ExposurePlan& p, SimFrame& out) {
    const sim::SensorModel& m = config.sensor;
    light_intervals(index, p, light);
    renderer.render(rendered_ground(), trajectory, config.camera, config.camera_height_mm, light, reflectance);
    add_lasers(index);
    // Photons follow the light dose; the gain follows like an auto-gain so the
    // mean stays at the run's level, within [1/r, r] of the run's gain.
    const double dose = light_dose(p);
    const double reference = config.exposure_us;  // continuous LED
    const double ratio = std::clamp(reference / dose, 1.0 / m.max_gain_ratio, m.max_gain_ratio);
    const std::uint64_t noise_seed =
        sim::detail::hash_cell(config.seed, 0x5EED, index, static_cast<std::int64_t>(config.sensor_seed));
    const auto t_sensor = std::chrono::steady_clock::now();
    if (config.live_fast_render) {
      sensor.expose_live(reflectance, m.led_flux_e_per_us * dose * light_level, gain * ratio, noise_seed,
                         out.gray);
    } else {
      sensor.expose(reflectance, m.led_flux_e_per_us * dose * light_level, gain * ratio, noise_seed,
                    out.gray);
    }
    stats = renderer.stats();
    stats.sensor_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_sensor).count();

    const std::int64_t t_ns = std::llround(static_cast<double>(index) * 1e9 / config.fps);
    out.record = FrameRecord{};
    out.record.index = index;
    out.record.t_ns = t_ns;
    out.record.exposure = p;

    const double centre_us = p.light_centre_us();
    const double t_mid = static_cast<double>(index) / config.fps + centre_us * 1e-6;
    const sim::BodyMotion v = trajectory.motion(t_mid);
    TruthRecord& tr = out.truth;
    tr = TruthRecord{};
    tr.index = index;
    tr.t_ns = core::mid_exposure_ns(t_ns, p);
    tr.vx_mps = v.vx_mps;
    tr.vy_mps = v.vy_mps;
    tr.speed_mps = std::hypot(v.vx_mps, v.vy_mps);
    if (tr.speed_mps >= 0.01) tr.direction_deg = core::direction_deg({v.vx_mps, v.vy_mps});
    tr.yaw_rate_dps = v.yaw_rate_dps;
    if (trajectory.has_body_motion()) {
      // At mid-light, as the velocity (the renderer follows the pose
      // through the exposure, knot by knot).
      const sim::BodyPose b = trajectory.body(t_mid);
      tr.height_mm = config.camera_height_mm + b.heave_mm;
      tr.pitch_deg = b.pitch_deg;
      tr.roll_deg = b.roll_deg;
    }
  }

  /// The laser dots, lit with the LED (in every pulse); off: nothing changes.
  void add_lasers(std::int64_t index) {
    if (!config.lasers.enabled()) return;
    sim::LaserLight laser;
    laser.peak_relative = config.laser_peak_relative;
    laser.speckle_grain_mm = config.laser_speckle_grain_mm;
    sim::add_laser_dots(config.lasers, laser, trajectory, config.camera, config.camera_height_mm, light,
                        sim::detail::hash_cell(config.seed, 0x1A5E, index, 0), reflectance, laser_scratch);
  }

  /// Period of the texture: 0 (never repeats) unless periodic_texture asks
  /// for one and its tile fits (at most 4096 samples a side; else the
  /// texture is rendered per frame as for datasets).
  static double texture_period_mm(const SimulatorConfig& c) {
    if (!c.periodic_texture) return 0.0;
    const double spacing = c.camera.mm_per_px / sim::ExposureRenderer::kSupersample;
    const double period = sim::TextureTile::period_for_view(c.camera.width_px * c.camera.mm_per_px,
                                                            c.camera.height_px * c.camera.mm_per_px, spacing);
    return sim::TextureTile::side_for(period, spacing) <= 4096
               ? period
               : 0.0;
  }
  /// The procedural asphalt of the seed (periodic and rendered into a tile
  /// when asked for), or the photo. A photo ground is sampled directly even
  /// for periodic_texture: a lookup in it costs within 2x of one in a tile.
  void make_ground(const sim::GroundSpec& spec) {
    if (spec.kind == sim::GroundSpec::Kind::photo) {
      ground = std::make_unique<sim::PhotoGround>(spec.photo_file, spec.photo_mm_per_pixel, config.seed);
      return;
    }
    const double period = texture_period_mm(config);
    auto texture = period > 0.0 ? std::make_unique<sim::AsphaltTexture>(config.seed, period)
                                : std::make_unique<sim::AsphaltTexture>(config.seed);
    if (period > 0.0) {
      // The live fast render takes the PSF from the tile (blurred once at
      // s/2) instead of per frame, and keeps the tile at the pixel pitch s.
      const bool fast = config.live_fast_render;
      const double psf_sigma_mm = fast ? sim::ExposureRenderer::kPsfSigmaPx * config.camera.mm_per_px : 0.0;
      tile = std::make_unique<sim::TextureTile>(
          *texture, config.camera.mm_per_px / sim::ExposureRenderer::kSupersample, psf_sigma_mm, fast ? 2 : 1);
    }
    ground = std::move(texture);
  }
  [[nodiscard]] const sim::Ground& rendered_ground() const { return tile ? *tile : *ground; }

  SimulatorConfig config;
  double period_s;
  sim::Trajectory trajectory;
  sim::Sensor sensor;
  std::unique_ptr<sim::Ground> ground;     ///< procedural asphalt or photo
  std::unique_ptr<sim::TextureTile> tile;  ///< periodic_texture with the procedural ground only
  sim::ExposureRenderer renderer;
  core::ExposurePlan plan;
  std::vector<sim::LightInterval> light;
  cv::Mat reflectance;
  cv::Mat laser_scratch;
  std::size_t frames = 0;
  std::int64_t next_index = 0;
  double gain = 1.0;
  double light_level = 1.0;
  sim::RenderStats stats;
};

Simulator::Simulator(const SimulatorConfig& config)
    : Simulator(config,
                (check_config(config), sim::with_body_motion(sim::make_scenario(config.scenario), config.body))) {}

Simulator::Simulator(const SimulatorConfig& config, sim::Scenario scenario) {
  check_config(config);
  if (!scenario.motion) throw std::invalid_argument("simulator: scenario '" + scenario.name + "' has no motion");
  if (!(scenario.length_s > 0.0) && !(config.seconds > 0.0))
    throw std::invalid_argument("simulator: scenario '" + scenario.name + "' has no length; set seconds");
  impl_ = std::make_unique<Impl>(config, std::move(scenario));
}

Simulator::~Simulator() = default;
Simulator::Simulator(Simulator&&) noexcept = default;
Simulator& Simulator::operator=(Simulator&&) noexcept = default;

bool Simulator::next(SimFrame& out) {
  if (!impl_->config.loop && impl_->next_index >= static_cast<std::int64_t>(impl_->frames)) return false;
  impl_->render(impl_->next_index, impl_->plan, out);
  ++impl_->next_index;
  return true;
}

void Simulator::set_exposure(const core::ExposurePlan& plan) {
  check_plan(plan, impl_->config.fps);
  impl_->plan = plan;
}

const core::ExposurePlan& Simulator::exposure() const { return impl_->plan; }

void Simulator::render(std::int64_t index, const core::ExposurePlan& plan, SimFrame& out) {
  check_plan(plan, impl_->config.fps);
  if (index < 0) throw std::invalid_argument("simulator: frame index must be >= 0");
  impl_->render(index, plan, out);
}

const SimulatorConfig& Simulator::config() const { return impl_->config; }
bool Simulator::has_body_motion() const { return impl_->trajectory.has_body_motion(); }
std::size_t Simulator::frame_count() const { return impl_->frames; }
const sim::Trajectory& Simulator::trajectory() const { return impl_->trajectory; }
double Simulator::run_gain_dn_per_e() const { return impl_->gain; }
const sim::RenderStats& Simulator::last_render_stats() const { return impl_->stats; }

}  // namespace gvs::drivers
