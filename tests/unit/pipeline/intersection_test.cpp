// The intersect stage (docs/intersection.md, docs/outputs.md intersection.csv, §6 `rangecal intersect`):
// triangulated poles against the truth of synthetic seed-002-like cameras (1280×800, 20 µm, 135 mm, ~64 m
// from the poles), Table 4's mean row against hand computation, the predicted sigma_m against Monte Carlo,
// warnings that do not stop the other poles, the CSV format, and both CLI forms.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/io/intersection_csv.hpp"
#include "pipeline/stages/intersect_stage.hpp"
#include "pipeline/steps/intersection.hpp"
#include "support/paths.hpp"
#include "support/pole_field.hpp"
#include "support/synthetic_camera.hpp"
#include "vision/triangulation/calibration_covariance.hpp"

namespace rangecal {
namespace {

TEST(Intersection, NoiseFreePicksRecoverTheTruth) {
  const auto poles = test::pole_field_truth();
  const IntersectionResult r = intersect_poles(test::pole_field_views(), poles, 0.5);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  ASSERT_EQ(r.poles.size(), poles.size());
  for (std::size_t i = 0; i < poles.size(); ++i) {
    const PoleIntersection& p = r.poles[i];
    EXPECT_EQ(p.id, poles[i].id);  // survey order
    EXPECT_TRUE(p.surveyed);
    EXPECT_EQ(p.role, poles[i].role);
    EXPECT_LT(p.dR, 1e-6) << p.id;
    EXPECT_LT((p.enu - poles[i].enu).norm(), 1e-6) << p.id;
    EXPECT_LT(p.rms_px, 1e-6);
    EXPECT_EQ(p.cameras, (std::vector<std::string>{"cam1", "cam2", "cam3"}));
    // 0.5 px at 64 m with 135 mm / 20 µm is ~5 mm per ray: a few mm in 3-D with three cameras.
    EXPECT_GT(p.sigma_m, 1e-3);
    EXPECT_LT(p.sigma_m, 1e-2);
  }
  EXPECT_EQ(r.check.n, 6);
  EXPECT_EQ(r.control.n, 2);
  EXPECT_LT(r.check.max_dR, 1e-6);
}

TEST(Intersection, MeanRowIsTable4MeanOfCheckPolesByHand) {
  // Survey = truth + offset, picks exact ⇒ d = −offset exactly (3-4-5 triangles for easy ΔR).
  auto survey = test::pole_field_truth();
  const Eigen::Vector3d off[8] = {{0.03, 0.04, 0},    {0, -0.03, 0.04}, {-0.06, 0, 0.08}, {0, 0, 0.02},
                                  {0.012, 0, -0.016}, {0, 0, 0},        {0.3, 0.4, 0},    {0, 0, 1.0}};
  for (int i = 0; i < 8; ++i) survey[i].enu += off[i];
  const IntersectionResult r = intersect_poles(test::pole_field_views(), survey, 0.5);
  EXPECT_NEAR(r.poles[0].d_enu.x(), -0.03, 1e-6);
  EXPECT_NEAR(r.poles[0].d_enu.y(), -0.04, 1e-6);
  EXPECT_NEAR(r.poles[2].dR, 0.10, 1e-6);
  ASSERT_EQ(r.check.n, 6);
  EXPECT_NEAR(r.check.mean_abs_d.x(), 0.102 / 6, 1e-6);  // (0.03 + 0.06 + 0.012) / 6
  EXPECT_NEAR(r.check.mean_abs_d.y(), 0.07 / 6, 1e-6);   // (0.04 + 0.03) / 6
  EXPECT_NEAR(r.check.mean_abs_d.z(), 0.156 / 6, 1e-6);  // (0.04 + 0.08 + 0.02 + 0.016) / 6
  EXPECT_NEAR(r.check.mean_dR, 0.04, 1e-6);              // (0.05 + 0.05 + 0.10 + 0.02 + 0.02 + 0) / 6
  EXPECT_NEAR(r.check.max_dR, 0.10, 1e-6);
  EXPECT_NEAR(r.check.rms_dR, std::sqrt((0.0025 * 2 + 0.01 + 0.0004 * 2) / 6), 1e-6);
  // Control poles (0.5 m and 1 m off) stay out of the check figures.
  EXPECT_NEAR(r.control.mean_dR, 0.75, 1e-6);
  // The rows of intersection.csv are the check poles only, and read back give the same mean row.
  const auto rows = intersection_rows(r);
  ASSERT_EQ(rows.size(), 6u);
  const IntersectionMeans back =
      intersection_means(parse_intersection_csv(format_intersection_csv(rows), "x"));
  EXPECT_NEAR(back.mean_dR, 0.04, 1e-4);
  EXPECT_NEAR(back.mean_abs_d.z(), 0.026, 1e-4);
}

TEST(Intersection, PredictedSigmaMatchesMonteCarloOfNoisyPicks) {
  const auto poles = test::pole_field_truth();
  const auto exact = test::pole_field_views();
  std::mt19937_64 rng(4511);
  std::normal_distribution<double> g(0.0, 0.5);
  const int trials = 300;
  double sum_dR = 0, sum_dR2 = 0, sum_sigma = 0;
  int n = 0;
  for (int t = 0; t < trials; ++t) {
    auto views = exact;
    for (auto& v : views)
      for (auto& p : v.picks) p.uv += Eigen::Vector2d(g(rng), g(rng));
    const IntersectionResult r = intersect_poles(views, poles, 0.5);
    ASSERT_EQ(r.check.n, 6);
    sum_dR += r.check.mean_dR * r.check.n;
    sum_dR2 += r.check.rms_dR * r.check.rms_dR * r.check.n;
    sum_sigma += r.check.mean_sigma_m * r.check.n;
    n += r.check.n;
  }
  const double mean_dR = sum_dR / n, rms_dR = std::sqrt(sum_dR2 / n), sigma = sum_sigma / n;
  // sigma_m is the predicted RMS of ΔR: Monte Carlo RMS within 10 %.
  EXPECT_NEAR(rms_dR / sigma, 1.0, 0.10) << "rms " << rms_dR << " predicted " << sigma;
  // Mean ΔR of a Gaussian error vector lies between √(2/π) ≈ 0.80 (one dominant axis) and
  // √(8/(3π)) ≈ 0.92 (isotropic) of its RMS: within 20 % of sigma_m.
  EXPECT_GT(mean_dR / sigma, 0.80 * 0.95);
  EXPECT_LT(mean_dR / sigma, 1.0);
  ::testing::Test::RecordProperty("mean_dR_mm", std::to_string(mean_dR * 1e3));
  ::testing::Test::RecordProperty("rms_dR_mm", std::to_string(rms_dR * 1e3));
  ::testing::Test::RecordProperty("predicted_sigma_mm", std::to_string(sigma * 1e3));
  std::printf("noisy picks 0.5 px, 3 cameras: mean dR %.3f mm, RMS dR %.3f mm, predicted sigma_m %.3f mm\n",
              mean_dR * 1e3, rms_dR * 1e3, sigma * 1e3);
}

TEST(Intersection, CalibrationCovarianceRaisesSigma) {
  const auto poles = test::pole_field_truth();
  auto views = test::pole_field_views();
  const double pick_only = intersect_poles(views, poles, 0.5).poles[0].sigma_m;
  // A 5 cm camera-centre uncertainty on cam1 must show in the predicted error of every pole.
  CalibrationResult cal;
  cal.parameters = test::parameters({"CE", "CN", "CU"});
  cal.covariance = Eigen::Matrix3d::Identity() * 0.05 * 0.05;
  bool usable = false;
  views[0].calibration = camera_covariance(cal, &usable);
  EXPECT_TRUE(usable);
  const double with_cal = intersect_poles(views, poles, 0.5).poles[0].sigma_m;
  // (cam1 weighs less for it: 1.47× here, 1.5× and more were the views weighed by their picks alone)
  EXPECT_GT(with_cal, pick_only * 1.3);
  // A covariance that does not match its names is not used (and says so).
  cal.covariance = Eigen::MatrixXd();
  EXPECT_TRUE(camera_covariance(cal, &usable).parameters.empty());
  EXPECT_FALSE(usable);
}

// One pole's X as a function of every camera's parameters and picks, differentiated numerically
// (central differences through the whole triangulation, weighted as the intersection weighs the
// views: their pick σ and their calibrations' covariances), and its covariance propagated directly:
// Σ_X = J_θ·Σ_joint·J_θᵀ + σ_pick²·J_uv·J_uvᵀ. Independent of triangulation.cpp's analytic
// Jacobians and of how it assembles the cross terms.
double direct_sigma(const std::vector<IntersectCamera>& views, const std::string& pole,
                    const std::vector<CameraParameter>& params, const Eigen::MatrixXd& joint,
                    double pick_sigma_px, const Eigen::VectorXd& scale) {
  const std::size_t nc = views.size(), np = params.size();
  auto solve = [&](const Eigen::VectorXd& dtheta, const Eigen::VectorXd& duv) {
    std::vector<TriangulationView> tv;
    for (std::size_t c = 0; c < nc; ++c) {
      TriangulationView v;
      const Eigen::VectorXd x0 = parameter_values(views[c].camera, params);
      v.camera = camera_with_parameters(
          views[c].camera, params,
          x0 + dtheta.segment(static_cast<Eigen::Index>(c * np), static_cast<Eigen::Index>(np)));
      for (const PolePick& p : views[c].picks)
        if (p.id == pole) v.uv_px = p.uv + duv.segment<2>(static_cast<Eigen::Index>(2 * c));
      // The same weights as the intersection's: each view's pick σ and its calibration's covariance.
      v.pick_sigma_px = pick_sigma_px;
      v.calibration = views[c].calibration;
      tv.push_back(v);
    }
    // The joint covariance's cross blocks weigh the views too (zero blocks for independent cameras).
    CrossCovariances cross(nc, std::vector<Eigen::MatrixXd>(nc));
    for (std::size_t a = 0; a < nc; ++a)
      for (std::size_t b = 0; b < nc; ++b)
        if (a != b)
          cross[a][b] = joint.block(static_cast<Eigen::Index>(a * np), static_cast<Eigen::Index>(b * np),
                                    static_cast<Eigen::Index>(np), static_cast<Eigen::Index>(np));
    return triangulate_point(tv, "pole", &cross).point;
  };
  const auto n = static_cast<Eigen::Index>(nc * np);
  Eigen::MatrixXd Jt(3, n), Ju(3, static_cast<Eigen::Index>(2 * nc));
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
    d[i] = 0.01 * scale[i];
    const Eigen::VectorXd z = Eigen::VectorXd::Zero(2 * static_cast<Eigen::Index>(nc));
    Jt.col(i) = (solve(d, z) - solve(-d, z)) / (2 * d[i]);
  }
  for (Eigen::Index i = 0; i < Ju.cols(); ++i) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(Ju.cols());
    d[i] = 0.01;
    Ju.col(i) = (solve(Eigen::VectorXd::Zero(n), d) - solve(Eigen::VectorXd::Zero(n), -d)) / 0.02;
  }
  const Eigen::Matrix3d cov =
      Jt * joint * Jt.transpose() + pick_sigma_px * pick_sigma_px * Ju * Ju.transpose();
  return std::sqrt(cov.trace());
}

TEST(Intersection, JointCovarianceOfANetworkEqualsDirectPropagation) {
  // Cameras calibrated together (a network) carry correlated errors: a joint covariance over all
  // cameras' f, rotation and centre, with strong cross-camera blocks.
  const std::vector<CameraParameter> params = {CameraParameter::f,  CameraParameter::wx, CameraParameter::wy,
                                               CameraParameter::wz, CameraParameter::CE, CameraParameter::CN,
                                               CameraParameter::CU};
  auto views = test::pole_field_views();
  const std::size_t nc = views.size(), np = params.size();
  const auto n = static_cast<Eigen::Index>(nc * np);
  Eigen::VectorXd scale(n);
  for (std::size_t c = 0; c < nc; ++c)
    scale.segment(static_cast<Eigen::Index>(c * np), static_cast<Eigen::Index>(np)) << 0.05, 3e-5, 3e-5, 3e-5,
        0.01, 0.01, 0.01;
  std::mt19937_64 rng(77);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd A(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index k = 0; k < n; ++k) A(i, k) = g(rng);
  // A random part plus a shared one: each parameter's error correlated 0.7 across cameras (as a
  // datum error common to all cameras would make it).
  Eigen::MatrixXd shared(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index k = 0; k < n; ++k)
      shared(i, k) = i % static_cast<Eigen::Index>(np) == k % static_cast<Eigen::Index>(np) ? 1 : 0;
  const Eigen::MatrixXd corr =
      0.3 * ((A * A.transpose()) / static_cast<double>(n) + 0.2 * Eigen::MatrixXd::Identity(n, n)) +
      0.7 * shared;
  const Eigen::MatrixXd joint = scale.asDiagonal() * corr * scale.asDiagonal();
  CrossCovariances cross(nc, std::vector<Eigen::MatrixXd>(nc));
  for (std::size_t a = 0; a < nc; ++a) {
    const auto ia = static_cast<Eigen::Index>(a * np);
    views[a].calibration = {
        params, joint.block(ia, ia, static_cast<Eigen::Index>(np), static_cast<Eigen::Index>(np))};
    for (std::size_t b = 0; b < nc; ++b)
      if (a != b)
        cross[a][b] = joint.block(ia, static_cast<Eigen::Index>(b * np), static_cast<Eigen::Index>(np),
                                  static_cast<Eigen::Index>(np));
  }
  const auto poles = test::pole_field_truth();
  const double pick = 0.5;
  const IntersectionResult indep = intersect_poles(views, poles, pick);
  const IntersectionResult net = intersect_poles(views, poles, pick, &cross);
  ASSERT_EQ(net.poles.size(), poles.size());
  Eigen::MatrixXd block_diag = Eigen::MatrixXd::Zero(n, n);
  for (std::size_t a = 0; a < nc; ++a) {
    const auto ia = static_cast<Eigen::Index>(a * np), m = static_cast<Eigen::Index>(np);
    block_diag.block(ia, ia, m, m) = joint.block(ia, ia, m, m);
  }
  for (std::size_t i = 0; i < poles.size(); ++i) {
    const double want_joint = direct_sigma(views, poles[i].id, params, joint, pick, scale);
    const double want_indep = direct_sigma(views, poles[i].id, params, block_diag, pick, scale);
    EXPECT_NEAR(net.poles[i].sigma_m, want_joint, 2e-3 * want_joint) << poles[i].id;
    EXPECT_NEAR(indep.poles[i].sigma_m, want_indep, 2e-3 * want_indep) << poles[i].id;
    // The cross blocks matter: the joint σ is not the independent-camera one.
    EXPECT_GT(std::abs(net.poles[i].sigma_m - indep.poles[i].sigma_m), 0.03 * indep.poles[i].sigma_m)
        << poles[i].id << " joint " << net.poles[i].sigma_m << " independent " << indep.poles[i].sigma_m;
  }
}

TEST(Intersection, OneCameraPolesUnknownIdsAndFailuresWarnButOthersProceed) {
  auto views = test::pole_field_views();
  // A2 picked only in cam1.
  for (int k : {1, 2}) views[k].picks.erase(views[k].picks.begin() + 1);
  // Z9 (not in the survey) in cam1 and cam2: triangulated, not compared.
  PolePick z{"Z9", Eigen::Vector2d::Zero(), 0};
  ASSERT_TRUE(project(views[0].camera, Eigen::Vector3d(0.5, 0.5, 4.0), &z.uv));
  views[0].picks.push_back(z);
  ASSERT_TRUE(project(views[1].camera, Eigen::Vector3d(0.5, 0.5, 4.0), &z.uv));
  views[1].picks.push_back(z);
  // PAR seen by cam3 and a twin of cam3 at the same place: parallel rays, triangulation fails.
  IntersectCamera twin = views[2];
  twin.id = "cam3b";
  twin.picks = {views[2].picks[0]};
  twin.picks[0].id = "PAR";
  views[2].picks.push_back(twin.picks[0]);
  views.push_back(twin);

  const IntersectionResult r = intersect_poles(views, test::pole_field_truth(), 0.5);
  auto warned = [&](const std::string& a, const std::string& b) {
    for (const auto& w : r.warnings)
      if (w.find(a) != std::string::npos && w.find(b) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(warned("'A2'", "cam1"));
  EXPECT_TRUE(warned("'Z9'", "cam1"));
  EXPECT_TRUE(warned("'PAR'", "triangulation failed"));
  EXPECT_TRUE(warned("'PAR'", "cam3b"));
  EXPECT_EQ(r.warnings.size(), 4u);  // PAR is also not in the survey
  // The other seven poles plus Z9.
  ASSERT_EQ(r.poles.size(), 8u);
  EXPECT_EQ(r.check.n, 5);
  EXPECT_LT(r.check.max_dR, 1e-6);
  EXPECT_EQ(r.poles.back().id, "Z9");
  EXPECT_FALSE(r.poles.back().surveyed);
  EXPECT_LT((r.poles.back().enu - Eigen::Vector3d(0.5, 0.5, 4.0)).norm(), 1e-6);
  EXPECT_EQ(intersection_rows(r).size(), 5u);  // Z9 is not a check pole
}

TEST(IntersectionCsv, ExactColumnsFixedDecimalsRoundTripAndByteIdentical) {
  auto survey = test::pole_field_truth();
  survey[0].enu += Eigen::Vector3d(0.01234, 0.00002, 0);  // dN rounds to −0.0000 → "0.0000"
  const IntersectionResult r = intersect_poles(test::pole_field_views(), survey, 0.5);
  const std::string text = format_intersection_csv(intersection_rows(r));
  EXPECT_EQ(text, format_intersection_csv(
                      intersection_rows(intersect_poles(test::pole_field_views(), survey, 0.5))));
  EXPECT_EQ(text.substr(0, text.find('\n')), "id,E,N,U,E_survey,N_survey,U_survey,dE,dN,dU,dR,sigma_m");
  const std::string line1 =
      text.substr(text.find('\n') + 1, text.find('\n', text.find('\n') + 1) - text.find('\n') - 1);
  const std::string start = "A1,-3.0000,-2.0000,3.5000,-2.9877,-2.0000,3.5000,-0.0123,0.0000,";
  EXPECT_EQ(line1.substr(0, start.size()), start);
  EXPECT_EQ(text.find("-0.0000"), std::string::npos);
  const auto rows = parse_intersection_csv(text, "intersection.csv");
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows[0].id, "A1");
  EXPECT_EQ(rows[0].line, 2);
  EXPECT_NEAR(rows[0].dR, 0.01234, 5e-5);
  EXPECT_NEAR(rows[5].sigma_m, r.poles[5].sigma_m, 5e-5);
  // Malformed rows name file, line and column.
  try {
    parse_intersection_csv(
        "id,E,N,U,E_survey,N_survey,U_survey,dE,dN,dU,dR,sigma_m\nA1,1,2,3,1,2,3,0,0,0,x,0\n", "i.csv");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.field(), "dR");
  }
}

}  // namespace
}  // namespace rangecal
