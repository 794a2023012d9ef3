// The numbers the report's plots draw, against independent computations written here: the
// projection σ against a finite-difference propagation through `project`, the predicted
// intersection covariance against the triangulation's own, the funnel against known run.json counts,
// the noise-model RMS against its formula, and compare-calibrations (zero for a calibration with
// itself; exceeding the combined σ at about 5 % for two Monte Carlo draws).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <functional>
#include <random>

#include "config/error.hpp"
#include "pipeline/report/calibration_difference.hpp"
#include "pipeline/report/data_funnel.hpp"
#include "pipeline/report/intersection_prediction.hpp"
#include "pipeline/report/lamp_residuals.hpp"
#include "pipeline/report/projection_uncertainty.hpp"
#include "pipeline/report/svg_chart.hpp"
#include "support/projection_sigma.hpp"
#include "support/synthetic_camera.hpp"
#include "vision/triangulation/triangulation.hpp"

namespace rangecal {
namespace {

// A calibration of `cam` with a dense, strongly correlated covariance over f, k1, rotation, centre
// (σ: 2 mm, 1.3e-5 mm⁻², 0.5 mrad, 0.7 m, 0.7 m, 0.06 m; f–CN correlation about 0.99).
CalibrationResult calibrated(const Camera& cam) {
  CalibrationResult r;
  r.camera = cam;
  r.method = "bundle";
  r.parameters = test::parameters({"f", "k1", "wx", "wy", "wz", "CE", "CN", "CU"});
  const Eigen::VectorXd sd = (Eigen::VectorXd(8) << 2.0, 1.3e-5, 5e-4, 5e-4, 5e-4, 0.7, 0.7, 0.06).finished();
  Eigen::MatrixXd L = Eigen::MatrixXd::Identity(8, 8);
  for (int i = 1; i < 8; ++i) L(i, 0) = 0.3 * ((i % 3) - 1);
  L(6, 0) = -7.0;  // f and CN nearly inseparable
  Eigen::MatrixXd C = L * L.transpose();
  const Eigen::VectorXd s = C.diagonal().cwiseSqrt();
  C = s.cwiseInverse().asDiagonal() * C * s.cwiseInverse().asDiagonal();  // correlation
  r.covariance = sd.asDiagonal() * C * sd.asDiagonal();
  return r;
}

TEST(ReportFigures, ProjectionSigmaMatchesFiniteDifferencePropagationThroughProject) {
  const CalibrationResult r = calibrated(test::range_camera(-3.4e-4));
  for (const Eigen::Vector2d& uv :
       {Eigen::Vector2d(639.5, 399.5), Eigen::Vector2d(20, 30), Eigen::Vector2d(1200, 700)}) {
    const Eigen::Vector3d X = point_on_pixel_ray(r.camera, uv, 64.0);
    Eigen::Vector2d back;
    ASSERT_TRUE(project(r.camera, X, &back));
    EXPECT_NEAR((back - uv).norm(), 0, 1e-6);  // the point is on the pixel's ray
    EXPECT_NEAR(world_to_camera(r.camera.pose, X).z(), 64.0, 1e-9);
    const double expected = test::finite_difference_projection_sigma_px(r, X);
    EXPECT_GT(expected, 0.01);
    EXPECT_NEAR(projection_sigma_px(r, uv, 64.0), expected, 0.01 * expected) << uv.transpose();
  }
  // The map's centre cell (odd grid) is the image centre.
  const ProjectionUncertaintyMap m = projection_uncertainty_map(r, 64.0, 41, 25);
  EXPECT_DOUBLE_EQ(m.u_px[20], 639.5);
  EXPECT_DOUBLE_EQ(m.v_px[12], 399.5);
  EXPECT_DOUBLE_EQ(m.sigma_px(12, 20), projection_sigma_px(r, Eigen::Vector2d(639.5, 399.5), 64.0));
}

TEST(ReportFigures, PredictedIntersectionEqualsTheTriangulationsCovariance) {
  CalibrationResult a = calibrated(test::range_camera_at("a", {-45, -45, 1.5}, {0, 0, 4}));
  CalibrationResult b = calibrated(test::range_camera_at("b", {45, -45, 1.8}, {0, 0, 4}));
  const Eigen::Vector3d X(0.7, 1.2, 4.5);
  std::vector<TriangulationView> views;
  for (const CalibrationResult* c : {&a, &b}) {
    TriangulationView v;
    v.camera = c->camera;
    v.calibration = {c->parameters, c->covariance};
    ASSERT_TRUE(project(c->camera, X, &v.uv_px));
    v.pick_sigma_px = 0.5;
    views.push_back(v);
  }
  const TriangulationResult t = triangulate_point(views, "X");
  const PredictedIntersection p = predict_intersection({&a, &b}, X, 0.5);
  EXPECT_EQ(p.n_cameras, 2);
  EXPECT_LT((p.cov_calibration_m2 - t.cov_calibration_m2).norm(), 1e-6 * t.cov_calibration_m2.norm());
  EXPECT_LT((p.cov_pick_m2 - t.cov_pick_m2).norm(), 1e-6 * t.cov_pick_m2.norm());
  // A joint (network) covariance: cross blocks of correlation 0.6 between the same parameters
  // change the prediction exactly as they change the triangulation's.
  const Eigen::MatrixXd ab = 0.6 * Eigen::MatrixXd(a.covariance.diagonal().cwiseSqrt().asDiagonal()) *
                             Eigen::MatrixXd(b.covariance.diagonal().cwiseSqrt().asDiagonal());
  const CrossCovariances cross = {{Eigen::MatrixXd(), ab},
                                  {Eigen::MatrixXd(ab.transpose()), Eigen::MatrixXd()}};
  const TriangulationResult tj = triangulate_point(views, "X", &cross);
  const PredictedIntersection pj = predict_intersection({&a, &b}, X, 0.5, &cross);
  EXPECT_GT((tj.cov_calibration_m2 - t.cov_calibration_m2).norm(),
            0.01 * t.cov_calibration_m2.norm());  // 2.5 % here
  EXPECT_LT((pj.cov_calibration_m2 - tj.cov_calibration_m2).norm(), 1e-6 * tj.cov_calibration_m2.norm());
  // Outside camera b's view: no intersection there.
  EXPECT_LT(predict_intersection({&a, &b}, Eigen::Vector3d(-40, 40, 4), 0.5).n_cameras, 2);
  const IntersectionSigmaSlice s = intersection_sigma_slice({&a, &b}, {-1, 1}, {0, 2}, 4.5, 3, 3, 0.5);
  EXPECT_NEAR(s.e_m[1], 0, 1e-12);
  EXPECT_NEAR(s.n_m[1], 1, 1e-12);
  EXPECT_NEAR(s.sigma_m(1, 1),
              std::sqrt(predict_intersection({&a, &b}, Eigen::Vector3d(0, 1, 4.5), 0.5, nullptr, false)
                            .cov_calibration_m2.trace()),
              1e-15);
}

TEST(ReportFigures, FunnelCountsComeFromRunJson) {
  const nlohmann::json stages = nlohmann::json::parse(R"({
    "gnss": {"counts": {"epochs_read": 292, "epochs_kept": 280, "dropped_quality_by_q": {"2": 10},
                        "dropped_sd": 2, "dropped_no_attitude": 0}},
    "align": {"counts": {"cam1": {"frames": 150, "frames_picked": 144, "frames_aligned": 139,
                                  "rejected_offset": 4, "rejected_gap": 0, "rejected_outside_track": 1}}},
    "detect": {"counts": {"cam1": {"frames_examined": 139, "correspondences": 73,
                                   "by_status": {"ok": 73, "rejected_static": 60, "not_found": 6}}}},
    "calibrate": {"counts": {"cameras": {"cam1": {"pairs": 73, "control_poles": 6, "n_used": 77,
                                                 "n_rejected": 2}}}},
    "intersect": {"counts": {"poles_picked": 17, "poles_triangulated": 16}}})");
  const std::vector<FunnelRow> rows = data_funnel(stages, {"cam1", "cam2"});
  ASSERT_EQ(rows.size(), 5u);  // cam2 has no counts: no rows
  EXPECT_EQ(rows[0].stage, "gnss");
  EXPECT_EQ(rows[0].in, 292);
  EXPECT_EQ(rows[0].kept, 280);
  ASSERT_EQ(rows[0].dropped.size(), 2u);
  EXPECT_EQ(rows[0].dropped[0].count, 10);
  EXPECT_EQ(rows[0].dropped[1].count, 2);
  EXPECT_EQ(rows[1].stage, "align");
  ASSERT_EQ(rows[1].dropped.size(), 3u);  // 6 not picked, 4 offset, 1 outside (gap 0 left out)
  EXPECT_EQ(rows[1].dropped[0].count, 6);
  EXPECT_EQ(rows[2].kept, 73);
  ASSERT_EQ(rows[2].dropped.size(), 2u);
  EXPECT_EQ(rows[2].dropped[0].count + rows[2].dropped[1].count, 66);
  EXPECT_EQ(rows[3].in, 79);
  EXPECT_EQ(rows[3].kept, 77);
  EXPECT_EQ(rows[4].in - rows[4].kept, 1);
  // Every row accounts for what it dropped.
  for (const FunnelRow& r : rows) {
    long long dropped = 0;
    for (const FunnelDrop& d : r.dropped) dropped += d.count;
    EXPECT_EQ(r.kept + dropped, r.in) << r.stage;
  }
  EXPECT_TRUE(data_funnel(nlohmann::json(), {"cam1"}).empty());
}

TEST(ReportFigures, NoiseModelSigmaIsPixelNoisePlusProjectedPpkSd) {
  const Camera cam = test::range_camera();
  CalibrationResult r;
  r.camera = cam;
  Correspondence p;
  p.enu = Eigen::Vector3d(0.5, 64, 7.5);
  ASSERT_TRUE(project(cam, p.enu, &p.uv));
  p.uv += Eigen::Vector2d(0.3, -0.4);
  p.sd_enu = Eigen::Vector3d(0.01, 0.01, 0.02);
  const std::vector<LampResidual> res = lamp_residuals({p, p}, &r, nullptr, 0.1);
  ASSERT_EQ(res.size(), 2u);
  EXPECT_NEAR(res[0].residual.x(), 0.3, 1e-9);
  EXPECT_NEAR(res[0].residual.y(), -0.4, 1e-9);
  // Independent J_X by central differences (px/m) at the point.
  Eigen::Matrix<double, 2, 3> J;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[k] = 1e-4;
    Eigen::Vector2d a, b;
    project(cam, p.enu + d, &a);
    project(cam, p.enu - d, &b);
    J.col(k) = (a - b) / 2e-4;
  }
  const Eigen::Matrix2d C =
      0.01 * Eigen::Matrix2d::Identity() + J * Eigen::Vector3d(1e-4, 1e-4, 4e-4).asDiagonal() * J.transpose();
  EXPECT_NEAR(res[0].sigma_px.x(), std::sqrt(C(0, 0)), 1e-6);
  EXPECT_NEAR(res[0].sigma_px.y(), std::sqrt(C(1, 1)), 1e-6);
  const ResidualConsistency c = residual_consistency(res, 1);
  EXPECT_EQ(c.n, 2);
  EXPECT_NEAR(c.rms_px, 0.5, 1e-9);
  EXPECT_NEAR(c.expected_rms_px, std::sqrt(C.trace() * 3.0 / 4.0), 1e-6);
}

TEST(ReportFigures, NoiseModelTakesThePpkErrorModelTheCalibrationUsed) {
  // Under the model, a fix's error is white S·Σ_pos·S plus the Gauss–Markov part of variance σ_g²
  // (gnss/track/ppk_error_model.hpp): the residual's σ carries both.
  const Camera cam = test::range_camera();
  CalibrationResult r;
  r.camera = cam;
  Correspondence p;
  p.enu = Eigen::Vector3d(0.5, 64, 7.5);
  ASSERT_TRUE(project(cam, p.enu, &p.uv));
  p.sd_enu = Eigen::Vector3d(0.01, 0.01, 0.02);
  PpkErrorModel m;
  m.white_scale_h = 0.4, m.white_scale_v = 0.3;
  m.gm_sd_h_m = 0.008, m.gm_sd_v_m = 0.014;
  m.tau_h_s = 30, m.tau_v_s = 30;
  const LampResidual a = lamp_residuals({p}, &r, nullptr, 0.1, &m).front();
  const Eigen::Vector3d var(0.004 * 0.004 + 0.008 * 0.008, 0.004 * 0.004 + 0.008 * 0.008,
                            0.006 * 0.006 + 0.014 * 0.014);
  const Eigen::Matrix2d C =
      0.01 * Eigen::Matrix2d::Identity() + a.world_jacobian * var.asDiagonal() * a.world_jacobian.transpose();
  EXPECT_NEAR(a.sigma_px.x(), std::sqrt(C(0, 0)), 1e-9);
  EXPECT_NEAR(a.sigma_px.y(), std::sqrt(C(1, 1)), 1e-9);
  // The white model (S = I, no σ_g) is the .pos sd as written, bit for bit as without a model.
  const PpkErrorModel white;
  const LampResidual w = lamp_residuals({p}, &r, nullptr, 0.1, &white).front();
  const LampResidual none = lamp_residuals({p}, &r, nullptr, 0.1).front();
  EXPECT_EQ(w.sigma_px, none.sigma_px);
  EXPECT_GT(none.sigma_px.y(), 1.2 * a.sigma_px.y()) << "the model's total is below the .pos sd here";
}

// Lamp pairs at 5 Hz for 60 s, the lamp at `z(t)` above (0.5, 64) moving at `vz(t)`; each pixel as
// the camera saw it with a clock offset `clock_s` and a world error `error_m` of the fix.
std::vector<LampResidual> moving_lamp_residuals(const std::function<double(double)>& z,
                                                const std::function<double(double)>& vz, double clock_s,
                                                const Eigen::Vector3d& error_m, const PpkErrorModel* model) {
  const Camera cam = test::range_camera();
  CalibrationResult r;
  r.camera = cam;
  std::vector<Correspondence> pairs;
  for (int i = 0; i < 300; ++i) {
    const double t = 0.2 * i;
    Correspondence p;
    p.utc = UtcTime{1700000000000000000LL + static_cast<std::int64_t>(i) * 200000000LL};
    const Eigen::Vector3d truth(0.5, 64, z(t));
    p.vel_enu = Eigen::Vector3d(0, 0, vz(t));
    p.enu = truth + error_m;
    p.sd_enu = Eigen::Vector3d(0.003, 0.003, 0.005);
    EXPECT_TRUE(project(cam, truth - *p.vel_enu * clock_s, &p.uv));
    pairs.push_back(p);
  }
  return lamp_residuals(pairs, &r, nullptr, 0.1, model);
}

TEST(ReportFigures, ClockOffsetSignatureIsTheLampsMotionNotASlowPpkError) {
  PpkErrorModel gm;
  gm.gm_sd_h_m = 0.008, gm.gm_sd_v_m = 0.014;
  gm.tau_h_s = 30, gm.tau_v_s = 30;
  // Ascents only (as the demo flies), at 0.2 m/s: a fix 4 mm low throughout looks like the lamp seen
  // 20 ms early.
  const auto up = [](double t) { return 3 + t * 0.2; };
  const auto up_v = [](double) { return 0.2; };
  const ClockOffsetSignature white =
      clock_offset_signature(moving_lamp_residuals(up, up_v, 0, {0, 0, -0.004}, nullptr), nullptr);
  EXPECT_EQ(white.n, 300);
  EXPECT_NEAR(white.offset_s, -0.020, 1e-3);
  EXPECT_GT(std::abs(white.offset_s), 5 * white.sigma_s) << "white noise alone: a clock offset";
  // Under the correlated model such an error is the Gauss–Markov part's, well within its σ.
  const std::vector<LampResidual> res = moving_lamp_residuals(up, up_v, 0, {0, 0, -0.004}, &gm);
  const ClockOffsetSignature correlated = clock_offset_signature(res, &gm);
  EXPECT_NEAR(correlated.offset_s, white.offset_s, 1e-9);
  EXPECT_LT(std::abs(correlated.offset_s), 3 * correlated.sigma_s);
  // The σ is the model's: the sum over pairs by the recursion equals the direct double sum.
  double direct = 0, gg = 0;
  for (const LampResidual& i : res) {
    gg += i.image_velocity_px_s.squaredNorm();
    for (const LampResidual& j : res) {
      const double dt = 1e-9 * static_cast<double>(i.utc.ns - j.utc.ns);
      const Eigen::Vector3d phi = gauss_markov_transition(gm, dt);
      const Eigen::Vector3d var =
          i.utc.ns == j.utc.ns ? Eigen::Vector3d::Zero() : gm.gm_sd().cwiseAbs2().cwiseProduct(phi).eval();
      direct += (i.world_jacobian.transpose() * i.image_velocity_px_s)
                    .dot(var.cwiseProduct(j.world_jacobian.transpose() * j.image_velocity_px_s));
    }
    direct += i.image_velocity_px_s.dot(i.cov_px * i.image_velocity_px_s);
  }
  EXPECT_NEAR(correlated.sigma_s, std::sqrt(direct) / gg, 1e-9 * correlated.sigma_s);
  // Up and down every 10 s: a 40 ms clock offset reverses with the lamp, which no error slow over
  // 30 s does, so it shows under the correlated model too; a flight with no offset shows none.
  const auto zigzag = [](double t) {
    const double u = std::fmod(t, 20.0);
    return 3 + (u < 10 ? u : 20 - u);
  };
  const auto zigzag_v = [](double t) { return std::fmod(t, 20.0) < 10 ? 1.0 : -1.0; };
  const ClockOffsetSignature late = clock_offset_signature(
      moving_lamp_residuals(zigzag, zigzag_v, 0.040, Eigen::Vector3d::Zero(), &gm), &gm);
  EXPECT_NEAR(late.offset_s, 0.040, 2e-3);
  EXPECT_GT(std::abs(late.offset_s), 3 * late.sigma_s);
  const ClockOffsetSignature on_time =
      clock_offset_signature(moving_lamp_residuals(zigzag, zigzag_v, 0, Eigen::Vector3d::Zero(), &gm), &gm);
  EXPECT_LT(std::abs(on_time.offset_s), 1e-6);
}

TEST(CompareCalibrations, ACalibrationWithItselfIsZeroEverywhere) {
  const CalibrationResult r = calibrated(test::range_camera(-3.4e-4));
  const CalibrationDifference d = compare_calibrations(r, r, 64.0, 9, 5);
  ASSERT_EQ(d.cells.size(), 45u);
  for (const DifferenceCell& c : d.cells) {
    EXPECT_EQ(c.diff_px.x(), 0.0);
    EXPECT_EQ(c.diff_px.y(), 0.0);
    EXPECT_FALSE(c.exceeds);
    EXPECT_GT(c.sigma_px, 0);
  }
  EXPECT_EQ(d.max_diff_px, 0.0);
  EXPECT_EQ(d.fraction_exceeding, 0.0);
  CalibrationResult other = r;
  other.camera.intr.width_px = 640;
  EXPECT_THROW(compare_calibrations(r, other, 64.0, 3, 3, "b.json"), Error);
}

TEST(CompareCalibrations, TwoMonteCarloDrawsExceedTheCombinedSigmaAtAboutFivePercent) {
  // Draws x = x̂ + L·z from the calibration's covariance, each carrying that covariance: their
  // difference is N(0, 2Σ) to first order, so m² ~ χ²₂ and m > 2.448 at 5 % of (pair, pixel) cells.
  const CalibrationResult r = calibrated(test::range_camera(-3.4e-4));
  const Eigen::MatrixXd L = r.covariance.llt().matrixL();
  const Eigen::VectorXd x0 = parameter_values(r.camera, r.parameters);
  std::mt19937_64 rng(14);
  std::normal_distribution<double> g;
  auto draw = [&]() {
    Eigen::VectorXd z(x0.size());
    for (Eigen::Index k = 0; k < z.size(); ++k) z[k] = g(rng);
    CalibrationResult c = r;
    c.camera = camera_with_parameters(r.camera, r.parameters, x0 + L * z);
    return c;
  };
  double exceeding = 0;
  const int pairs = 400;
  for (int k = 0; k < pairs; ++k)
    exceeding += compare_calibrations(draw(), draw(), 64.0, 5, 3).fraction_exceeding;
  const double rate = exceeding / pairs;
  // 400 pairs: the rate's sd is at most √(0.05·0.95/400) ≈ 1.1 % (less, cells are correlated
  // within a pair only partly); 2.5–8 % holds it to the expected 5 %.
  EXPECT_GT(rate, 0.025) << rate;
  EXPECT_LT(rate, 0.08) << rate;
}

TEST(SvgChart, TicksAreRoundAndClippingKeepsSegmentsInside) {
  EXPECT_EQ(nice_ticks(0, 10, 5), (std::vector<double>{0, 2, 4, 6, 8, 10}));
  EXPECT_EQ(nice_ticks(-0.5, 1279.5, 8), (std::vector<double>{0, 200, 400, 600, 800, 1000, 1200}));
  Eigen::Vector2d p(5, 5), q(15, 5);
  bool cut = false;
  ASSERT_TRUE(clip_segment(0, 0, 10, 10, &p, &q, &cut));
  EXPECT_TRUE(cut);
  EXPECT_DOUBLE_EQ(q.x(), 10);
  Eigen::Vector2d a(20, 20), b(30, 30);
  EXPECT_FALSE(clip_segment(0, 0, 10, 10, &a, &b, &cut));
}

}  // namespace
}  // namespace rangecal
