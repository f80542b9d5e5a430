// One row of the sensor model (docs/simulator.md, "Sensor and light"),
// shared by the exact render (sensor.cpp) and the live one (sensor_live.cpp),
// which differ only in where their random draws come from.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace gvs::drivers::sim {

struct PixelModel {
  float e_per_reflectance;  ///< electrons of a white pixel at the centre
  float gain_dn_per_e;
  float full_well_e;
  float read_noise2_e2;     ///< read noise variance
  bool shot_and_read_noise;
};

/// Electrons (shot and read noise, full well), then DN (gain, offset, round,
/// clip). `draws` gives standard normals (normal()) and uniforms in [0, 1)
/// (uniformf()), consumed in pixel order.
template <class Draws>
void expose_row(const PixelModel& m, const float* rho, const float* resp, const float* off, std::uint8_t* dst,
                int cols, Draws& draws) {
  for (int c = 0; c < cols; ++c) {
    float e = std::max(0.0f, m.e_per_reflectance * rho[c] * resp[c]);
    if (m.shot_and_read_noise) {
      if (e > 30.0f) {
        // Poisson shot noise (Gaussian limit) and read noise in one normal draw.
        e += std::sqrt(e + m.read_noise2_e2) * draws.normal();
      } else {
        // Exact Poisson for dim pixels (Knuth), then read noise.
        const float limit = std::exp(-e);
        float p = 1.0f;
        int k = -1;
        do {
          ++k;
          p *= draws.uniformf();
        } while (p > limit);
        e = static_cast<float>(k) + std::sqrt(m.read_noise2_e2) * draws.normal();
      }
    }
    e = std::min(e, m.full_well_e);
    const float dn = std::clamp(m.gain_dn_per_e * e + off[c], 0.0f, 255.0f);
    dst[c] = static_cast<std::uint8_t>(dn + 0.5f);  // round half up (dn >= 0)
  }
}

}  // namespace gvs::drivers::sim
