// The calibrate stage end to end: methods on the same problem (noise-free recovery of the truth,
// where each method's model can), the files it writes, and its failures.
#include "pipeline/stages/calibrate_stage.hpp"

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/persistence.hpp>

#include "config/error.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/io/residuals_csv.hpp"
#include "pipeline/steps/calibration_methods.hpp"
#include "pipeline/steps/calibration_problem.hpp"
#include "support/paths.hpp"
#include "support/single_camera_mission.hpp"
#include "support/synthetic_camera.hpp"

namespace rangecal {
namespace {

CalibrationProblem problem_for(const Camera& truth, const std::vector<PointCorrespondence>& pts,
                               std::vector<std::string> free) {
  CalibrationProblem p;
  p.camera_id = "cam1";
  p.sensor = {truth.intr.width_px, truth.intr.height_px, truth.intr.dx_mm, truth.intr.dy_mm};
  p.nominal_focal_mm = 135;
  p.priors.principal_point_px = Eigen::Vector2d(truth.intr.u0_px, truth.intr.v0_px);
  p.free = std::move(free);
  for (const auto& c : pts) {
    BundleObservation o;
    o.world = c.world;
    o.pixel = c.pixel;
    o.world_cov = Eigen::Matrix3d::Identity() * 1e-4;
    p.observations.push_back(o);
  }
  return p;
}

TEST(CalibrateStage, EveryMethodRecoversNoiseFreeTruth) {
  // Seed 002-like: narrow lens, k1, sx 1 — every method's model covers it.
  const Camera truth = test::range_camera(-3.4e-4, 1.0);
  const auto pts = test::observe(truth, test::range_world_points(truth));
  const auto p = problem_for(truth, pts, {"f", "k1", "pose"});
  // Every method the config accepts is one the dispatch runs (planar: refused for a lamp track).
  for (const std::string& m : calibration_method_names()) {
    if (m == "planar") {
      try {
        calibrate_camera(m, p);
        ADD_FAILURE() << "planar accepted a lamp track";
      } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::usage);
        EXPECT_NE(std::string(e.what()).find("planar target"), std::string::npos) << e.what();
      }
      continue;
    }
    const CalibrationResult r = calibrate_camera(m, p);
    EXPECT_EQ(r.method, m);
    EXPECT_NEAR(r.camera.intr.f_mm / truth.intr.f_mm, 1.0, 1e-6) << m;
    EXPECT_NEAR(r.camera.intr.dist.k1, truth.intr.dist.k1, 1e-9) << m;
    EXPECT_LT((r.camera.pose.center() - truth.pose.center()).norm(), 1e-6) << m;
    EXPECT_LT(test::rotation_angle_between(r.camera.pose.R, truth.pose.R), 1e-8) << m;
    EXPECT_LT(r.reprojection.rms_px, 1e-6) << m;
    EXPECT_EQ(r.reprojection.n_used, static_cast<int>(pts.size())) << m;
  }
}

TEST(CalibrateStage, BundleAndDltLmqnReportSigmaForEveryFreeParameter) {
  const Camera truth = test::range_camera(-3.4e-4, 1.0);
  const auto pts = test::observe(truth, test::range_world_points(truth), 0.1, 0.01, 5);
  const auto p = problem_for(truth, pts, {"f", "k1", "pose"});
  for (const std::string m : {"dlt_lmqn", "bundle"}) {
    const CalibrationResult r = calibrate_camera(m, p);
    for (const CameraParameter n : test::parameters({"f", "k1", "wx", "wy", "wz", "CE", "CN", "CU"})) {
      EXPECT_TRUE(std::isfinite(r.sigma(n)) && r.sigma(n) > 0) << m << " " << parameter_name(n);
    }
    EXPECT_TRUE(r.center_sigma_m().allFinite()) << m;
    // With 1 cm world noise at 64 m the estimate stays within 4σ of the truth.
    EXPECT_LT(std::abs(r.camera.intr.f_mm - truth.intr.f_mm), 4 * r.sigma(CameraParameter::f)) << m;
  }
}

// The lamp pairs `truth` sees of the range scene, noise-free, each fix stated at 1 mm.
std::vector<Correspondence> noise_free_pairs(const Camera& truth) {
  std::vector<Correspondence> pairs;
  for (const auto& c : test::observe(truth, test::range_world_points(truth))) {
    Correspondence k;
    k.enu = c.world, k.uv = c.pixel, k.sd_enu = Eigen::Vector3d::Constant(0.001);
    pairs.push_back(k);
  }
  return pairs;
}

// The config of test::range_camera: 1280 × 800 px of 20 µm, 135 mm.
CameraConfig range_camera_config() {
  CameraConfig cam;
  cam.id = "cam1";
  cam.sensor.width_px = 1280, cam.sensor.height_px = 800;
  cam.sensor.pixel_size_um[0] = cam.sensor.pixel_size_um[1] = 20;
  cam.nominal_focal_mm = 135;
  return cam;
}

TEST(CalibrateStage, DefaultFreesThePrincipalPointUnderAnImageCentrePrior) {
  // docs/config.md "The principal point": by default u0, v0 are free under a prior at the image
  // centre (σ 30 px) unless the camera's priors give one; fixed (f, k1, pose) there is no prior.
  const Camera truth = test::range_camera(-3.4e-4, 1.0, 12.0, -9.0);  // 15 px off centre
  const std::vector<Correspondence> pairs = noise_free_pairs(truth);
  CameraConfig cam = range_camera_config();
  const CalibrationProblem p = make_calibration_problem(cam, CalibrateConfig{}, pairs);
  ASSERT_TRUE(p.priors.principal_point_px.has_value());
  EXPECT_EQ(*p.priors.principal_point_px, Eigen::Vector2d(639.5, 399.5));
  EXPECT_DOUBLE_EQ(p.priors.principal_point_sigma_px, 30);
  // Noise-free data bring the principal point to the truth; the prior pulls it by < 0.5 px.
  const CalibrationResult r = calibrate_camera("bundle", p);
  EXPECT_NEAR(r.camera.intr.u0_px, truth.intr.u0_px, 0.5);
  EXPECT_NEAR(r.camera.intr.v0_px, truth.intr.v0_px, 0.5);
  // Held at the centre instead, the 15 px are absorbed by the other parameters: the reprojection
  // shows it (the noise-free free solution fits to ~0).
  CalibrateConfig fixed;
  fixed.free = {"f", "k1", "pose"};
  const CalibrationProblem q = make_calibration_problem(cam, fixed, pairs);
  EXPECT_FALSE(q.priors.principal_point_px.has_value());
  const CalibrationResult s = calibrate_camera("bundle", q);
  EXPECT_DOUBLE_EQ(s.camera.intr.u0_px, 639.5);
  EXPECT_GT(s.reprojection.rms_px, 10 * r.reprojection.rms_px);
  // A prior the camera gives is kept.
  cam.priors.principal_point_px = Eigen::Vector2d(650, 390);
  EXPECT_EQ(*make_calibration_problem(cam, CalibrateConfig{}, pairs).priors.principal_point_px,
            Eigen::Vector2d(650, 390));
}

TEST(CalibrateStage, ACameraOwnFreeSetReplacesTheMissionOne) {
  // cameras[i].free (docs/config.md): a lens with k2 (4 px at 15 mm from the centre) calibrated with
  // k2 in its own free set recovers it and fits the noise-free data exactly; the mission's set (no
  // k2: f, k1 and the principal point absorb most of it) leaves a misfit (measured 0.05 px rms).
  Camera truth = test::range_camera(-3.4e-4, 1.0, 12.0, -9.0);
  truth.intr.dist.k2 = 1e-7;
  const std::vector<Correspondence> pairs = noise_free_pairs(truth);
  CameraConfig cam = range_camera_config();
  const CalibrationProblem mission = make_calibration_problem(cam, CalibrateConfig{}, pairs);
  EXPECT_EQ(mission.free, default_calibrate_free());
  cam.free = {"f", "k1", "k2", "u0", "v0", "pose"};
  const CalibrationProblem own = make_calibration_problem(cam, CalibrateConfig{}, pairs);
  EXPECT_EQ(own.free, cam.free);
  const CalibrationResult with = calibrate_camera("bundle", own);
  const CalibrationResult without = calibrate_camera("bundle", mission);
  EXPECT_NEAR(with.camera.intr.dist.k2, 1e-7, 1e-9);
  EXPECT_LT(with.reprojection.rms_px, 0.01);
  EXPECT_GT(without.reprojection.rms_px, 0.03);
  EXPECT_GT(without.reprojection.rms_px, 100 * with.reprojection.rms_px);
}

TEST(CalibrateStage, BundleStatesItsSigmaUnderThePpkErrorModel) {
  // make_calibration_problem gives each lamp pair its time (s from the first pair); run_bundle
  // hands the problem's PPK error model to the bundle, which keeps its estimate and states σ under
  // the model (optim/bundle/correlated_ppk_covariance.hpp), naming it in details.
  const Camera truth = test::range_camera(-3.4e-4, 1.0);
  const auto pts = test::observe(truth, test::range_world_points(truth), 0.1, 0.01, 5);
  CameraConfig cam;
  cam.id = "cam1";
  cam.sensor.width_px = truth.intr.width_px, cam.sensor.height_px = truth.intr.height_px;
  cam.sensor.pixel_size_um[0] = 1e3 * truth.intr.dx_mm, cam.sensor.pixel_size_um[1] = 1e3 * truth.intr.dy_mm;
  cam.nominal_focal_mm = 135;
  CalibrateConfig calibrate;
  std::vector<Correspondence> pairs;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    Correspondence c;
    c.utc = UtcTime{1'750'000'000'000'000'000 + static_cast<std::int64_t>(i) * 250'000'000};
    c.enu = pts[i].world, c.uv = pts[i].pixel, c.sd_enu = Eigen::Vector3d::Constant(0.01);
    pairs.push_back(c);
  }
  CalibrationProblem p = make_calibration_problem(cam, calibrate, pairs);
  ASSERT_EQ(p.observations.size(), pts.size());
  EXPECT_EQ(p.observations[0].time_s, 0.0);
  EXPECT_NEAR(p.observations[4].time_s, 1.0, 1e-12);
  const CalibrationResult white = calibrate_camera("bundle", p);
  EXPECT_FALSE(white.details.contains("ppk_error_model"));
  p.ppk_error.white_scale_h = p.ppk_error.white_scale_v = 0.4;
  p.ppk_error.gm_sd_h_m = p.ppk_error.gm_sd_v_m = 0.009;
  p.ppk_error.tau_h_s = p.ppk_error.tau_v_s = 30;
  const CalibrationResult gm = calibrate_camera("bundle", p);
  EXPECT_EQ(gm.camera.intr.f_mm, white.camera.intr.f_mm);  // the estimate is the white-weighted one
  EXPECT_EQ(gm.camera.pose.T, white.camera.pose.T);
  EXPECT_GT(gm.sigma(CameraParameter::f), 1.3 * white.sigma(CameraParameter::f));
  ASSERT_TRUE(gm.details.contains("ppk_error_model"));
  EXPECT_EQ(gm.details["ppk_error_model"]["gauss_markov"]["states"],
            gm.reprojection.n_used);  // the used fixes
}

TEST(CalibrateStage, DegenerateGeometryIsACalibrationError) {
  const Camera truth = test::range_camera();
  std::vector<Eigen::Vector3d> line;
  const Eigen::Vector3d a = truth.pose.center() + truth.pose.R.transpose() * Eigen::Vector3d(0, 0, 64);
  for (int i = 0; i < 30; ++i) line.push_back(a + Eigen::Vector3d(0, 0, 0.3 * i));  // one vertical line
  const auto p = problem_for(truth, test::observe(truth, line), {"f", "k1", "pose"});
  for (const std::string m : {"tsai", "tsai_sassa", "dlt_lmqn", "bundle"}) {
    try {
      calibrate_camera(m, p);
      ADD_FAILURE() << m << " accepted points on one line";
    } catch (const Error& e) {
      EXPECT_EQ(e.exit_code(), 4) << m << ": " << e.what();
    }
  }
  EXPECT_THROW(calibrate_camera("planar", p), Error);
  EXPECT_THROW(calibrate_camera("nonsense", p), Error);
}

}  // namespace
}  // namespace rangecal
