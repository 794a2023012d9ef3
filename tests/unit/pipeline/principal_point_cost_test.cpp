// The principal-point offset cost of pipeline/report/principal_point_cost.hpp (linear propagation)
// against an independent computation: each camera's true principal point moved by d along u, then
// along v, its pixels re-made from the moved truth, the camera re-calibrated by the bundle with the
// principal point held where it was, and the flight-volume points triangulated (nonlinear) from the
// true pixels with the re-calibrated camera.
#include "pipeline/report/principal_point_cost.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "optim/bundle/bundle_adjustment.hpp"
#include "support/correlated_crb.hpp"
#include "vision/triangulation/triangulation.hpp"

namespace rangecal::test {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

const Vector3d kSd(0.0085, 0.0085, 0.015);  // the measured mission's PPK σ per axis (m)

struct Scene {
  CrbNetwork n;
  std::vector<std::vector<Correspondence>> pairs;
  std::vector<CalibrationResult> calibrations;
  std::vector<Vector3d> volume;
};

Scene scene(const std::vector<std::string>& free) {
  Scene s;
  AscentNetworkOptions o;
  o.rate_hz = 2;
  s.n = ascent_network(o);
  s.pairs.resize(s.n.cameras.size());
  for (const CrbView& v : s.n.views) {
    Correspondence c;
    c.enu = s.n.epochs[v.point];
    EXPECT_TRUE(project(s.n.cameras[v.camera].truth, c.enu, &c.uv));
    c.sd_enu = kSd;
    s.pairs[v.camera].push_back(c);
  }
  for (const CrbCamera& c : s.n.cameras) {
    CalibrationResult r;
    r.camera = c.truth;
    r.parameters = expand_free_parameters(free);
    s.calibrations.push_back(r);
  }
  s.volume = flight_volume(s.n, 100, 5);
  return s;
}

std::vector<PrincipalPointCostCamera> cost_cameras(const Scene& s) {
  std::vector<PrincipalPointCostCamera> c;
  for (std::size_t i = 0; i < s.calibrations.size(); ++i) c.push_back({&s.calibrations[i], &s.pairs[i]});
  return c;
}

/// The re-solve: rms over the volume of the direction-averaged bias, from bundle re-calibrations.
double resolved_bias_m(const Scene& s, double d) {
  double sum = 0;
  for (std::size_t c = 0; c < s.n.cameras.size(); ++c)
    for (const Vector2d& dir : {Vector2d(1, 0), Vector2d(0, 1)}) {
      Camera moved = s.n.cameras[c].truth;
      moved.intr.u0_px += d * dir.x(), moved.intr.v0_px += d * dir.y();
      std::vector<BundleObservation> obs;
      for (const Correspondence& p : s.pairs[c]) {
        BundleObservation b;
        b.world = p.enu;
        b.world_cov = kSd.cwiseProduct(kSd).asDiagonal();
        EXPECT_TRUE(project(moved, p.enu, &b.pixel));
        b.pixel_sigma_px = 0.1;
        obs.push_back(b);
      }
      BundleOptions o;
      o.free = {"f", "k1", "pose"};
      o.loss = RobustLoss::none;
      o.resolve_without_outliers = false;
      const Camera estimate = bundle_adjust(s.n.cameras[c].truth, obs, o).calibration.camera;
      double pass = 0;
      for (const Vector3d& X : s.volume) {
        std::vector<TriangulationView> views;
        for (std::size_t k = 0; k < s.n.cameras.size(); ++k) {
          TriangulationView v;
          v.camera = k == c ? estimate : s.n.cameras[k].truth;
          Eigen::Vector2d uv;
          if (!project(k == c ? moved : s.n.cameras[k].truth, X, &uv) || !inside_image(v.camera.intr, uv))
            continue;
          v.uv_px = uv;
          views.push_back(v);
        }
        if (views.size() < 2) continue;
        pass += (triangulate_point(views).point - X).squaredNorm() / static_cast<double>(s.volume.size());
      }
      sum += 0.5 * pass;
    }
  return std::sqrt(sum);
}

TEST(PrincipalPointCost, LinearBiasMatchesReSolvedCalibrations) {
  const Scene s = scene({"f", "k1", "pose"});
  for (double d : {5.0, 15.0}) {
    const double linear = principal_point_offset_bias_m(cost_cameras(s), s.volume, d, 0.1);
    const double resolved = resolved_bias_m(s, d);
    std::printf("offset %.0f px: linear %.3f cm, re-solved %.3f cm\n", d, 100 * linear, 100 * resolved);
    EXPECT_GT(resolved, 0.001);  // a bias of millimetres: the comparison measures something
    EXPECT_NEAR(linear / resolved, 1.0, 0.05) << d;
  }
}

TEST(PrincipalPointCost, FreePrincipalPointCostsNothingFixedOneScalesWithTheOffset) {
  const Scene free = scene({"f", "k1", "u0", "v0", "pose"});
  EXPECT_EQ(principal_point_offset_bias_m(cost_cameras(free), free.volume, 5, 0.1), 0.0);
  const Scene fixed = scene({"f", "k1", "pose"});
  const double b5 = principal_point_offset_bias_m(cost_cameras(fixed), fixed.volume, 5, 0.1);
  EXPECT_NEAR(principal_point_offset_bias_m(cost_cameras(fixed), fixed.volume, 15, 0.1) / b5, 3.0, 1e-9);
}

}  // namespace
}  // namespace rangecal::test
