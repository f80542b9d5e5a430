// The knots of an exposure (exposure_knots.hpp).
#include "exposure_knots.hpp"

#include <algorithm>
#include <cmath>

namespace gvs::drivers::sim {
namespace {
constexpr int kMaxDepth = 12;  ///< at most 2^12 pieces per light interval
}  // namespace

/// Adds knots in (ta, tb] so that every corner's path deviates less than tol_mm
/// from its chord on each piece (the deviation is affine in the pixel position
/// for a level body, so the corners bound it over the image; a tilt of a few
/// degrees bends that by a few per cent of it). The body pose is taken at
/// every knot, not held over the exposure: at the rates of "ride" (a kerb:
/// 10 mm in 50 ms, i.e. 0.6 mm and 1 % of scale in a 3 ms exposure, 2.5 px
/// at the frame's edge) holding it would be visible.
void subdivide(const Trajectory& traj, const CameraFrame& cam, const PoseAt& a, const PoseAt& b, double tol_mm,
               int depth, std::vector<PoseAt>& out) {
  const double tm = 0.5 * (a.t_s + b.t_s);
  const PoseAt m{tm, traj.pose(tm), traj.body(tm)};
  double worst = 0.0;
  for (const double r : {-0.5, cam.height - 0.5}) {
    for (const double c : {-0.5, cam.width - 0.5}) {
      double xa, ya, xb, yb, xm, ym;
      pixel_world(cam, a.pose, a.body, r, c, xa, ya);
      pixel_world(cam, b.pose, b.body, r, c, xb, yb);
      pixel_world(cam, m.pose, m.body, r, c, xm, ym);
      worst = std::max(worst, std::hypot(xm - 0.5 * (xa + xb), ym - 0.5 * (ya + yb)));
    }
  }
  if (worst > tol_mm && depth < kMaxDepth) {
    subdivide(traj, cam, a, m, tol_mm, depth + 1, out);
    subdivide(traj, cam, m, b, tol_mm, depth + 1, out);
  } else {
    out.push_back(b);
  }
}

/// A tilted view's knot: pixel (r, c) -> raster (J / W, I / W), with J, I, W
/// affine in (r, c): the world map's numerators through the raster's affine
/// to_raster (j = (x ux + y uy) / hu - U0, so J = (X ux + Y uy) / hu - U0 W).
ExposureRenderer::Knot projective_knot(double t_s, const ViewMap& m, const RasterGrid& g) {
  ExposureRenderer::Knot k{};
  k.t_s = t_s;
  const auto j_of = [&](double x, double y, double w) { return (x * g.ux + y * g.uy) / g.spacing_u_mm - g.u0 * w; };
  const auto i_of = [&](double x, double y, double w) { return (-x * g.uy + y * g.ux) / g.spacing_mm - g.v0 * w; };
  k.j00 = j_of(m.x00, m.y00, m.w00);
  k.jr = j_of(m.xr, m.yr, m.wr);
  k.jc = j_of(m.xc, m.yc, m.wc);
  k.i00 = i_of(m.x00, m.y00, m.w00);
  k.ir = i_of(m.xr, m.yr, m.wr);
  k.ic = i_of(m.xc, m.yc, m.wc);
  k.w00 = m.w00;
  k.wr = m.wr;
  k.wc = m.wc;
  return k;
}

}  // namespace gvs::drivers::sim
