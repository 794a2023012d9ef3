// DLT-11 + Argus undistortion profile (vision/camera/dlt_export.hpp): read back from the files as
// DLTdv/Argus read them and evaluated here independently (the DLT equations of Abdel-Aziz &
// Karara, the profile's pinhole distortion written out below, cv::undistortPoints for the tools'
// direction), they must reproduce rangecal's projection within 0.05 px over the image for points
// at the flight distance (64 m).
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <sstream>

#include "config/error.hpp"
#include "support/synthetic_camera.hpp"
#include "vision/camera/dlt_export.hpp"

namespace rangecal {
namespace {

// The demo's calibrated camera (7 % pincushion at the corners), ~64 m from the lamp.
Camera demo_camera() {
  Camera c;
  c.id = "cam1";
  c.intr = {1280, 800, 0.020, 0.020, 135.41832751959438, 1.0, 639.5, 399.5, {}};
  c.intr.dist.k1 = -3.2386531432679203e-4;
  c.pose = test::look_at_pose({-44.8, -44.8, 1.56}, {0.0, 0.0, 4.0});
  return c;
}

// Seed 002's lens with sx ≠ 1 and an off-centre principal point, plus tangential terms.
Camera narrow_camera() {
  Camera c;
  c.id = "cam2";
  c.intr = {1280, 800, 0.020, 0.020, 135.2, 1.0004, 652.3, 391.7, {}};
  c.intr.dist.k1 = -3.443e-4;
  c.intr.dist.p1 = 1e-6;
  c.intr.dist.p2 = -2e-6;
  c.pose = test::look_at_pose({45.0, -45.0, 1.8}, {0.0, 0.0, 4.0});
  return c;
}

std::vector<std::vector<double>> parse_rows(const std::string& text, char sep) {
  std::vector<std::vector<double>> rows;
  std::istringstream is(text);
  for (std::string line; std::getline(is, line);) {
    std::vector<double> row;
    std::istringstream ls(line);
    for (std::string f; std::getline(ls, f, sep);)
      if (!f.empty()) row.push_back(std::stod(f));
    rows.push_back(row);
  }
  return rows;
}

struct Errors {
  double forward_max = 0, tools_max = 0, dlt_only_max = 0;
};

/// Evaluates camera `col` of the two files at points 64 m along the rays of a pixel grid.
Errors evaluate(const Camera& cam, const std::string& coeff_csv, const std::string& profile_txt,
                std::size_t col) {
  const auto L = parse_rows(coeff_csv, ',');
  const auto prof = parse_rows(profile_txt, ' ').at(col);
  EXPECT_EQ(prof.size(), 12u);
  EXPECT_EQ(prof[0], col + 1.0);
  const double f = prof[1], cx = prof[4], cy = prof[5], k1 = prof[7], k2 = prof[8], t1 = prof[9],
               t2 = prof[10], k3 = prof[11];
  EXPECT_EQ(prof[2], cam.intr.width_px);
  EXPECT_EQ(prof[3], cam.intr.height_px);
  EXPECT_EQ(prof[6], 1.0);
  const int W = cam.intr.width_px, H = cam.intr.height_px;
  Errors e;
  std::vector<cv::Point2d> tools_px, dlt_px;
  for (int j = 0; j <= 40; ++j)
    for (int i = 0; i <= 64; ++i) {
      const Eigen::Vector2d p(-0.5 + W * i / 64.0, -0.5 + H * j / 40.0);
      const Eigen::Vector3d X = cam.pose.center() + 64.0 * pixel_ray_world(cam, p);
      Eigen::Vector2d uv;
      EXPECT_TRUE(project(cam, X, &uv));
      // DLT-11: x = (L1 X + L2 Y + L3 Z + L4)/(L9 X + L10 Y + L11 Z + 1), y likewise with L5–L8.
      const auto l = [&](int k) { return L.at(k - 1).at(col); };
      const double den = l(9) * X.x() + l(10) * X.y() + l(11) * X.z() + 1;
      const double x = (l(1) * X.x() + l(2) * X.y() + l(3) * X.z() + l(4)) / den;
      const double y = (l(5) * X.x() + l(6) * X.y() + l(7) * X.z() + l(8)) / den;
      // The profile's pinhole model (Brown–Conrady as OpenCV): undistorted → distorted.
      const double xn = (x - cx) / f, yn = (y - cy) / f, r2 = xn * xn + yn * yn;
      const double radial = 1 + k1 * r2 + k2 * r2 * r2 + k3 * r2 * r2 * r2;
      const double xd = xn * radial + 2 * t1 * xn * yn + t2 * (r2 + 2 * xn * xn);
      const double yd = yn * radial + t1 * (r2 + 2 * yn * yn) + 2 * t2 * xn * yn;
      // The tools' frame: origin at the image's bottom-left corner, y up.
      const Eigen::Vector2d distorted(f * xd + cx - 0.5, H - 0.5 - (f * yd + cy));
      const Eigen::Vector2d undistorted(x - 0.5, H - 0.5 - y);
      e.forward_max = std::max(e.forward_max, (distorted - uv).norm());
      e.dlt_only_max = std::max(e.dlt_only_max, (undistorted - uv).norm());
      tools_px.emplace_back(uv.x() + 0.5, H - 0.5 - uv.y());
      dlt_px.emplace_back(x, y);
    }
  // The tools' direction: Argus undistorts a clicked point with cv2.undistortPoints(pts, K,
  // [k1 k2 t1 t2 k3], P = K) at its default settings, then applies the DLT.
  const cv::Matx33d K(f, 0, cx, 0, f, cy, 0, 0, 1);
  std::vector<cv::Point2d> und;
  cv::undistortPoints(tools_px, und, K, std::vector<double>{k1, k2, t1, t2, k3}, cv::noArray(), K);
  for (std::size_t i = 0; i < und.size(); ++i)
    e.tools_max = std::max(e.tools_max, std::hypot(und[i].x - dlt_px[i].x, und[i].y - dlt_px[i].y));
  return e;
}

TEST(DltExport, DltPlusProfileReproduceProjectWithinTolerance) {
  const std::vector<DltCamera> cams = {dlt_camera(demo_camera()), dlt_camera(narrow_camera())};
  const std::string coeff = dlt_coefficients_csv(cams), prof = argus_profile_txt(cams);
  // DLTdv/Argus layout: 11 rows, one column per camera; one profile line per camera.
  const auto rows = parse_rows(coeff, ',');
  ASSERT_EQ(rows.size(), 11u);
  for (const auto& r : rows) ASSERT_EQ(r.size(), 2u);
  ASSERT_EQ(parse_rows(prof, ' ').size(), 2u);
  const Camera sources[] = {demo_camera(), narrow_camera()};
  for (std::size_t c = 0; c < 2; ++c) {
    const Errors e = evaluate(sources[c], coeff, prof, c);
    EXPECT_LT(e.forward_max, 0.05) << cams[c].id;
    EXPECT_LT(e.tools_max, 0.05) << cams[c].id;
    // The report agrees with this independent evaluation (both include the image corners).
    EXPECT_LE(e.forward_max, cams[c].profile_max_px * 1.05 + 1e-4) << cams[c].id;
    EXPECT_LE(e.tools_max, cams[c].undistort_max_px * 1.05 + 1e-4) << cams[c].id;
    EXPECT_NEAR(e.dlt_only_max, cams[c].dlt_only_max_px, 0.01 * cams[c].dlt_only_max_px) << cams[c].id;
    // The distortion the DLT alone ignores: tens of pixels at the corners of a 7 % lens.
    EXPECT_GT(cams[c].dlt_only_max_px, 30.0) << cams[c].id;
    EXPECT_GT(cams[c].dlt_only_max_px, cams[c].dlt_only_rms_px);
  }
}

TEST(DltExport, PixelFrameIsBottomLeftYUp) {
  const Camera cam = demo_camera();
  const DltCamera d = dlt_camera(cam);
  // The principal point, in the tools' frame: x = u0 + 0.5, y = H − 0.5 − v0.
  EXPECT_NEAR(d.cx_px, cam.intr.u0_px + 0.5, 0.05);
  EXPECT_NEAR(d.cy_px, cam.intr.height_px - 0.5 - cam.intr.v0_px, 0.05);
  EXPECT_EQ(to_dlt_pixel({0, 0}, 800), Eigen::Vector2d(0.5, 799.5));
  EXPECT_EQ(from_dlt_pixel(to_dlt_pixel({12.25, 700.5}, 800), 800), Eigen::Vector2d(12.25, 700.5));
  // A lossless lens: the DLT alone is exact, the profile is zero.
  Camera ideal = cam;
  ideal.intr.dist = {};
  const DltCamera i = dlt_camera(ideal);
  EXPECT_LT(i.dlt_only_max_px, 1e-6);
  for (double k : i.k) EXPECT_LT(std::abs(k), 1e-6);
  // The world origin in the camera's principal plane has no DLT-11 form.
  Camera bad = cam;
  bad.pose.T.z() = 0;
  EXPECT_THROW(dlt_camera(bad), Error);
}

}  // namespace
}  // namespace rangecal
