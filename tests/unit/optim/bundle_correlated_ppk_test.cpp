// The per-camera bundle's σ under a correlated PPK error model (optim/bundle/correlated_ppk_covariance.hpp):
//   - under the bundle's own weighting (the default model) its covariance is the one it has always
//     given, bit for bit, and the meat of the sandwich is then JᵀJ;
//   - the O(n) forward recursion equals the n × n sums formed densely here, alone and in the meat;
//   - at the truth the sandwich is the independent one of tests/support/correlated_crb.hpp (a
//     one-camera network with the fixes as points, dense Σ_PPK, numeric derivatives), white and
//     correlated;
//   - over simulated one-camera missions with correlated errors (τ = 30 s) its σ hold (z-scores of f
//     and the camera centre), where the white bundle's do not.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "optim/bundle/bundle_covariance.hpp"
#include "optim/bundle/bundle_parameters.hpp"
#include "optim/bundle/correlated_ppk_covariance.hpp"
#include "support/correlated_crb.hpp"

namespace rangecal::test {
namespace {

using Eigen::MatrixXd;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::VectorXd;

/// The bundle's observations of `n` (one camera): each view's epoch at truth + ppk_error[k] under
/// diag(total²) with its time, its pixel at truth + pixel_noise[i].
std::vector<BundleObservation> observations(const CrbNetwork& n, const GaussMarkovPpk& model,
                                            const NetworkNoise& noise = {}) {
  const Vector3d s = model.total_sigma();
  std::vector<BundleObservation> obs;
  for (std::size_t i = 0; i < n.views.size(); ++i) {
    const std::size_t k = n.views[i].point;
    BundleObservation o;
    Vector2d uv;
    EXPECT_TRUE(project(n.cameras[0].truth, n.epochs[k], &uv));
    o.pixel = uv + (noise.pixel_noise.empty() ? Vector2d::Zero() : noise.pixel_noise[i]);
    o.world = n.epochs[k] + (noise.ppk_error.empty() ? Vector3d::Zero() : noise.ppk_error[k]);
    o.world_cov = s.cwiseProduct(s).asDiagonal();
    o.pixel_sigma_px = n.views[i].pixel_sigma_px;
    o.time_s = n.epoch_time_s[k];
    obs.push_back(o);
  }
  return obs;
}

BundleOptions ascent_options() {
  BundleOptions opt;
  opt.free = {"f", "k1", "pose"};
  opt.pixel_sigma_px = 0.1;
  return opt;
}

/// The truth off by f × 1.001, 3 cm in the centre and 0.2 mrad: the data bring it back.
Camera perturbed(const Camera& truth) {
  Camera s = truth;
  s.intr.f_mm *= 1.001;
  const Vector3d C = s.pose.center() + Vector3d(0.03, -0.02, 0.03);
  s.pose.R = Eigen::AngleAxisd(2e-4, Vector3d(1, -1, 0.5).normalized()).toRotationMatrix() * s.pose.R;
  s.pose.T = -s.pose.R * C;
  return s;
}

/// exp(−|Δt|/τ) summed over every pair, densely.
MatrixXd dense_kernel_sum(const MatrixXd& H, const std::vector<double>& t, double tau) {
  MatrixXd K = MatrixXd::Zero(H.rows(), H.rows());
  for (Eigen::Index i = 0; i < H.cols(); ++i)
    for (Eigen::Index j = 0; j < H.cols(); ++j)
      K += std::exp(-std::abs(t[static_cast<std::size_t>(i)] - t[static_cast<std::size_t>(j)]) / tau) *
           H.col(i) * H.col(j).transpose();
  return K;
}

double relative_difference(const MatrixXd& a, const MatrixXd& b) {
  return (a - b).norm() / b.norm();
}

TEST(BundleCorrelatedPpk, BundleWeightingIsTheCovarianceAsItWas) {
  AscentNetworkOptions o;
  o.ascents = 2, o.rate_hz = 2;
  const CrbNetwork n = one_camera(ascent_network(o));
  const GaussMarkovPpk m = measured_ppk_model(30);
  DeterministicRandom rng(11);
  NetworkNoise noise;
  noise.ppk_error = draw_correlated_ppk_errors(n.epoch_time_s, m, &rng);
  for (std::size_t i = 0; i < n.views.size(); ++i)
    noise.pixel_noise.push_back(0.1 * Vector2d(rng.normal(), rng.normal()));
  std::vector<BundleObservation> obs = observations(n, m, noise);
  std::vector<BundleObservation> untimed = obs;
  for (BundleObservation& ob : untimed) ob.time_s = std::numeric_limits<double>::quiet_NaN();
  const Camera start = perturbed(n.cameras[0].truth);
  BundleOptions opt = ascent_options();
  const BundleResult timed = bundle_adjust(start, obs, opt);
  const BundleResult before = bundle_adjust(start, untimed, opt);  // as before observations had a time
  opt.ppk_error = PpkErrorModel{};                                 // the default model, stated
  const BundleResult stated = bundle_adjust(start, obs, opt);
  ASSERT_EQ(before.covariance_unscaled.rows(), 8);
  // Bit for bit: the default model never enters the covariance.
  EXPECT_TRUE(timed.covariance_unscaled == before.covariance_unscaled);
  EXPECT_TRUE(stated.covariance_unscaled == before.covariance_unscaled);
  EXPECT_TRUE(stated.covariance_scaled == before.covariance_scaled);
  EXPECT_TRUE(stated.calibration.covariance == before.calibration.covariance);
  EXPECT_FALSE(stated.details.ppk_error_model.has_value());
  EXPECT_TRUE(is_bundle_weighting(PpkErrorModel{}));

  // The meat under the bundle's weighting is JᵀJ (each whitened residual has unit covariance), and
  // bundle_covariance_under at the solution gives the bundle's own covariance back.
  const Camera& cam = before.calibration.camera;
  std::vector<char> used(obs.size(), 1);
  for (std::size_t i : before.calibration.rejected) used[i] = 0;
  const auto W = whitening_matrices(cam, obs, opt.pixel_sigma_px);
  const WhitenedSystem sys =
      whitened_system(BundleParameterBlocks::from_camera(cam, before.calibration.clock_offset_s), cam, obs,
                      used, W, bundle_setup(opt), opt);
  const MatrixXd N = sys.J.transpose() * sys.J;
  EXPECT_LT(relative_difference(correlated_ppk_meat(sys.J, cam, obs, used, W, 0.1, PpkErrorModel{}), N),
            1e-12);
  const BundleCovariance again = bundle_covariance_under(PpkErrorModel{}, obs, opt, before.calibration);
  EXPECT_LT(relative_difference(again.covariance_unscaled, before.covariance_unscaled), 1e-9);
  EXPECT_NEAR(again.variance_factor, before.variance_factor, 1e-9 * before.variance_factor);
  EXPECT_EQ(again.gauss_markov_states, 0);

  // Under a GM model: the same estimate bit for bit, the sandwich scaled by the same variance factor,
  // and bundle_covariance_under gives it again after the solve.
  BundleOptions correlated = ascent_options();
  correlated.ppk_error = network_model(m);
  const BundleResult gm = bundle_adjust(start, obs, correlated);
  EXPECT_TRUE(gm.calibration.camera.pose.T == before.calibration.camera.pose.T);
  EXPECT_EQ(gm.calibration.camera.intr.f_mm, before.calibration.camera.intr.f_mm);
  EXPECT_EQ(gm.variance_factor, before.variance_factor);
  EXPECT_GT(gm.covariance_unscaled(0, 0), 4 * before.covariance_unscaled(0, 0));
  EXPECT_LT(relative_difference(gm.covariance_scaled, gm.variance_factor * gm.covariance_unscaled), 1e-15);
  const BundleCovariance after =
      bundle_covariance_under(correlated.ppk_error, obs, correlated, gm.calibration);
  EXPECT_LT(relative_difference(after.covariance_unscaled, gm.covariance_unscaled), 1e-9);
  EXPECT_EQ(after.gauss_markov_states, gm.details.gauss_markov_states);
  EXPECT_EQ(gm.details.gauss_markov_states, gm.calibration.reprojection.n_used);

  // A white scale alone (no GM part) is not the bundle's weighting: it scales the world part.
  PpkErrorModel half;
  half.white_scale_h = half.white_scale_v = 0.5;
  EXPECT_FALSE(is_bundle_weighting(half));
  const BundleCovariance smaller = bundle_covariance_under(half, obs, opt, before.calibration);
  EXPECT_LT(smaller.covariance_unscaled(0, 0), 0.8 * before.covariance_unscaled(0, 0));
}

TEST(BundleCorrelatedPpk, ForwardRecursionIsTheDenseSum) {
  // Irregular times with ties and a gap of many τ.
  DeterministicRandom rng(3);
  std::vector<double> t;
  double now = 0;
  for (int k = 0; k < 150; ++k) {
    now += (k % 17 == 5 ? 0.0 : 0.05 + rng.uniform()) + (k == 80 ? 400.0 : 0.0);
    t.push_back(now);
  }
  MatrixXd H(7, static_cast<Eigen::Index>(t.size()));
  for (Eigen::Index i = 0; i < H.rows(); ++i)
    for (Eigen::Index j = 0; j < H.cols(); ++j) H(i, j) = rng.normal();
  for (double tau : {0.3, 12.0, 1e4}) {
    const double d = relative_difference(exponential_kernel_sum(H, t, tau), dense_kernel_sum(H, t, tau));
    std::printf("kernel sum, τ %g s: O(n) vs dense %.1e relative\n", tau, d);
    EXPECT_LT(d, 1e-12) << tau;
  }
}

TEST(BundleCorrelatedPpk, SandwichIsTheDenseSandwich) {
  // The meat and the sandwich against Jᵀ·Σ_ε·J with Σ_ε (2n × 2n) formed here entry by entry from the
  // model: observations out of time order, two control poles (no time: white under their own Σ_X), a
  // centre prior, distinct horizontal and vertical τ and white scales.
  AscentNetworkOptions o;
  o.ascents = 3, o.rate_hz = 2;
  const CrbNetwork n = one_camera(ascent_network(o));
  const GaussMarkovPpk gm = measured_ppk_model(30);
  std::vector<BundleObservation> obs = observations(n, gm);
  std::reverse(obs.begin() + 10, obs.begin() + 60);
  for (const Vector3d& X : {Vector3d(-2, -1, 2.2), Vector3d(2, -1, 7.5)}) {
    BundleObservation pole;
    pole.world = X;
    ASSERT_TRUE(project(n.cameras[0].truth, X, &pole.pixel));
    pole.world_cov = Eigen::Matrix3d::Identity() * 9e-6;
    pole.pixel_sigma_px = 0.3;
    obs.insert(obs.begin() + 30, pole);
  }
  PpkErrorModel model = network_model(gm);
  model.tau_v_s = 70, model.white_scale_v = 0.45;
  BundleOptions opt = ascent_options();
  opt.priors.use_center = true;
  opt.priors.center_enu_m = n.cameras[0].truth.pose.center();
  opt.priors.center_sigma_m = Vector3d(0.01, 0.01, 0.02);
  const Camera& cam = n.cameras[0].truth;
  std::vector<char> used(obs.size(), 1);
  used[7] = 0;
  const auto W = whitening_matrices(cam, obs, opt.pixel_sigma_px);
  const WhitenedSystem sys =
      whitened_system(BundleParameterBlocks::from_camera(cam, 0), cam, obs, used, W, bundle_setup(opt), opt);

  // Σ_ε of the used observations' whitened residuals, then the prior rows' identity.
  std::vector<std::size_t> rows_of;
  for (std::size_t i = 0; i < obs.size(); ++i)
    if (used[i]) rows_of.push_back(i);
  const Eigen::Index m = static_cast<Eigen::Index>(rows_of.size());
  MatrixXd Sigma = MatrixXd::Identity(sys.J.rows(), sys.J.rows());
  const Vector3d S = model.white_scale(), sd = model.gm_sd(), tau = model.tau();
  for (Eigen::Index a = 0; a < m; ++a)
    for (Eigen::Index b = 0; b < m; ++b) {
      const BundleObservation& oa = obs[rows_of[static_cast<std::size_t>(a)]];
      const BundleObservation& ob = obs[rows_of[static_cast<std::size_t>(b)]];
      const std::size_t ia = rows_of[static_cast<std::size_t>(a)], ib = rows_of[static_cast<std::size_t>(b)];
      const Eigen::Matrix<double, 2, 3> Ja = pixel_jacobian_wrt_world(cam, oa.world);
      const Eigen::Matrix<double, 2, 3> Jb = pixel_jacobian_wrt_world(cam, ob.world);
      Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
      const bool fa = std::isfinite(oa.time_s), fb = std::isfinite(ob.time_s);
      if (a == b) {
        const double s = oa.pixel_sigma_px;
        const Eigen::Matrix3d white =
            fa ? Eigen::Matrix3d(S.asDiagonal() * oa.world_cov * S.asDiagonal()) : oa.world_cov;
        C = s * s * Eigen::Matrix2d::Identity() + Ja * white * Ja.transpose();
      }
      if (fa && fb) {
        Eigen::Matrix3d D = Eigen::Matrix3d::Zero();
        for (int x = 0; x < 3; ++x)
          D(x, x) = sd[x] * sd[x] * std::exp(-std::abs(oa.time_s - ob.time_s) / tau[x]);
        C += Ja * D * Jb.transpose();
      }
      Sigma.block(2 * a, 2 * b, 2, 2) = W[ia] * C * W[ib].transpose();
    }
  const MatrixXd dense_meat = sys.J.transpose() * Sigma * sys.J;
  const MatrixXd fast_meat = correlated_ppk_meat(sys.J, cam, obs, used, W, opt.pixel_sigma_px, model);
  const RankTestedInverse Ninv =
      estimate_covariance(sys.J, bundle_setup(opt).free_parameters(), cam, 60, 0, opt.rank_tolerance);
  ASSERT_FALSE(Ninv.rank_deficient);
  const MatrixXd dense = Ninv.covariance * dense_meat * Ninv.covariance;
  const MatrixXd fast =
      ppk_sandwich_covariance(Ninv.covariance, sys.J, cam, obs, used, W, opt.pixel_sigma_px, model);
  double worst = 0;
  for (Eigen::Index a = 0; a < dense.rows(); ++a)
    for (Eigen::Index b = 0; b < dense.cols(); ++b)
      worst = std::max(worst, std::abs(fast(a, b) - dense(a, b)) / std::sqrt(dense(a, a) * dense(b, b)));
  std::printf(
      "%lld observations: meat O(n) vs dense %.1e relative; sandwich entries within %.1e of √(C_ii·C_jj)\n",
      static_cast<long long>(m), relative_difference(fast_meat, dense_meat), worst);
  EXPECT_LT(relative_difference(fast_meat, dense_meat), 1e-9);
  EXPECT_LT(worst, 1e-9);
  // Not the white covariance: the correlated part more than doubles σ_f² here.
  EXPECT_GT(dense(0, 0), 2 * Ninv.covariance(0, 0));
}

TEST(BundleCorrelatedPpk, SandwichAtTheTruthIsTheIndependentOne) {
  // At the truth (noise-free data) the bundle's covariance against tests/support/correlated_crb's for
  // a one-camera network whose fixes are white-weighted points: its Cramér–Rao bound under the white
  // Σ_PPK, and its sandwich under the GM one (numeric derivatives there; measured 2.8e-9, held to 1e-6).
  AscentNetworkOptions o;
  o.rate_hz = 2;
  const CrbNetwork n = one_camera(ascent_network(o));
  for (double tau : {10.0, 100.0}) {
    const GaussMarkovPpk m = measured_ppk_model(tau);
    const std::vector<BundleObservation> obs = observations(n, m);
    const PpkJointCovariance white = ppk_joint_covariance(n.epoch_time_s, m.as_white());
    const PpkJointCovariance truth = ppk_joint_covariance(n.epoch_time_s, m);
    const CameraJointCovariance bound_white = cramer_rao_bound(n, white);
    const CameraJointCovariance bound_gm = sandwich_covariance(n, white, truth);
    CalibrationResult solution;
    solution.camera = n.cameras[0].truth;
    const BundleOptions opt = ascent_options();
    const BundleCovariance w = bundle_covariance_under(PpkErrorModel{}, obs, opt, solution);
    const BundleCovariance g = bundle_covariance_under(network_model(m), obs, opt, solution);
    ASSERT_EQ(g.free, n.cameras[0].free);
    EXPECT_EQ(g.gauss_markov_states, static_cast<int>(obs.size()));
    const VectorXd sw = bound_white.sigma(0), sg = bound_gm.sigma(0);
    double worst = 0;
    for (std::size_t k = 0; k < g.free.size(); ++k) {
      const auto j = static_cast<Eigen::Index>(k);
      const double rw = std::sqrt(w.covariance_unscaled(j, j)) / sw[j] - 1;
      const double rg = std::sqrt(g.covariance_unscaled(j, j)) / sg[j] - 1;
      EXPECT_LT(std::abs(rw), 1e-6) << parameter_name(g.free[k]);
      EXPECT_LT(std::abs(rg), 1e-6) << parameter_name(g.free[k]);
      worst = std::max({worst, std::abs(rw), std::abs(rg)});
    }
    std::printf(
        "τ %.0f s, %zu fixes: σ_f %.4f mm white, %.4f mm under GM; every σ within %.1e of the "
        "independent one\n",
        tau, obs.size(), std::sqrt(w.covariance_unscaled(0, 0)), std::sqrt(g.covariance_unscaled(0, 0)),
        worst);
  }
}

/// rms z-scores of f, CE, CN, CU over `missions` one-camera missions of `n` with correlated errors of
/// `m`: under the bundle's σ (the sandwich of the stated model) and under the white bundle's.
struct ZScores {
  VectorXd sandwich = VectorXd::Zero(4), white = VectorXd::Zero(4);
  double worst = 0;  ///< the largest |z| under the sandwich
};

ZScores z_scores(const CrbNetwork& n, const GaussMarkovPpk& m, int missions, std::uint64_t seed) {
  BundleOptions opt = ascent_options();
  opt.ppk_error = network_model(m);
  const Camera start = perturbed(n.cameras[0].truth);
  const std::vector<CameraParameter>& free = n.cameras[0].free;
  const CameraParameter scored[4] = {CameraParameter::f, kCenterParameters[0], kCenterParameters[1],
                                     kCenterParameters[2]};
  DeterministicRandom rng(seed);
  ZScores z;
  for (int d = 0; d < missions; ++d) {
    NetworkNoise noise;
    noise.ppk_error = draw_correlated_ppk_errors(n.epoch_time_s, m, &rng);
    for (const CrbView& v : n.views)
      noise.pixel_noise.push_back(v.pixel_sigma_px * Vector2d(rng.normal(), rng.normal()));
    const std::vector<BundleObservation> obs = observations(n, m, noise);
    const BundleResult r = bundle_adjust(start, obs, opt);
    EXPECT_FALSE(r.rank_deficient);
    EXPECT_TRUE(r.details.ppk_error_model.has_value());
    if (r.rank_deficient) continue;
    const BundleCovariance white = bundle_covariance_under(PpkErrorModel{}, obs, opt, r.calibration);
    const VectorXd e = free_values(n, 0, r.calibration.camera) - free_values(n, 0, n.cameras[0].truth);
    for (Eigen::Index q = 0; q < 4; ++q) {
      const CameraParameter p = scored[q];
      const double err = e[static_cast<Eigen::Index>(std::find(free.begin(), free.end(), p) - free.begin())];
      const int j = r.calibration.parameter_index(p);
      const double zs = err / std::sqrt(r.calibration.covariance(j, j));
      const double zw = err / std::sqrt(white.covariance_unscaled(j, j));
      z.sandwich[q] += zs * zs / missions, z.white[q] += zw * zw / missions;
      z.worst = std::max(z.worst, std::abs(zs));
    }
  }
  z.sandwich = z.sandwich.cwiseSqrt(), z.white = z.white.cwiseSqrt();
  return z;
}

TEST(BundleCorrelatedPpk, SigmaHoldsUnderCorrelatedErrors) {
  // Five ascents at 5 Hz (~143 s), white 0.3 / 0.5 cm + GM 0.8 / 1.4 cm, one camera, the bundle as
  // the calibrate stage runs it (robust solve, outliers, plain solve); 100 missions at τ = 30 s (the
  // acceptance setting), and at 10 and 100 s.
  const auto t0 = std::chrono::steady_clock::now();
  const CrbNetwork n = one_camera(ascent_network());
  constexpr int kMissions = 100;
  std::uint64_t seed = 2026;
  for (double tau : {30.0, 10.0, 100.0}) {
    const ZScores z = z_scores(n, measured_ppk_model(tau), kMissions, seed++);
    std::printf("τ %.0f s, %d one-camera missions, %zu fixes; z rms of f, CE, CN, CU:\n", tau, kMissions,
                n.epochs.size());
    std::printf("  sandwich %.2f %.2f %.2f %.2f (worst |z| %.1f)\n", z.sandwich[0], z.sandwich[1],
                z.sandwich[2], z.sandwich[3], z.worst);
    std::printf("  white    %.2f %.2f %.2f %.2f\n", z.white[0], z.white[1], z.white[2], z.white[3]);
    for (Eigen::Index q = 0; q < 4; ++q) {
      EXPECT_GE(z.sandwich[q], 0.8) << tau << " " << q;
      EXPECT_LE(z.sandwich[q], 1.25) << tau << " " << q;
    }
    // The white bundle's σ do not hold on the same missions: this test can fail.
    EXPECT_GT(z.white.maxCoeff(), 2.0) << tau;
  }
  std::printf("Monte Carlo took %.1f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

}  // namespace
}  // namespace rangecal::test
