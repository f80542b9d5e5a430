// The simulated camera sensor and LED ring light (docs/simulator.md, "Sensor").
#pragma once

namespace gvs::drivers::sim {

/// Numbers of the sensor and light model. Defaults: a global-shutter
/// machine-vision CMOS sensor behind an LED ring light.
struct SensorModel {
  /// Electrons per microsecond collected by a pixel at the image centre from a
  /// white (reflectance 1) surface with the LED in continuous mode, at
  /// LightLevel::normal. Only the ratio to the read noise and the full well
  /// matters; the gain is set per run so the mean grey hits its target.
  double led_flux_e_per_us = 5.0;
  /// LED current in strobe (pulse) mode relative to continuous mode, for
  /// pulses up to strobe_rated_pulse_us.
  double strobe_overdrive = 10.0;
  /// Longest pulse the LED takes at full overdrive (pulse ratings: 10-200 us
  /// at a few % duty). A longer pulse is driven at the current that keeps
  /// that pulse's energy (the die's heat per pulse), never below the
  /// continuous current: light = min(overdrive * t, overdrive * rated) for
  /// t above rated, and at least t.
  double strobe_rated_pulse_us = 200.0;
  double full_well_e = 10000.0;
  double read_noise_e = 3.0;        ///< RMS, electrons
  double prnu = 0.01;               ///< photo-response non-uniformity, RMS (multiplicative)
  double dsnu_dn = 1.5;             ///< dark-signal non-uniformity, RMS offset per pixel, DN
  double column_dsnu_dn = 0.5;      ///< column offset pattern (column amplifiers), RMS, DN
  double black_level_dn = 4.0;      ///< pedestal added before quantisation
  double corner_falloff = 0.35;     ///< LED-ring falloff: corners this much darker than the centre
  double max_gain_ratio = 16.0;     ///< per-frame auto-gain range around the run's gain: [1/r, r]
  double target_mean_dn = 110.0;    ///< LightLevel::normal
  double under_mean_dn = 10.0;      ///< LightLevel::under
  double over_saturated_fraction = 0.15;  ///< LightLevel::over
  bool shot_and_read_noise = true;  ///< temporal noise (off only for tests of geometry)
  bool fixed_pattern_noise = true;  ///< PRNU and DSNU
  bool light_falloff = true;
};

}  // namespace gvs::drivers::sim
