// The knots of an exposure (exposure.cpp): instants at which the car's pose
// and the body's height and attitude are taken, close enough that every
// pixel's path between two of them is straight, and each knot as a map
// pixel -> raster coordinates.
#pragma once

#include <vector>

#include "camera_view.hpp"
#include "exposure.hpp"
#include "ground.hpp"
#include "gvs/drivers/sim/scenario.hpp"

namespace gvs::drivers::sim {

/// A knot: an instant with the car's pose and the body's height and attitude.
struct PoseAt {
  double t_s;
  Pose pose;
  BodyPose body;
};

/// Adds knots in (a, b] (appending b last) so that every corner's path
/// deviates less than tol_mm from its chord on each piece.
void subdivide(const Trajectory& traj, const CameraFrame& cam, const PoseAt& a, const PoseAt& b, double tol_mm,
               int depth, std::vector<PoseAt>& out);

/// A tilted view's knot: pixel (r, c) -> raster (J / W, I / W).
ExposureRenderer::Knot projective_knot(double t_s, const ViewMap& m, const RasterGrid& g);

}  // namespace gvs::drivers::sim
