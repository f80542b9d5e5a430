// The laser dots' tracks (the image of each beam between the lowest and
// highest ground searched, sampled 1 px apart, with the spot's and its
// ring's pixel offsets) and step 1 along them: the centre-surround
// response (docs/estimator.md, "Height from the laser dots").
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "dot_constants.hpp"
#include "gvs/dsp/laser_dots.hpp"

namespace gvs::dsp {

using namespace dots;

LaserDotFinder::LaserDotFinder(const core::CameraGeometry& camera, double nominal_height_mm,
                               const core::LaserGeometry& lasers)
    : camera_(camera), nominal_height_mm_(nominal_height_mm), lasers_(lasers) {
  auto fail = [](const std::string& what) {
    throw std::invalid_argument("laser dots: " + what + " (camera.json 'lasers' or gvsd.toml [lasers])");
  };
  if (!lasers.enabled() || lasers.count > core::LaserGeometry::kMaxBeams) fail("need 1 to 4 beams");
  if (!(nominal_height_mm > 0.0)) fail("the nominal height must be positive");
  if (!(lasers.min_height_mm > 0.0 && lasers.max_height_mm > lasers.min_height_mm))
    fail("min_height_mm must be positive and below max_height_mm");
  if (!(lasers.spot_sigma_mm > 0.0)) fail("spot_sigma_mm must be positive");
  std::size_t longest = 0;
  for (std::size_t k = 0; k < lasers.count; ++k) {
    const core::LaserBeam& beam = lasers.beams[k];
    if (!(beam.tilt_deg > 1.0 && beam.tilt_deg < 80.0)) fail("beam " + std::to_string(k) + ": tilt_deg must be in (1, 80)");
    Track& t = tracks_[k];
    // The track: the image of the beam between the lowest and highest
    // level ground searched (a straight line: the image of a straight line).
    const core::Vec3 o = beam.origin_mm();
    const core::Vec3 u = beam.direction();
    double r0 = 0.0, c0 = 0.0, r1 = 0.0, c1 = 0.0;
    const double h0 = lasers.min_height_mm - kHeightMarginMm, h1 = lasers.max_height_mm + kHeightMarginMm;
    core::head_to_pixel(camera, nominal_height_mm, o + ((h0 + o.z) / -u.z) * u, r0, c0);
    core::head_to_pixel(camera, nominal_height_mm, o + ((h1 + o.z) / -u.z) * u, r1, c1);
    const double length = std::hypot(r1 - r0, c1 - c0);
    if (!(length > 1.0)) fail("beam " + std::to_string(k) + ": its dot does not move with the height");
    t.row0 = r0;
    t.col0 = c0;
    t.er = (r1 - r0) / length;
    t.ec = (c1 - c0) / length;
    t.px_per_mm_height = length / (h1 - h0);
    // The spot: Gaussian of the beam's sigma, stretched by 1 / cos(tilt)
    // along the track (oblique incidence), blurred by the optics.
    const double sigma_px = lasers.spot_sigma_mm / camera.mm_per_px;
    t.sigma_across_px = std::hypot(sigma_px, kPsfSigmaPx);
    t.sigma_along_px = std::hypot(sigma_px / std::cos(core::deg_to_rad(beam.tilt_deg)), kPsfSigmaPx);
    const double sa = t.sigma_along_px, sc = t.sigma_across_px;
    const int reach = static_cast<int>(std::ceil(kMaskEdgeSigmas * std::max(sa, sc))) + 1;
    for (int dr = -reach; dr <= reach; ++dr) {
      for (int dc = -reach; dc <= reach; ++dc) {
        const double along = dr * t.er + dc * t.ec;
        const double across = -dr * t.ec + dc * t.er;
        const Offset off{dr, dc, along / sa, across / sc};
        // Centre-surround: the spot (rho <= 1.5 sigma) against a ring
        // around it (2.5 to 3.5 sigma), which a stone or an edge larger
        // than the spot also lights.
        const double rho = std::hypot(off.along, off.across);
        if (rho <= kInnerSigmas) t.inner.push_back(off);
        else if (rho >= kRingInnerSigmas && rho <= kRingOuterSigmas) t.side.push_back(off);
        if (std::abs(along) <= kWindowSigmas * sa + 1.0 && std::abs(across) <= kWindowSigmas * sc + 1.0)
          t.window.push_back(off);
      }
    }
    // One pixel's step of the spot and the ring: the offsets of the moved
    // shape not in the old one enter, those of the old one not in the moved leave.
    const auto minus = [](const std::vector<Offset>& a, int ar, int ac, const std::vector<Offset>& b, int br, int bc,
                          std::vector<Offset>& out) {
      for (const Offset& p : a) {
        const bool in_b = std::any_of(b.begin(), b.end(), [&](const Offset& q) {
          return q.dr + br == p.dr + ar && q.dc + bc == p.dc + ac;
        });
        if (!in_b) out.push_back({p.dr + ar, p.dc + ac, 0.0, 0.0});  // a pixel, not a place in the spot
      }
    };
    for (int sr = -1; sr <= 1; ++sr) {
      for (int sc2 = -1; sc2 <= 1; ++sc2) {
        Track::Step& st = t.steps[static_cast<std::size_t>(3 * (sr + 1) + sc2 + 1)];
        minus(t.inner, sr, sc2, t.inner, 0, 0, st.inner_in);
        minus(t.inner, 0, 0, t.inner, sr, sc2, st.inner_out);
        minus(t.side, sr, sc2, t.side, 0, 0, st.side_in);
        minus(t.side, 0, 0, t.side, sr, sc2, st.side_out);
      }
    }
    // Samples 1 px apart whose windows lie inside the frame.
    for (double s = 0.0; s <= length; s += 1.0) {
      const double r = r0 + s * t.er, c = c0 + s * t.ec;
      if (r < reach || c < reach || r > camera.height_px - 1 - reach || c > camera.width_px - 1 - reach) continue;
      t.row.push_back(r);
      t.col.push_back(c);
    }
    if (t.row.size() < 8) fail("beam " + std::to_string(k) + ": its track is not in the frame");
    // The pixels step 1 reads along the track, row by row (step 5 resamples
    // only these).
    std::vector<std::array<int, 2>> cols(static_cast<std::size_t>(camera.height_px),
                                         {camera.width_px, -1});
    for (std::size_t i = 0; i < t.row.size(); ++i) {
      const auto r = static_cast<int>(std::lround(t.row[i])), c = static_cast<int>(std::lround(t.col[i]));
      for (int rr = std::max(0, r - reach); rr <= std::min(camera.height_px - 1, r + reach); ++rr) {
        auto& span = cols[static_cast<std::size_t>(rr)];
        span[0] = std::min(span[0], std::max(0, c - reach));
        span[1] = std::max(span[1], std::min(camera.width_px - 1, c + reach));
      }
    }
    for (int r = 0; r < camera.height_px; ++r) {
      const auto& span = cols[static_cast<std::size_t>(r)];
      if (span[1] >= span[0]) t.pixels.push_back({r, span[0], span[1]});
    }
    longest = std::max(longest, t.row.size());
  }
  for (std::size_t k = 0; k < lasers.count; ++k) {
    responses_[k].resize(longest);
    backgrounds_[k].resize(longest);
    last_responses_[k].resize(longest);
    brightening_[k].resize(longest);
    reference_responses_[k].resize(longest);
  }
  scratch_.resize(longest);
  scratch_backgrounds_.resize(longest);
  reference_gray_.create(camera.height_px, camera.width_px, CV_8UC1);
  rescaled_.create(camera.height_px, camera.width_px, CV_8UC1);
}

void LaserDotFinder::robust_spread(const std::vector<double>& values, std::size_t n, double& median, double& spread) {
  std::copy(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(n), scratch_.begin());
  const auto mid = scratch_.begin() + static_cast<std::ptrdiff_t>(n / 2);
  std::nth_element(scratch_.begin(), mid, scratch_.begin() + static_cast<std::ptrdiff_t>(n));
  median = *mid;
  for (std::size_t i = 0; i < n; ++i) scratch_[i] = std::abs(values[i] - median);
  std::nth_element(scratch_.begin(), mid, scratch_.begin() + static_cast<std::ptrdiff_t>(n));
  spread = 1.4826 * *mid;
}

void LaserDotFinder::track_responses(const cv::Mat& gray, std::size_t k, std::vector<double>& resp,
                                     std::vector<double>& bgs) const {
  const Track& t = tracks_[k];
  const std::size_t n = t.row.size();
  // 1. Centre-surround along the track: mean over the spot minus the
  //    ground around it. The sums are whole numbers, carried from one
  //    sample to the next by the pixels that enter and leave (Track::steps).
  const auto sum = [&gray](const std::vector<Offset>& offsets, int r, int c) {
    int s = 0;
    for (const Offset& o : offsets) s += gray.at<std::uint8_t>(r + o.dr, c + o.dc);
    return s;
  };
  const auto inner_n = static_cast<double>(t.inner.size()), side_n = static_cast<double>(t.side.size());
  int inner = 0, side = 0, last_r = 0, last_c = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto r = static_cast<int>(std::lround(t.row[i])), c = static_cast<int>(std::lround(t.col[i]));
    const int dr = r - last_r, dc = c - last_c;
    if (i == 0 || std::abs(dr) > 1 || std::abs(dc) > 1) {
      inner = sum(t.inner, r, c);
      side = sum(t.side, r, c);
    } else {
      const Track::Step& st = t.steps[static_cast<std::size_t>(3 * (dr + 1) + dc + 1)];
      inner += sum(st.inner_in, last_r, last_c) - sum(st.inner_out, last_r, last_c);
      side += sum(st.side_in, last_r, last_c) - sum(st.side_out, last_r, last_c);
    }
    last_r = r;
    last_c = c;
    bgs[i] = side / side_n;
    resp[i] = inner / inner_n - bgs[i];
  }
}

}  // namespace gvs::dsp
