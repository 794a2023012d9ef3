// The trajectory of a moving target from unsynchronised cameras (vision/triangulation/target_trajectory.hpp):
// its σ against simulated truth over many missions with timing errors — a clock offset per camera and
// per-frame jitter — that move each label along its image track; ignoring the timing term must
// under-cover; the output grid, gaps, velocity and the extrapolation flag.
#include "vision/triangulation/target_trajectory.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "config/error.hpp"
#include "vision/triangulation/trajectory_smoother.hpp"

#include "support/synthetic_camera.hpp"

namespace rangecal {
namespace {

constexpr std::int64_t kT0 = 1'800'000'000'000'000'000;  // 2027-01-15T08:00:00Z, a whole second

// A drone-like target: a 6-m circle at 8 m/s, 20 m up, ~64 m from the cameras.
Eigen::Vector3d target_at(double t) {
  const double w = 8.0 / 6.0;
  return {6 * std::cos(w * t), 6 * std::sin(w * t), 20 + 0.5 * t};
}

struct Simulated {
  std::vector<TrajectoryCamera> cameras;
};

// Three cameras at 50, 60 and 47 frames/s, starting at different instants; each label's time is off
// by its camera's clock error (σ clock_sd) plus jitter (σ jitter_sd) and its pixel by noise (σ 0.5 px);
// the labels state a timing σ of √(clock² + jitter²) when `state_timing`.
Simulated simulate(std::mt19937_64* rng, double clock_sd, double jitter_sd, bool state_timing,
                   double seconds = 4) {
  std::normal_distribution<double> n01(0, 1);
  const Eigen::Vector3d aim(0, 0, 21);
  const struct {
    const char* id;
    Eigen::Vector3d centre;
    double fps, start_s;
  } rig[] = {{"west", {-46, -44, 1.5}, 50, 0.003},
             {"east", {45, -46, 1.8}, 60, 0.011},
             {"north", {4, 62, 2.5}, 47, 0.017}};
  Simulated s;
  for (const auto& r : rig) {
    TrajectoryCamera c;
    c.id = r.id;
    c.camera = test::range_camera_at(r.id, r.centre, aim);
    c.label_sigma_px = 0.5;
    const double clock_error = clock_sd * n01(*rng);
    for (int j = 0; r.start_s + j / r.fps < seconds + 0.1; ++j) {
      const double stated = r.start_s + j / r.fps;
      const double truth = stated + clock_error + jitter_sd * n01(*rng);
      TimedLabel l;
      l.t = UtcTime{kT0 + std::llround(stated * 1e9)};
      EXPECT_TRUE(project(c.camera, target_at(truth), &l.uv_px));
      l.uv_px += 0.5 * Eigen::Vector2d(n01(*rng), n01(*rng));
      l.timing_sigma_s = state_timing ? std::hypot(clock_sd, jitter_sd) : 0.0;
      c.labels.push_back(l);
    }
    s.cameras.push_back(std::move(c));
  }
  return s;
}

double seconds_of(UtcTime t) {
  return 1e-9 * static_cast<double>(t.ns - kT0);
}

// z² = |error|²/σ_m² pooled over every instant of `missions` missions.
double z_rms(bool state_timing, int missions, double* error_rms_m = nullptr) {
  std::mt19937_64 rng(2026);
  double z2 = 0, e2 = 0;
  std::size_t n = 0;
  for (int m = 0; m < missions; ++m) {
    const Simulated s = simulate(&rng, 0.002, 0.002, state_timing);
    const Trajectory tr = estimate_trajectory(s.cameras, trajectory_instants(s.cameras, 25), nullptr);
    EXPECT_GT(tr.points.size(), 90u);
    for (const TrajectoryPoint& p : tr.points) {
      const double e = (p.fix.point - target_at(seconds_of(p.t))).squaredNorm();
      z2 += e / (p.fix.sigma_m * p.fix.sigma_m);
      e2 += e;
      ++n;
    }
  }
  if (error_rms_m) *error_rms_m = std::sqrt(e2 / static_cast<double>(n));
  return std::sqrt(z2 / static_cast<double>(n));
}

TEST(TargetTrajectory, SigmaHoldsWithTimingErrorsOverTwentyMissions) {
  double rms = 0;
  const double z = z_rms(true, 20, &rms);
  std::printf("timing stated: error rms %.2f cm, z rms %.3f\n", 100 * rms, z);
  EXPECT_GT(z, 0.85);
  EXPECT_LT(z, 1.15);
  // 8 m/s × 2.8 ms ≈ 2.3 cm along the path, against ~0.5 cm from the labels' noise alone.
  EXPECT_GT(rms, 0.01);
}

TEST(TargetTrajectory, IgnoringTheTimingTermUnderCovers) {
  const double z = z_rms(false, 20);
  std::printf("timing not stated: z rms %.2f\n", z);
  EXPECT_GT(z, 1.5);
}

// The smoother (vision/triangulation/trajectory_smoother.hpp) over the same twenty missions: the
// labels' noise averaged down, the timing errors (a clock offset per camera: common to a stretch)
// kept whole. Its error must be lower than the instants' own and its σ must hold; its velocity
// against the circle's within its σ.
TEST(TargetTrajectory, SmoothingLowersTheErrorAndItsSigmaHolds) {
  std::mt19937_64 rng(2026);
  double e2_raw = 0, e2 = 0, z2 = 0, zv2 = 0;
  std::size_t n = 0, nv = 0;
  double q_min = 1e300, q_max = 0;
  for (int m = 0; m < 20; ++m) {
    const Simulated s = simulate(&rng, 0.002, 0.002, true);
    Trajectory tr = estimate_trajectory(s.cameras, trajectory_instants(s.cameras, 25), nullptr);
    for (const TrajectoryPoint& p : tr.points)
      e2_raw += (p.fix.point - target_at(seconds_of(p.t))).squaredNorm();
    const SmootherReport r = smooth_trajectory(&tr);
    EXPECT_EQ(r.smoothed, tr.points.size());
    q_min = std::min(q_min, r.jerk_psd), q_max = std::max(q_max, r.jerk_psd);
    for (const TrajectoryPoint& p : tr.points) {
      const double t = seconds_of(p.t);
      const double e = (p.fix.point - target_at(t)).squaredNorm();
      e2 += e;
      z2 += e / (p.fix.sigma_m * p.fix.sigma_m);
      ++n;
      const double h = 1e-4;
      const Eigen::Vector3d v = (target_at(t + h) - target_at(t - h)) / (2 * h);
      for (int k = 0; k < 3; ++k) {
        const double d = p.velocity[k] - v[k];
        zv2 += d * d / (p.velocity_sd[k] * p.velocity_sd[k]);
        ++nv;
      }
    }
  }
  const double raw = std::sqrt(e2_raw / n), smoothed = std::sqrt(e2 / n), z = std::sqrt(z2 / n),
               zv = std::sqrt(zv2 / nv);
  std::printf("smoothing: error rms %.2f → %.2f cm, z rms %.3f; velocity z rms %.2f; q %.3g–%.3g m²/s⁵\n",
              100 * raw, 100 * smoothed, z, zv, q_min, q_max);
  EXPECT_LT(smoothed, 0.85 * raw);
  // The clock offsets are kept whole though the frames' jitter (half the timing variance here)
  // averages down: σ on the safe side.
  EXPECT_GT(z, 0.75);
  EXPECT_LT(z, 1.1);
  EXPECT_GT(zv, 0.8);
  EXPECT_LT(zv, 1.25);
}

// An instant with a view outside its calibration's coverage — every view, or one — is left as
// triangulated and splits the stretch; the others are smoothed.
TEST(TargetTrajectory, SmoothingLeavesAnInstantWhoseEveryViewIsExtrapolated) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n01(0, 1);
  Trajectory tr;
  for (int k = 0; k < 40; ++k) {
    TrajectoryPoint p;
    p.t = UtcTime{kT0 + std::int64_t{k} * 100'000'000};
    p.cameras = {"a", "b"};
    if (k == 20) p.extrapolated = {"a", "b"};
    if (k == 30) p.extrapolated = {"b"};
    p.fix.point =
        Eigen::Vector3d(0.8 * k, 0.1 * k, 20) + 0.02 * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
    p.fix.cov_pick_m2 = 0.0004 * Eigen::Matrix3d::Identity();
    p.fix.cov_m2 = p.fix.cov_pick_m2;
    p.fix.sigma_m = std::sqrt(p.fix.cov_m2.trace());
    tr.points.push_back(p);
  }
  const Trajectory before = tr;
  const SmootherReport r = smooth_trajectory(&tr);
  EXPECT_EQ(r.stretches, 3u);
  EXPECT_EQ(r.smoothed, 38u);
  for (const int k : {20, 30}) {
    EXPECT_EQ(tr.points[k].fix.point, before.points[k].fix.point) << k;
    EXPECT_TRUE(std::isnan(tr.points[k].acceleration.x())) << k;
  }
  EXPECT_NE(tr.points[25].fix.point, before.points[25].fix.point);
  EXPECT_LT(tr.points[25].fix.sigma_m, before.points[25].fix.sigma_m);  // averaged down
}

// Labels' errors correlated in time (a tracker's): instants 0.1 s apart on a gently turning path,
// each fix off by an AR(1) error of φ 0.8 per step (τ 0.45 s) and 2 cm per axis. The likelihood
// must choose a correlated model (τ > 0), and the smoothed σ must hold (it would not if the errors
// were averaged as independent); with white errors it must choose white.
double smoothed_z_rms(double phi, double* tau_s) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n01(0, 1);
  double z2 = 0, tau = 0;
  std::size_t n = 0;
  for (int m = 0; m < 10; ++m) {
    Trajectory tr;
    std::vector<Eigen::Vector3d> truth;
    Eigen::Vector3d e = 0.02 * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
    for (int k = 0; k < 400; ++k) {
      const double t = 0.1 * k;
      truth.emplace_back(5 * t, 20 * std::sin(0.05 * t), 30 + 0.2 * t);
      e = phi * e + std::sqrt(1 - phi * phi) * 0.02 * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
      TrajectoryPoint p;
      p.t = UtcTime{kT0 + std::int64_t{k} * 100'000'000};
      p.cameras = {"a", "b"};
      p.fix.point = truth.back() + e;
      p.fix.cov_pick_m2 = 0.0004 * Eigen::Matrix3d::Identity();
      p.fix.cov_m2 = p.fix.cov_pick_m2;
      p.fix.sigma_m = std::sqrt(p.fix.cov_m2.trace());
      tr.points.push_back(p);
    }
    tau += smooth_trajectory(&tr).label_tau_s / 10;
    for (std::size_t k = 0; k < tr.points.size(); ++k) {
      z2 += (tr.points[k].fix.point - truth[k]).squaredNorm() / std::pow(tr.points[k].fix.sigma_m, 2);
      ++n;
    }
  }
  *tau_s = tau;
  return std::sqrt(z2 / static_cast<double>(n));
}

TEST(TargetTrajectory, SmoothingFindsTheLabelsErrorsCorrelationAndItsSigmaHolds) {
  double tau_correlated = 0, tau_white = 0;
  const double z_correlated = smoothed_z_rms(0.8, &tau_correlated);
  const double z_white = smoothed_z_rms(0, &tau_white);
  std::printf("labels' errors AR(1) φ 0.8: τ chosen %.2f s (mean), z rms %.2f; white: τ %.2f s, z rms %.2f\n",
              tau_correlated, z_correlated, tau_white, z_white);
  EXPECT_GT(tau_correlated, 0.15);
  EXPECT_LT(tau_white, 0.05);
  for (const double z : {z_correlated, z_white}) {
    EXPECT_GT(z, 0.8);
    EXPECT_LT(z, 1.25);
  }
}

TEST(TargetTrajectory, InstantsOnWholeSecondsWhereTwoCamerasSee) {
  std::mt19937_64 rng(1);
  const Simulated s = simulate(&rng, 0, 0, true, 2);
  const std::vector<UtcTime> t = trajectory_instants(s.cameras, 5);
  ASSERT_FALSE(t.empty());
  // From the second-earliest first label (0.011 s) to the second-latest last label: 0.2, 0.4, …
  EXPECT_EQ(t.front().ns, kT0 + 200'000'000);
  for (std::size_t i = 1; i < t.size(); ++i) EXPECT_EQ(t[i].ns - t[i - 1].ns, 200'000'000);
  EXPECT_NEAR(fastest_label_rate_hz(s.cameras), 60, 1e-4);  // frame times rounded to ns
}

TEST(TargetTrajectory, GapsVelocityAndExtrapolation) {
  std::mt19937_64 rng(7);
  Simulated s = simulate(&rng, 0, 0, true);
  // The north camera loses the target between 1.0 and 2.0 s; the east camera's calibration saw only
  // the left half of its image.
  auto& north = s.cameras[2].labels;
  north.erase(std::remove_if(north.begin(), north.end(),
                             [](const TimedLabel& l) {
                               const double t = 1e-9 * static_cast<double>(l.t.ns - kT0);
                               return t > 1.0 && t < 2.0;
                             }),
              north.end());
  std::vector<Eigen::Vector2d> left;
  for (double u = 0; u < 640; u += 16)
    for (double v = 0; v < 800; v += 16) left.emplace_back(u, v);
  s.cameras[1].coverage = ImageCoverage(left, 64);
  const Trajectory tr = estimate_trajectory(s.cameras, trajectory_instants(s.cameras, 25), nullptr);
  std::size_t two = 0, flagged = 0, right_half = 0;
  for (const TrajectoryPoint& p : tr.points) {
    const double t = seconds_of(p.t);
    if (t > 1.05 && t < 1.95) {
      EXPECT_EQ(p.cameras.size(), 2u) << t;  // west and east only
      ++two;
    }
    Eigen::Vector2d uv;
    ASSERT_TRUE(project(s.cameras[1].camera, target_at(t), &uv));
    const bool outside = uv.x() > 640 + 64 + 1;  // beyond the covered cells and their neighbours
    right_half += outside ? 1 : 0;
    const bool is_flagged =
        std::find(p.extrapolated.begin(), p.extrapolated.end(), "east") != p.extrapolated.end();
    flagged += is_flagged ? 1 : 0;
    if (outside) {
      EXPECT_TRUE(is_flagged) << t;
    }
    if (uv.x() < 640) {
      EXPECT_FALSE(is_flagged) << t;
    }
    // Velocity by central difference of the 25-Hz instants: the circle's 8 m/s (and 0.5 m/s up)
    // within 4σ plus the difference's own bias on the circle, (ω·Δt)²/6 of the speed.
    if (std::isfinite(p.velocity.x())) {
      const double h = 1e-4;
      const Eigen::Vector3d v = (target_at(t + h) - target_at(t - h)) / (2 * h);
      for (int k = 0; k < 3; ++k) {
        EXPECT_LT(std::abs(p.velocity[k] - v[k]), 4 * p.velocity_sd[k] + 0.01) << t << " axis " << k;
      }
    }
  }
  EXPECT_GT(two, 15u);
  EXPECT_GT(right_half, 5u);
  EXPECT_GT(flagged, 0u);
  EXPECT_EQ(tr.single_camera, 0u);
}

TEST(ImageCoverage, DistanceOutsideTheCoveredCellsAndTheirNeighbours) {
  // One observation in cell (2, 3) of a 64-px grid: covered is the box of cells 1..3 × 2..4, i.e.
  // u in [64, 256), v in [128, 320).
  const ImageCoverage c({Eigen::Vector2d(150, 200)}, 64);
  EXPECT_EQ(c.distance_outside_px({100, 300}), 0.0);
  EXPECT_NEAR(c.distance_outside_px({356, 200}), 100, 1e-9);           // right of the box
  EXPECT_NEAR(c.distance_outside_px({30, 200}), 34, 1e-9);             // left of it
  EXPECT_NEAR(c.distance_outside_px({256 + 30, 320 + 40}), 50, 1e-9);  // off its corner: √(30² + 40²)
  EXPECT_EQ(ImageCoverage().distance_outside_px({1e6, 1e6}), 0.0);     // nothing known: no term
  EXPECT_TRUE(std::isinf(c.distance_outside_px({NAN, 0})));
}

// A lens model extrapolated beyond its calibration's coverage: the east camera's labels carry an
// error that is nil where its calibration saw the lamp (the left half of its image) and grows by
// 0.05 px per px beyond the covered cells — what a distortion polynomial fitted on one half does on
// the other. Twenty missions; over the instants where east's label lies outside its coverage.
struct ExtrapolatedFigures {
  double error_rms_m = 0, z_rms = 0;
  std::size_t instants = 0;
};

ExtrapolatedFigures extrapolated_instants(double stated_px_per_px) {
  std::mt19937_64 rng(35);
  std::vector<Eigen::Vector2d> left;
  for (double u = 0; u < 640; u += 16)
    for (double v = 0; v < 800; v += 16) left.emplace_back(u, v);
  TrajectoryOptions options;
  options.extrapolation_sigma_px_per_px = stated_px_per_px;
  double e2 = 0, z2 = 0;
  ExtrapolatedFigures f;
  for (int m = 0; m < 20; ++m) {
    Simulated s = simulate(&rng, 0, 0, true);
    TrajectoryCamera& east = s.cameras[1];
    east.coverage = ImageCoverage(left, 64);
    for (TimedLabel& l : east.labels) {
      const double outside = std::max(0.0, l.uv_px.x() - (640 + 64));  // beyond the covered box
      l.uv_px += 0.05 * outside * Eigen::Vector2d(0.6, 0.8);
    }
    const Trajectory tr =
        estimate_trajectory(s.cameras, trajectory_instants(s.cameras, 25), nullptr, options);
    for (const TrajectoryPoint& p : tr.points) {
      if (std::find(p.extrapolated.begin(), p.extrapolated.end(), "east") == p.extrapolated.end()) continue;
      const double e = (p.fix.point - target_at(seconds_of(p.t))).squaredNorm();
      e2 += e;
      z2 += e / (p.fix.sigma_m * p.fix.sigma_m);
      ++f.instants;
    }
  }
  f.error_rms_m = std::sqrt(e2 / static_cast<double>(f.instants));
  f.z_rms = std::sqrt(z2 / static_cast<double>(f.instants));
  return f;
}

TEST(TargetTrajectory, AnExtrapolatedLensWeighsLessAndItsSigmaHolds) {
  const ExtrapolatedFigures without = extrapolated_instants(0);
  const ExtrapolatedFigures with = extrapolated_instants(0.05);
  std::printf("extrapolated instants %zu: without the term error %.2f cm z %.2f; with it %.2f cm z %.2f\n",
              with.instants, 100 * without.error_rms_m, without.z_rms, 100 * with.error_rms_m, with.z_rms);
  ASSERT_GT(with.instants, 200u);
  // Without the term the east view weighs as much as the others: the instant takes the east lens's
  // error, and only the χ² inflation widens its σ (it cannot tell which view is off). With it the
  // other two cameras carry the instant, and its σ holds.
  EXPECT_LT(with.error_rms_m, 0.25 * without.error_rms_m);
  EXPECT_GT(with.z_rms, 0.7);
  EXPECT_LT(with.z_rms, 1.25);
}

// A label's own σ (the track file's sigma_px) replaces the camera's for that label: the label part
// of an instant's covariance scales as σ² when every label gives its own, and an instant between a
// label with σ and one without takes the σ between them.
TEST(TargetTrajectory, ALabelsOwnSigmaReplacesTheCameras) {
  std::mt19937_64 rng(3);
  Simulated s = simulate(&rng, 0, 0, true, 2);
  const std::vector<UtcTime> t = trajectory_instants(s.cameras, 5);
  const Trajectory base = estimate_trajectory(s.cameras, t, nullptr);
  for (TrajectoryCamera& c : s.cameras)
    for (TimedLabel& l : c.labels) l.sigma_px = 2 * c.label_sigma_px;
  const Trajectory own = estimate_trajectory(s.cameras, t, nullptr);
  ASSERT_EQ(base.points.size(), own.points.size());
  ASSERT_FALSE(base.points.empty());
  for (std::size_t k = 0; k < base.points.size(); ++k)
    EXPECT_NEAR(own.points[k].fix.cov_pick_m2.trace() / base.points[k].fix.cov_pick_m2.trace(), 4, 1e-6);
  // One camera's labels alternate between 4× the camera's σ and none of their own: every instant
  // lies between one of each, at weights w and 1 − w; its σ there is (1 − w)·σ_a + w·σ_b.
  for (TrajectoryCamera& c : s.cameras)
    for (std::size_t i = 0; i < c.labels.size(); ++i)
      c.labels[i].sigma_px = i % 2 == 0 ? 4 * c.label_sigma_px : 0;
  const Trajectory mixed = estimate_trajectory(s.cameras, t, nullptr);
  for (std::size_t k = 0; k < base.points.size(); ++k) {
    const double ratio = mixed.points[k].fix.cov_pick_m2.trace() / base.points[k].fix.cov_pick_m2.trace();
    EXPECT_GT(ratio, 1 - 1e-9);
    EXPECT_LT(ratio, 16 + 1e-9);
  }
  s.cameras[1].labels[3].sigma_px = -1;
  s.cameras[1].labels[3].line = 5;
  try {
    estimate_trajectory(s.cameras, t, nullptr);
    ADD_FAILURE() << "a negative label σ was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.line(), 5);
    EXPECT_EQ(e.field(), "sigma_px");
  }
}

TEST(TargetTrajectory, LabelsOutOfOrderAreAnInputError) {
  std::mt19937_64 rng(3);
  Simulated s = simulate(&rng, 0, 0, true, 1);
  std::swap(s.cameras[0].labels[3], s.cameras[0].labels[4]);
  s.cameras[0].labels[4].line = 6;
  try {
    estimate_trajectory(s.cameras, trajectory_instants(s.cameras, 10), nullptr);
    FAIL() << "accepted labels out of time order";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.line(), 6);
    EXPECT_NE(std::string(e.what()).find("west"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rangecal
