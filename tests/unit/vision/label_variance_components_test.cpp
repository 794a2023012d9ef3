// Each camera's label σ estimated from the views' disagreement
// (vision/triangulation/label_variance_components.hpp) and used by the trajectory
// (vision/triangulation/target_trajectory.hpp): against simulated truth over twenty missions with
// label noise unlike the σ stated, per camera; against the closed-form a-posteriori variance factor
// for one scale; cameras the geometry cannot tell apart share one scale; gross labels do not set it.
#include "vision/triangulation/label_variance_components.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "vision/camera/camera_parameters.hpp"
#include "vision/triangulation/target_trajectory.hpp"

#include "support/synthetic_camera.hpp"

namespace rangecal {
namespace {

TrajectoryOptions estimating() {
  TrajectoryOptions o;
  o.estimate_label_sigma = true;
  return o;
}

constexpr std::int64_t kT0 = 1'800'000'000'000'000'000;  // 2027-01-15T08:00:00Z, a whole second

// A drone-like target: a 6-m circle at 8 m/s, 18–22 m up, ~64 m from the cameras.
Eigen::Vector3d target_at(double t) {
  const double w = 8.0 / 6.0;
  return {6 * std::cos(w * t), 6 * std::sin(w * t), 20 + 2 * std::sin(0.3 * t)};
}

struct Rig {
  const char* id;
  Eigen::Vector3d centre;
  double fps, start_s, true_sigma_px;
};

// Cameras labelling the target with pixel noise of σ true_sigma_px each, while every camera states
// `stated_px`; clocks off by N(0, 2 ms) plus 2 ms of jitter per frame, stated. `gross` labels of the
// first camera are off by 40 px.
std::vector<TrajectoryCamera> simulate(std::mt19937_64* rng, const std::vector<Rig>& rig, double stated_px,
                                       double seconds, int gross = 0, double timing_s = 0.002) {
  std::normal_distribution<double> n01(0, 1);
  const Eigen::Vector3d aim(0, 0, 21);
  std::vector<TrajectoryCamera> out;
  for (const Rig& r : rig) {
    TrajectoryCamera c;
    c.id = r.id;
    c.camera = test::range_camera_at(r.id, r.centre, aim);
    c.label_sigma_px = stated_px;
    const double clock_error = timing_s * n01(*rng);
    for (int j = 0; r.start_s + j / r.fps < seconds + 0.1; ++j) {
      const double stated = r.start_s + j / r.fps;
      TimedLabel l;
      l.t = UtcTime{kT0 + std::llround(stated * 1e9)};
      EXPECT_TRUE(project(c.camera, target_at(stated + clock_error + timing_s * n01(*rng)), &l.uv_px));
      l.uv_px += r.true_sigma_px * Eigen::Vector2d(n01(*rng), n01(*rng));
      l.timing_sigma_s = std::hypot(timing_s, timing_s);
      c.labels.push_back(l);
    }
    out.push_back(std::move(c));
  }
  for (int g = 0; g < gross; ++g) out[0].labels[static_cast<std::size_t>(10 + 17 * g)].uv_px.x() += 40;
  return out;
}

const std::vector<Rig> kThree = {{"west", {-46, -44, 1.5}, 50, 0.003, 0.6},
                                 {"east", {45, -46, 1.8}, 60, 0.011, 0.9},
                                 {"north", {4, 62, 2.5}, 47, 0.017, 1.2}};

double seconds_of(UtcTime t) {
  return 1e-9 * static_cast<double>(t.ns - kT0);
}

// The σ of a camera's label interpolated to the instants, from its labels' own: between labels a and
// b at weight w the noise variance is ((1 − w)² + w²)·σ², averaged over the instants it sees.
double interpolated_sigma(const TrajectoryCamera& c, const std::vector<UtcTime>& instants, double sigma) {
  double sum = 0;
  int n = 0;
  for (UtcTime t : instants)
    for (std::size_t j = 1; j < c.labels.size(); ++j)
      if (c.labels[j - 1].t <= t && t < c.labels[j].t) {
        const double w =
            seconds_between(c.labels[j - 1].t, t) / seconds_between(c.labels[j - 1].t, c.labels[j].t);
        sum += (1 - w) * (1 - w) + w * w;
        ++n;
      }
  return sigma * std::sqrt(sum / n);
}

// What the scale of camera c measures: with the labels' correlation estimated, a label's σ on its own
// frame; without, that of its labels as interpolated to the instants.
double measured_sigma(const LabelVcResult& vc, std::size_t c, const TrajectoryCamera& cam,
                      const std::vector<UtcTime>& instants, double true_sigma_px) {
  return vc.correlation_estimated[c] ? true_sigma_px : interpolated_sigma(cam, instants, true_sigma_px);
}

double z_rms(const Trajectory& tr, double* e2, double* z2, std::size_t* n) {
  for (const TrajectoryPoint& p : tr.points) {
    const double e = (p.fix.point - target_at(seconds_of(p.t))).squaredNorm();
    *z2 += e / (p.fix.sigma_m * p.fix.sigma_m);
    *e2 += e;
    ++*n;
  }
  return std::sqrt(*z2 / static_cast<double>(*n));
}

// Twenty missions of 30 s, three cameras whose labels scatter 0.6, 0.9 and 1.2 px where 0.5 px is
// stated, time code to 0.2 ms: each camera's σ — that of its labels interpolated to the instants —
// found within 25 % in every mission (3σ of the least determined camera; 59 of 60 within 20 %), its
// stated 1σ matching the missions' spread, and the trajectory's σ holds with the estimate where the
// stated σ under-covers.
TEST(LabelVarianceComponents, EachCamerasSigmaOverTwentyMissions) {
  std::mt19937_64 rng(2027);
  constexpr int kMissions = 20;
  // Per camera, over the missions: estimated / true σ and the stated 1σ of that ratio; the labels'
  // correlation where it was estimated, with its 1σ.
  std::vector<std::vector<double>> ratio(3), ratio_sd(3), rho(3), rho_sd(3);
  int within_20 = 0;
  double e2_est = 0, z2_est = 0, e2_stated = 0, z2_stated = 0;
  std::size_t n_est = 0, n_stated = 0;
  for (int m = 0; m < kMissions; ++m) {
    const std::vector<TrajectoryCamera> cams = simulate(&rng, kThree, 0.5, 30, 0, 0.0002);
    const std::vector<UtcTime> t = trajectory_instants(cams, 25);
    const Trajectory tr = estimate_trajectory(cams, t, nullptr, estimating());
    ASSERT_TRUE(tr.label_sigma_estimated);
    for (std::size_t c = 0; c < 3; ++c) {
      const LabelVcResult& vc = tr.label_sigma;
      EXPECT_EQ(vc.kind[c], LabelScaleKind::own) << "mission " << m << " camera " << c;
      const double truth = measured_sigma(vc, c, cams[c], t, kThree[c].true_sigma_px);
      const double r = 0.5 * vc.sigma_scale[c] / truth;
      EXPECT_NEAR(r, 1, 0.25) << "mission " << m << " camera " << c;
      within_20 += std::abs(r - 1) <= 0.2 ? 1 : 0;
      ratio[c].push_back(r);
      ratio_sd[c].push_back(0.5 * vc.sigma_scale_sd[c] / truth);
      if (vc.correlation_estimated[c]) {
        rho[c].push_back(vc.correlation[c]);
        rho_sd[c].push_back(vc.correlation_sd[c]);
      }
    }
    z_rms(tr, &e2_est, &z2_est, &n_est);
    z_rms(estimate_trajectory(cams, t, nullptr), &e2_stated, &z2_stated, &n_stated);
  }
  const auto mean_of = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x / static_cast<double>(v.size());
    return s;
  };
  for (std::size_t c = 0; c < 3; ++c) {
    const double mean = mean_of(ratio[c]);
    double var = 0;
    for (double r : ratio[c]) var += (r - mean) * (r - mean) / (kMissions - 1);
    const double stated_sd = mean_of(ratio_sd[c]);
    std::printf("camera %s: labels %.2f px, estimated / true %.3f, spread %.4f, stated sd %.4f", kThree[c].id,
                kThree[c].true_sigma_px, mean, std::sqrt(var), stated_sd);
    EXPECT_NEAR(mean, 1, 0.05);
    // The spread of twenty estimates is itself uncertain by ~16 %: within [0.6, 1.6] of what is stated.
    EXPECT_GT(std::sqrt(var) / stated_sd, 0.6);
    EXPECT_LT(std::sqrt(var) / stated_sd, 1.6);
    // The simulated labels are independent from frame to frame: ρ = 0, within 3 of its stated 1σ
    // (north's frames fall at varying places between the instants: its ρ is estimated).
    if (c == 2) {
      EXPECT_GE(rho[c].size(), 10u);
    }
    if (!rho[c].empty()) {
      std::printf("; correlation in %zu missions, mean %.3f (stated sd %.3f)", rho[c].size(), mean_of(rho[c]),
                  mean_of(rho_sd[c]));
      EXPECT_LT(std::abs(mean_of(rho[c])),
                3 * mean_of(rho_sd[c]) / std::sqrt(static_cast<double>(rho[c].size())));
    }
    std::printf("\n");
  }
  std::printf("%d of %d estimates within 20 %% of the truth\n", within_20, 3 * kMissions);
  EXPECT_GE(within_20, 57);  // 95 %: the least determined camera's 1σ is ~8 %
  const double z_est = std::sqrt(z2_est / static_cast<double>(n_est));
  const double z_stated = std::sqrt(z2_stated / static_cast<double>(n_stated));
  std::printf("trajectory: estimated σ error rms %.2f cm z rms %.3f; stated σ %.2f cm z rms %.3f\n",
              100 * std::sqrt(e2_est / static_cast<double>(n_est)), z_est,
              100 * std::sqrt(e2_stated / static_cast<double>(n_stated)), z_stated);
  EXPECT_GT(z_est, 0.85);
  EXPECT_LT(z_est, 1.15);
  EXPECT_GT(z_stated, 1.25);
}

// One scale over views whose only other covariance is zero: REML's estimate is the classic
// a-posteriori variance factor Σ vᵀ·v / (σ²·Σ dof), v the unweighted least-squares residuals —
// computed here independently.
TEST(LabelVarianceComponents, OneScaleIsTheAPosterioriVarianceFactor) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n01(0, 1);
  std::vector<LabelVcInstant> instants;
  double vtv = 0;
  int dof = 0;
  constexpr double kGiven = 0.4;
  for (int k = 0; k < 300; ++k) {
    const int m = 2 + k % 3;
    LabelVcInstant inst;
    Eigen::MatrixXd A(2 * m, 3);
    Eigen::VectorXd r(2 * m);
    for (int i = 0; i < m; ++i) {
      LabelVcView v;
      v.camera = 0;
      v.label_sigma_px = kGiven;
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 3; ++b) v.d_pixel_d_point(a, b) = 30 * n01(rng);
      v.residual_px = 0.7 * Eigen::Vector2d(n01(rng), n01(rng));
      A.block<2, 3>(2 * i, 0) = v.d_pixel_d_point;
      r.segment<2>(2 * i) = v.residual_px;
      inst.push_back(v);
    }
    const Eigen::VectorXd v = r - A * A.colPivHouseholderQr().solve(r);
    vtv += v.squaredNorm();
    dof += 2 * m - 3;
    instants.push_back(inst);
  }
  LabelVcOptions options;
  options.tolerance = 1e-12;
  const LabelVcResult res = estimate_label_variance_components(instants, 1, 0, options);
  ASSERT_TRUE(res.converged);
  ASSERT_EQ(res.kind[0], LabelScaleKind::own);
  EXPECT_EQ(res.excluded, 0u);
  const double factor = vtv / (kGiven * kGiven * dof);
  EXPECT_NEAR(res.sigma_scale[0] * res.sigma_scale[0] / factor, 1, 1e-9);
  // Its 1σ: var(θ̂) = 2θ²/dof for Gaussian residuals.
  EXPECT_NEAR(res.sigma_scale_sd[0] / (res.sigma_scale[0] / std::sqrt(2.0 * dof)), 1, 1e-6);
  EXPECT_NEAR(res.redundancy[0], dof, 1e-6);
}

// Two cameras only, placed symmetrically: every instant's one degree of freedom is shared between
// them in the same proportion, so their scales cannot be told apart. They share one — the labels'
// a-posteriori variance factor — which is then well determined: the root mean square of the two
// cameras' interpolated σ over the one given.
TEST(LabelVarianceComponents, CamerasTheGeometryCannotSeparateShareOneScale) {
  std::mt19937_64 rng(11);
  const std::vector<Rig> pair = {{"west", {-45, -45, 1.5}, 50, 0.003, 0.8},
                                 {"east", {45, -45, 1.5}, 50, 0.013, 0.8}};
  const std::vector<TrajectoryCamera> cams = simulate(&rng, pair, 0.4, 12, 0, 0.0002);
  const std::vector<UtcTime> t = trajectory_instants(cams, 25);
  const Trajectory tr = estimate_trajectory(cams, t, nullptr, estimating());
  const double a = interpolated_sigma(cams[0], t, 0.8), b = interpolated_sigma(cams[1], t, 0.8);
  const double expected = std::sqrt((a * a + b * b) / 2) / 0.4;
  for (std::size_t c = 0; c < 2; ++c) {
    EXPECT_EQ(tr.label_sigma.kind[c], LabelScaleKind::common);
    EXPECT_NEAR(tr.label_sigma.sigma_scale[c] / expected, 1, 0.1);
  }
  EXPECT_EQ(tr.label_sigma.sigma_scale[0], tr.label_sigma.sigma_scale[1]);
}

// Calibrations each off by a draw from the covariance they state — 2 cm of centre, 0.2 mrad of
// attitude, 1 px of principal point: at 64 m with a 135-mm lens ~1.5 px at the pixel, three times the
// labels' 0.5 px — over twenty missions. The calibration's error is one draw for the whole track; the
// estimate takes it as such (a random effect common to every instant) and finds the labels' σ. Taken
// as exact, the calibration's error is read as label noise.
TEST(LabelVarianceComponents, CalibrationErrorsAreNotReadAsLabelNoise) {
  const std::vector<CameraParameter> params = {CameraParameter::u0, CameraParameter::v0, CameraParameter::wx,
                                               CameraParameter::wy, CameraParameter::wz, CameraParameter::CE,
                                               CameraParameter::CN, CameraParameter::CU};
  Eigen::VectorXd sd(8);
  sd << 1, 1, 2e-4, 2e-4, 2e-4, 0.02, 0.02, 0.02;
  std::mt19937_64 rng(23);
  std::normal_distribution<double> n01(0, 1);
  const std::vector<Rig> rig = {{"west", {-46, -44, 1.5}, 50, 0.003, 0.5},
                                {"east", {45, -46, 1.8}, 60, 0.011, 0.5},
                                {"north", {4, 62, 2.5}, 47, 0.017, 0.5}};
  double ratio_with = 0, ratio_without = 0, ratio2 = 0, ratio_sd = 0;
  int n = 0;
  for (int m = 0; m < 20; ++m) {
    std::vector<TrajectoryCamera> cams = simulate(&rng, rig, 0.5, 12, 0, 0.0002);
    const std::vector<UtcTime> t = trajectory_instants(cams, 25);
    std::vector<TrajectoryCamera> exact = cams;
    for (std::size_t c = 0; c < cams.size(); ++c) {
      Eigen::VectorXd delta(8);
      for (int i = 0; i < 8; ++i) delta[i] = sd[i] * n01(rng);
      cams[c].camera =
          camera_with_parameters(cams[c].camera, params, parameter_values(cams[c].camera, params) + delta);
      cams[c].calibration.parameters = params;
      cams[c].calibration.covariance = sd.cwiseAbs2().asDiagonal();
      exact[c].camera = cams[c].camera;
    }
    const Trajectory with = estimate_trajectory(cams, t, nullptr, estimating());
    const Trajectory without = estimate_trajectory(exact, t, nullptr, estimating());
    // The same covariance given as a joint one (cross blocks of zeros): the calibrations whitened
    // together, one u for all cameras — the same estimate.
    if (m < 3) {
      const CrossCovariances zeros(3, std::vector<Eigen::MatrixXd>(3, Eigen::MatrixXd::Zero(8, 8)));
      const Trajectory joint = estimate_trajectory(cams, t, &zeros, estimating());
      for (std::size_t c = 0; c < cams.size(); ++c)
        EXPECT_NEAR(joint.label_sigma.sigma_scale[c], with.label_sigma.sigma_scale[c], 1e-6);
    }
    for (std::size_t c = 0; c < cams.size(); ++c) {
      const LabelVcResult& vc = with.label_sigma;
      const double truth = measured_sigma(vc, c, cams[c], t, 0.5);
      const double r = 0.5 * vc.sigma_scale[c] / truth;
      ratio_with += r;
      ratio2 += r * r;
      ratio_sd += 0.5 * vc.sigma_scale_sd[c] / truth;
      ratio_without +=
          0.5 * without.label_sigma.sigma_scale[c] / measured_sigma(without.label_sigma, c, exact[c], t, 0.5);
      ++n;
    }
  }
  ratio_with /= n;
  ratio_without /= n;
  const double spread = std::sqrt((ratio2 / n - ratio_with * ratio_with) * n / (n - 1));
  ratio_sd /= n;
  std::printf(
      "estimated / true label σ: %.3f with the calibrations' covariance (spread %.3f, stated sd %.3f), %.3f "
      "taken "
      "as exact\n",
      ratio_with, spread, ratio_sd, ratio_without);
  EXPECT_NEAR(ratio_with, 1, 0.1);
  // The Fisher σ with the calibrations' errors integrated out against the missions' spread (60
  // estimates: the spread known to ~9 %).
  EXPECT_GT(spread / ratio_sd, 0.7);
  EXPECT_LT(spread / ratio_sd, 1.4);
  EXPECT_GT(ratio_without, 1.5);
}

// Twelve labels of one camera off by 40 px (60× its σ) must not set its scale: the instants they
// reach are left out, the rest give the σ.
TEST(LabelVarianceComponents, GrossLabelsDoNotSetTheScale) {
  std::mt19937_64 rng(17);
  const std::vector<TrajectoryCamera> cams = simulate(&rng, kThree, 0.5, 12, 12, 0.0002);
  const std::vector<UtcTime> t = trajectory_instants(cams, 25);
  const Trajectory tr = estimate_trajectory(cams, t, nullptr, estimating());
  EXPECT_GE(tr.label_sigma.excluded, 10u);
  ASSERT_EQ(tr.label_sigma.kind[0], LabelScaleKind::own);
  const double truth = measured_sigma(tr.label_sigma, 0, cams[0], t, kThree[0].true_sigma_px);
  EXPECT_NEAR(0.5 * tr.label_sigma.sigma_scale[0] / truth, 1, 0.2);
}

// A camera seen only where no other camera sees (one view per instant) cannot be judged: its σ is
// the one given, and said so.
TEST(LabelVarianceComponents, ACameraNeverSeenWithAnotherKeepsItsSigma) {
  std::vector<LabelVcInstant> instants(1);
  LabelVcView v;
  v.camera = 1;
  v.label_sigma_px = 1;
  instants[0].push_back(v);
  const LabelVcResult res = estimate_label_variance_components(instants, 2);
  for (std::size_t c = 0; c < 2; ++c) {
    EXPECT_EQ(res.kind[c], LabelScaleKind::as_given);
    EXPECT_EQ(res.sigma_scale[c], 1);
    EXPECT_EQ(res.sigma_scale_sd[c], 0);
  }
}

}  // namespace
}  // namespace rangecal
