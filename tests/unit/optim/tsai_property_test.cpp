// Tsai (vision/calibration/tsai.hpp) and tsai_sassa (optim/methods/tsai_sassa.hpp) over random range
// placements: fields of view 3–40°, the world origin anywhere (in view, on the v = v0 line, far
// outside the view, behind the camera, at the camera), centroid noise 0.1–1 px. Each is compared with
// the per-camera bundle (optim/bundle/bundle_adjustment.hpp) on the same data, all three against the
// simulated truth (docs/calibration_methods.md "Tsai two-step").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "config/deterministic_random.hpp"
#include "config/error.hpp"
#include "optim/bundle/bundle_adjustment.hpp"
#include "optim/methods/tsai_sassa.hpp"
#include "support/synthetic_camera.hpp"
#include "vision/calibration/tsai.hpp"

namespace rangecal {
namespace {

enum class Origin { in_view, on_v0_line, far_outside, behind, at_camera };
const char* const kOriginNames[] = {"in view", "on v=v0 line", "far outside", "behind", "at camera"};

struct Placement {
  Camera truth;
  std::vector<Eigen::Vector3d> world;  ///< true world points (world frame of the user)
  std::vector<PointCorrespondence> pts;
  double pixel_sd = 0;
  double fov_deg = 0;
  double nominal_f_mm = 0;
  Origin origin = Origin::in_view;
  int n_ascents = 0;
};

Eigen::Vector3d random_unit(DeterministicRandom& rng) {
  const Eigen::Vector3d d(rng.normal(), rng.normal(), rng.normal());
  return d.normalized();
}

// Camera coordinates → site (ENU about the site's own origin).
Eigen::Vector3d camera_to_site(const CameraPose& site_pose, const Eigen::Vector3d& xc) {
  return site_pose.R.transpose() * (xc - site_pose.T);
}

// A range placement: the camera somewhere on site looking level-ish, 3–6 vertical lamp ascents at
// depths D..(1.4–2)·D spread across the view, radial distortion up to ±3 % at the image corner.
Placement random_placement(std::uint64_t seed) {
  DeterministicRandom rng(seed);
  Placement p;
  Camera cam;
  cam.intr.width_px = 1024;
  cam.intr.height_px = rng.uniform() < 0.5 ? 1024 : 768;
  cam.intr.dx_mm = cam.intr.dy_mm = rng.uniform(0.005, 0.020);
  cam.intr.sx = 1.0;
  cam.intr.u0_px = 0.5 * (cam.intr.width_px - 1);
  cam.intr.v0_px = 0.5 * (cam.intr.height_px - 1);
  p.fov_deg = 3.0 * std::pow(40.0 / 3.0, rng.uniform());  // log-uniform 3–40°
  cam.intr.f_mm = 0.5 * cam.intr.width_px * cam.intr.dx_mm / std::tan(0.5 * p.fov_deg * M_PI / 180);
  const double r_corner2 = 0.25 * (std::pow(cam.intr.width_px * cam.intr.dx_mm, 2) +
                                   std::pow(cam.intr.height_px * cam.intr.dy_mm, 2));
  cam.intr.dist.k1 = rng.uniform(-0.03, 0.03) / r_corner2;
  p.nominal_f_mm = cam.intr.f_mm * (1 + rng.uniform(-0.03, 0.03));

  const Eigen::Vector3d center(rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(1, 3));
  const double az = rng.uniform(0, 2 * M_PI), el = rng.uniform(-5, 20) * M_PI / 180;
  const Eigen::Vector3d axis(std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el));
  CameraPose site = test::look_at_pose(center, center + axis);
  const double roll = rng.uniform(-10, 10) * M_PI / 180;
  site.R = Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix() * site.R;
  site.T = -site.R * center;
  cam.pose = site;

  // Ascents: vertical lines through a pixel column at a depth, sampled where they are in view.
  const double d_near = rng.uniform(20, 200), d_far = d_near * rng.uniform(1.4, 2.0);
  const int n_ascents = 3 + static_cast<int>(rng.below(4));
  p.n_ascents = n_ascents;
  std::vector<Eigen::Vector3d> world;
  for (int a = 0; a < n_ascents; ++a) {
    const double depth = a == 0 ? d_near : a == 1 ? d_far : rng.uniform(d_near, d_far);
    const double u = rng.uniform(0.05, 0.95) * (cam.intr.width_px - 1);
    const Eigen::Vector2d s = pixel_to_undistorted_sensor(cam.intr, {u, cam.intr.v0_px});
    const Eigen::Vector3d base =
        camera_to_site(site, {s.x() / cam.intr.f_mm * depth, s.y() / cam.intr.f_mm * depth, depth});
    const double half = depth * std::tan(0.5 * p.fov_deg * M_PI / 180) * 2.0;
    const int wanted = 12 + static_cast<int>(rng.below(19));
    std::vector<Eigen::Vector3d> line;
    for (int k = 0; k <= 400; ++k) {
      const Eigen::Vector3d X = base + Eigen::Vector3d(0, 0, -half + 2 * half * k / 400.0);
      Eigen::Vector2d uv;
      if (project(cam, X, &uv) && uv.x() > 10 && uv.y() > 10 && uv.x() < cam.intr.width_px - 11 &&
          uv.y() < cam.intr.height_px - 11)
        line.push_back(X);
    }
    for (int k = 0; k < wanted && line.size() > 1; ++k)
      world.push_back(line[std::size_t(k) * (line.size() - 1) / std::size_t(wanted - 1)]);
  }

  // The world origin of the user, placed relative to the camera.
  p.origin = static_cast<Origin>(rng.below(5));
  Eigen::Vector3d origin_site;
  const double depth = rng.uniform(d_near, d_far);
  switch (p.origin) {
    case Origin::in_view:
    case Origin::on_v0_line: {
      const double u = rng.uniform(0.1, 0.9) * cam.intr.width_px;
      const double v =
          p.origin == Origin::on_v0_line ? cam.intr.v0_px : rng.uniform(0.1, 0.9) * cam.intr.height_px;
      const Eigen::Vector2d s = pixel_to_undistorted_sensor(cam.intr, {u, v});
      origin_site =
          camera_to_site(site, {s.x() / cam.intr.f_mm * depth, s.y() / cam.intr.f_mm * depth, depth});
      break;
    }
    case Origin::far_outside: {
      Eigen::Vector3d dir;
      do dir = random_unit(rng);
      while (std::acos(dir.dot(axis)) < p.fov_deg * M_PI / 180);
      origin_site = center + dir * 10 * std::pow(500.0, rng.uniform());  // 10 m – 5 km
      break;
    }
    case Origin::behind:
      origin_site = center - axis * rng.uniform(1, 100) + random_unit(rng) * rng.uniform(0, 5);
      break;
    case Origin::at_camera:
      origin_site = center;
      if (rng.uniform() < 0.5) origin_site += 1e-3 * random_unit(rng);
      break;
  }
  for (auto& X : world) X -= origin_site;
  cam.pose.T = -cam.pose.R * (center - origin_site);
  p.truth = cam;
  p.world = world;
  p.pixel_sd = rng.uniform(0.1, 1.0);
  p.pts = test::observe(cam, world, p.pixel_sd, 0.0, seed * 7 + 1);
  return p;
}

// RMS image distance (px) between where `est` and the truth put the true world points: the error of
// the estimate against the simulated truth, in the units a range reads it in.
double image_error_px(const Camera& est, const Placement& p) {
  double ss = 0;
  for (const auto& X : p.world) {
    Eigen::Vector2d a, b;
    if (!project(est, X, &a) || !project(p.truth, X, &b)) return std::numeric_limits<double>::infinity();
    ss += (a - b).squaredNorm();
  }
  return std::sqrt(ss / static_cast<double>(p.world.size()));
}

double bundle_error_px(const Placement& p) {
  std::vector<BundleObservation> obs;
  for (const auto& q : p.pts) {
    BundleObservation o;
    o.world = q.world;
    o.pixel = q.pixel;
    obs.push_back(o);
  }
  BundleOptions o;  // the plain least-squares solve: no outliers here
  o.pixel_sigma_px = p.pixel_sd;
  o.loss = RobustLoss::none;
  o.resolve_without_outliers = false;
  return image_error_px(bundle_adjust(p.truth, obs, o).calibration.camera, p);
}

struct Errors {
  double bundle = 0, tsai = 0, tsai_sassa = 0;  ///< image error against the truth (px)
  TsaiStartSource sassa_start = TsaiStartSource::linear;
  double sassa_f0 = 0;
};

// The three methods on one placement; a method that throws is a test failure naming the placement.
Errors run_methods(const Placement& p, const std::string& name) {
  Errors e;
  e.bundle = bundle_error_px(p);
  try {
    TsaiOptions o;
    o.nominal_f_mm = p.nominal_f_mm;
    e.tsai = image_error_px(tsai_calibrate(p.pts, test::tsai_sensor_of(p.truth), o).camera, p);
  } catch (const Error& err) {
    ADD_FAILURE() << name << ": tsai refused a well-posed problem: " << err.what();
  }
  try {
    TsaiSassaOptions o;
    o.nominal_f_mm = p.nominal_f_mm;
    const TsaiSassaResult r = tsai_sassa_calibrate(p.pts, test::tsai_sensor_of(p.truth), o);
    e.tsai_sassa = image_error_px(r.camera, p);
    e.sassa_start = r.start.source;
    e.sassa_f0 = r.theta0[0];
  } catch (const Error& err) {
    ADD_FAILURE() << name << ": tsai_sassa refused a well-posed problem: " << err.what();
  }
  return e;
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))];
}

// Tsai's error against the bundle's, both against the truth: measured over the 1,000 placements
// below (4–6 ascents, 770 of them) median 1.6, 99th percentile 8.9, largest 15.8 (the same for
// tsai_sassa, whose polish lands on Tsai's step-2 optimum). The stated bounds keep a margin of
// about 1.6× on the largest and on the median.
constexpr double kMaxRatio = 25.0;
constexpr double kMaxMedianRatio = 2.5;

// A narrow-field range camera (docs/calibration_methods.md "Tsai two-step"): 100 mm lens, 20 µm
// pixels, 1024² (a 12° field) at (42, 14, 1.8) m looking at (1, 80, 6), so the world origin lies 77°
// off the optical axis (T ≈ (−43, 1.9, 10) m); five vertical ascents 44–80 m away, spread across
// `spread_px` about the image's centre column. Before the conditioned frames, Tsai refused 1–2 of
// 90 draws (0.2, 0.3, 0.5 px) across 300 px and 81–87 across 100 px ("point 0 lies behind the camera
// in the linear solution", and tsai_sassa with it), and fitted its points to 4.4–5.2 px rms at worst
// across 700 px (1.0 px after).
Placement narrow_field_placement(double pixel_sd, std::uint64_t seed, double spread_px) {
  Placement p;
  Camera cam = test::range_camera_at("narrow", {42, 14, 1.8}, {1, 80, 6}, -3e-5, {511.5, 511.5});
  cam.intr.width_px = cam.intr.height_px = 1024;
  cam.intr.f_mm = 100;
  const double depths[5] = {44, 53, 62, 71, 80},
               cols[5] = {511.5 - spread_px / 2, 511.5 + spread_px / 4, 511.5 - spread_px / 4,
                          511.5 + spread_px / 2, 511.5};
  for (int a = 0; a < 5; ++a) {
    const Eigen::Vector2d s = pixel_to_undistorted_sensor(cam.intr, {cols[a], 511.5});
    const Eigen::Vector3d base =
        camera_to_site(cam.pose, {s.x() / 100 * depths[a], s.y() / 100 * depths[a], depths[a]});
    for (int k = 0; k < 30; ++k) {
      const Eigen::Vector3d X = base + Eigen::Vector3d(0, 0, -8 + 16 * k / 29.0);
      Eigen::Vector2d uv;
      if (project(cam, X, &uv) && uv.y() > 5 && uv.y() < 1018) p.world.push_back(X);
    }
  }
  p.truth = cam;
  p.fov_deg = 2 * std::atan(0.5 * 1024 * 0.02 / 100) * 180 / M_PI;
  p.nominal_f_mm = 100;
  p.pixel_sd = pixel_sd;
  p.n_ascents = 5;
  p.pts = test::observe(cam, p.world, pixel_sd, 0.0, seed);
  return p;
}

// Largest error / bundle's per spread of the five ascents across the image (px), measured over the
// 90 draws: 3.7 (700 px), 10.6 (300 px), 76 (100 px). Within ±50 px of the centre column every point
// has Xd' ≈ 0, so the radial alignment constraint (eq. 11) barely sees r4..r6 and R stays as poor as
// its linear estimate (Tsai's step 2 refines f, Tz, k1 only): both methods calibrate, at a median
// 26× the bundle's error — the per-camera bundle is the method for such a track.
struct Spread {
  double px;
  double max_ratio;
};
const Spread kSpreads[] = {{700, kMaxRatio}, {300, kMaxRatio}, {100, 150}};

TEST(TsaiProperty, NarrowFieldWithTheOriginFarOffAxisCalibrates) {
  for (const Spread& spread : kSpreads) {
    std::vector<double> ratios;
    for (double sd : {0.2, 0.3, 0.5}) {
      for (std::uint64_t seed = 1; seed <= 30; ++seed) {
        const Placement p = narrow_field_placement(sd, seed, spread.px);
        ASSERT_GE(p.pts.size(), 100u);
        const Errors e = run_methods(p, "σ " + std::to_string(sd) + " px, draw " + std::to_string(seed));
        ratios.push_back(e.tsai / e.bundle);
        ratios.push_back(e.tsai_sassa / e.bundle);
      }
    }
    std::printf(
        "12° field, origin 77° off axis, ascents across %.0f px: error / bundle's median %.2f, largest "
        "%.2f\n",
        spread.px, quantile(ratios, 0.5), quantile(ratios, 1.0));
    EXPECT_LT(quantile(ratios, 1.0), spread.max_ratio) << spread.px;
  }
}

// The f–distance ridge: a 3° field (1024², 20 µm, f ≈ 391 mm) and five ascents 300–301.5 m away (a
// depth spread of 0.5 %), 1 px noise. Tsai's linear f, Tz (eq. 15) slide far along the ridge (measured:
// f 71–95 mm for the true 391 mm, relative σ of f 0.09–0.13); tsai_sassa's search then starts from the lens's
// nominal focal length, Tsai's step 2 too when it is given, and from the depth profile of eq. 13 when not.
Placement ridge_placement(std::uint64_t seed) {
  Placement p;
  Camera cam = test::range_camera_at("ridge", {0, 0, 1.5}, {30, 300, 4}, 0.0, {511.5, 511.5});
  cam.intr.width_px = cam.intr.height_px = 1024;
  cam.intr.f_mm = 0.5 * 1024 * 0.02 / std::tan(1.5 * M_PI / 180);
  const double depths[5] = {300, 301.1, 300.35, 301.5, 300.75}, cols[5] = {100, 300, 500, 700, 900};
  for (int a = 0; a < 5; ++a) {
    const Eigen::Vector2d s = pixel_to_undistorted_sensor(cam.intr, {cols[a], 511.5});
    const double z = depths[a];
    const Eigen::Vector3d base =
        camera_to_site(cam.pose, {s.x() / cam.intr.f_mm * z, s.y() / cam.intr.f_mm * z, z});
    for (int k = 0; k < 30; ++k) {
      const Eigen::Vector3d X = base + Eigen::Vector3d(0, 0, -7.5 + 15 * k / 29.0);
      Eigen::Vector2d uv;
      if (project(cam, X, &uv) && uv.y() > 5 && uv.y() < 1018) p.world.push_back(X);
    }
  }
  p.truth = cam;
  p.fov_deg = 3;
  p.nominal_f_mm = std::round(cam.intr.f_mm);
  p.pixel_sd = 1.0;
  p.n_ascents = 5;
  p.pts = test::observe(cam, p.world, p.pixel_sd, 0.0, seed);
  return p;
}

TEST(TsaiProperty, OnTheFocalLengthRidgeTheSearchStartsFromTheNominalFocalLength) {
  int ill = 0, behind = 0;
  std::vector<double> ratios, linear_f;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const Placement p = ridge_placement(seed);
    ASSERT_GE(p.pts.size(), 100u);
    TsaiStep1 s1 = tsai_step1(p.pts, test::tsai_sensor_of(p.truth));
    TsaiStep1 s1_linear = s1;
    try {
      tsai_linear_f_tz(p.pts, test::tsai_sensor_of(p.truth), &s1_linear);  // Tsai's eq. 15 as published
    } catch (const Error&) {
      ++behind;
    }
    const TsaiStart with_lens = tsai_f_tz_start(p.pts, test::tsai_sensor_of(p.truth), &s1, p.nominal_f_mm);
    linear_f.push_back(with_lens.f_linear_mm);
    if (with_lens.f_linear_rel_sigma <= 0.1) continue;
    ++ill;
    EXPECT_EQ(with_lens.source, TsaiStartSource::nominal_focal_length);
    EXPECT_EQ(with_lens.f_mm, p.nominal_f_mm);
    TsaiStep1 s1b = tsai_step1(p.pts, test::tsai_sensor_of(p.truth));
    EXPECT_EQ(tsai_f_tz_start(p.pts, test::tsai_sensor_of(p.truth), &s1b, 0).source,
              TsaiStartSource::depth_profile);

    const Errors e = run_methods(p, "ridge draw " + std::to_string(seed));
    EXPECT_EQ(e.sassa_start, TsaiStartSource::nominal_focal_length);
    EXPECT_EQ(e.sassa_f0, p.nominal_f_mm);
    ratios.push_back(e.tsai / e.bundle);
    ratios.push_back(e.tsai_sassa / e.bundle);
    TsaiResult no_lens = tsai_calibrate(p.pts, test::tsai_sensor_of(p.truth));
    EXPECT_EQ(no_lens.start.source, TsaiStartSource::depth_profile);
    ratios.push_back(image_error_px(no_lens.camera, p) / e.bundle);
  }
  std::printf(
      "3° field, 300–301.5 m: eq. 15 ill-conditioned in %d of 20 draws (points behind the camera in %d; "
      "linear f median %.1f mm for %.1f mm); error / bundle's there median %.2f, largest %.2f\n",
      ill, behind, linear_f.empty() ? 0.0 : quantile(linear_f, 0.5), ridge_placement(1).truth.intr.f_mm,
      ratios.empty() ? 0.0 : quantile(ratios, 0.5), ratios.empty() ? 0.0 : quantile(ratios, 1.0));
  EXPECT_GE(ill, 10);
  ASSERT_FALSE(ratios.empty());
  EXPECT_LT(quantile(ratios, 1.0), kMaxRatio);
}

// ≥ 1,000 random placements, fixed seeds. Tsai's radial alignment constraint from three vertical
// ascents is barely over-determined in a narrow field (each line fixes about two of its six
// unknowns), so with 3 ascents both methods must succeed but their error is only reported;
// the factor is asserted from 4 ascents on. Four shards of 250 placements, so that ctest spreads the
// ≈ 17 s of one core (tsai_sassa's search is 15 s of it) over both of CI's cores.
constexpr int kShards = 4, kPerShard = 250;

class TsaiRandomPlacements : public ::testing::TestWithParam<int> {};

TEST_P(TsaiRandomPlacements, NeverFailAndStayNearTheBundle) {
  std::vector<double> ratio_tsai, ratio_sassa, ratio_three;
  std::vector<double> worst_by_origin(5, 0.0);
  int starts[3] = {0, 0, 0};
  for (int i = GetParam() * kPerShard; i < (GetParam() + 1) * kPerShard; ++i) {
    const Placement p = random_placement(1000 + static_cast<std::uint64_t>(i));
    const Errors e = run_methods(p, "placement " + std::to_string(i));
    const double rt = e.tsai / e.bundle, rs = e.tsai_sassa / e.bundle;
    ++starts[int(e.sassa_start)];
    if (p.n_ascents == 3) {
      ratio_three.push_back(std::max(rt, rs));
      continue;
    }
    ratio_tsai.push_back(rt);
    ratio_sassa.push_back(rs);
    worst_by_origin[std::size_t(p.origin)] = std::max({worst_by_origin[std::size_t(p.origin)], rt, rs});
    EXPECT_LT(rt, kMaxRatio) << "placement " << i << ": fov " << p.fov_deg << "°, origin "
                             << kOriginNames[int(p.origin)] << ", σ " << p.pixel_sd << " px";
    EXPECT_LT(rs, kMaxRatio) << "placement " << i;
  }
  std::printf(
      "error / bundle's, 4–6 ascents (%zu): tsai median %.2f p99 %.2f max %.2f; tsai_sassa median %.2f "
      "p99 %.2f max %.2f\n",
      ratio_tsai.size(), quantile(ratio_tsai, 0.5), quantile(ratio_tsai, 0.99), quantile(ratio_tsai, 1.0),
      quantile(ratio_sassa, 0.5), quantile(ratio_sassa, 0.99), quantile(ratio_sassa, 1.0));
  for (int o = 0; o < 5; ++o)
    std::printf("  origin %s: largest %.2f\n", kOriginNames[o], worst_by_origin[std::size_t(o)]);
  std::printf("3 ascents (%zu): median %.2f p90 %.2f max %.2f\n", ratio_three.size(),
              quantile(ratio_three, 0.5), quantile(ratio_three, 0.9), quantile(ratio_three, 1.0));
  std::printf("tsai_sassa started from Tsai's linear f, Tz in %d placements, from the nominal f in %d\n",
              starts[0], starts[1]);
  EXPECT_LT(quantile(ratio_tsai, 0.5), kMaxMedianRatio);
  EXPECT_LT(quantile(ratio_sassa, 0.5), kMaxMedianRatio);
}

INSTANTIATE_TEST_SUITE_P(Shards, TsaiRandomPlacements, ::testing::Range(0, kShards));

// Only degenerate data are refused, with the reason, by both methods: points coplanar with the
// camera (three ascents in one vertical plane through its centre: the image is one line and
// f cannot be told from the distance), all points on one ascent, fewer points than unknowns.
void expect_refused(const std::vector<PointCorrespondence>& pts, const TsaiSensor& s,
                    const std::string& reason) {
  for (const char* method : {"tsai", "tsai_sassa"}) {
    try {
      if (std::string(method) == "tsai")
        tsai_calibrate(pts, s);
      else
        tsai_sassa_calibrate(pts, s);
      ADD_FAILURE() << method << " accepted data that should be refused as: " << reason;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::calibration) << method;
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << method << ": " << e.what();
    }
  }
}

TEST(TsaiProperty, OnlyDegenerateDataAreRefused) {
  const Placement p = narrow_field_placement(0.3, 1, 700);
  const TsaiSensor s = test::tsai_sensor_of(p.truth);
  const Eigen::Vector3d C = p.truth.pose.center();
  const Eigen::Vector3d axis = p.truth.pose.R.row(2).transpose();
  const Eigen::Vector3d across = axis.cross(Eigen::Vector3d::UnitZ()).normalized();
  // The vertical plane through the camera centre and a direction 3° off the optical axis.
  const Eigen::Vector3d d = (axis + std::tan(3 * M_PI / 180) * across).normalized();
  std::vector<Eigen::Vector3d> in_plane;
  for (double depth : {44.0, 62.0, 80.0})
    for (int k = 0; k < 20; ++k) in_plane.push_back(C + depth * d + Eigen::Vector3d(0, 0, -3 + 0.3 * k));
  const auto coplanar = test::observe(p.truth, in_plane, 0.3, 0.0, 2);
  ASSERT_EQ(coplanar.size(), in_plane.size());
  expect_refused(coplanar, s, "coplanar");
  // One ascent.
  std::vector<PointCorrespondence> line;
  for (const auto& q : p.pts)
    if ((q.world - p.pts[0].world).head<2>().norm() < 1e-9) line.push_back(q);
  ASSERT_GE(line.size(), 10u);
  expect_refused(line, s, "one line");
  // Six points for seven unknowns.
  std::vector<PointCorrespondence> six;
  for (std::size_t i = 0; i < 6; ++i) six.push_back(p.pts[i * 15]);
  expect_refused(six, s, "too few points");
  // The well-posed data of the same camera are calibrated.
  EXPECT_NO_THROW(tsai_calibrate(p.pts, s));
  EXPECT_NO_THROW(tsai_sassa_calibrate(p.pts, s));
}

}  // namespace
}  // namespace rangecal
