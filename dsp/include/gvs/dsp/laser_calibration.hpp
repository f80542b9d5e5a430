// Fitting the laser dots' geometry from frames at known heights (`gvs
// calibrate height`: the head on spacer blocks over a flat plate). Setup
// only: allocates, may be slow; not for the real-time path.
//
// At a known height h over level ground, the dot seen at pixel (r, c) is
// the ground point where the line of sight (a, b, -1) (core/laser_geometry.hpp)
// meets z = -h:  P = h (a, b, -1). Every beam is a straight line, so its
// points at several heights lie on one line: fit x and y as linear
// functions of z (least squares),
//     x = x0 + kx z,   y = y0 + ky z,
// and read the beam off it: a descent of dz moves the dot by
// tan(tilt) (cos az, sin az) dz, so
//     tilt = atan(hypot(kx, ky)),  azimuth = atan2(-ky, -kx),
// and its exit point at z = exit_z_mm is (x0 + kx exit_z, y0 + ky exit_z).
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "gvs/core/frame.hpp"
#include "gvs/core/laser_geometry.hpp"

namespace gvs::dsp {

struct BrightSpot {
  double row = 0.0;
  double col = 0.0;
  double response_dn = 0.0;  ///< centre over surround
};

/// The `max_spots` strongest compact bright spots of about `sigma_px`
/// (difference of Gaussians, local maxima at least 4 sigma apart),
/// strongest first, with matched-centroid positions.
std::vector<BrightSpot> find_bright_spots(const cv::Mat& gray, double sigma_px, std::size_t max_spots);

/// Dots seen in the frames of one known height.
struct HeightObservation {
  double height_mm = 0.0;
  std::vector<BrightSpot> spots;
};

struct LaserFit {
  core::LaserGeometry lasers;
  std::size_t heights_used = 0;
  double rms_residual_mm = 0.0;  ///< distance of the ground points from their fitted lines
};

/// Fits every beam of `prior` (its count, spot size, search range; positions
/// only to tell the beams apart: a spot belongs to the beam whose predicted
/// dot at that height is nearest, within `match_px`). Needs at least two
/// heights with every beam seen; nullopt otherwise.
std::optional<LaserFit> fit_laser_geometry(const std::vector<HeightObservation>& observations,
                                           const core::CameraGeometry& camera, double nominal_height_mm,
                                           const core::LaserGeometry& prior, double exit_z_mm,
                                           double match_px = 60.0);

}  // namespace gvs::dsp
