// OpenCV → rangecal camera conversion ("conversions to and from OpenCV's model, with the
// fit error reported"). Truth: cv::projectPoints of the OpenCV camera (an independent
// implementation of OpenCV's model) against rangecal's projection of the imported camera.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <opencv2/calib3d.hpp>
#include <random>

#include "config/error.hpp"
#include "vision/camera/opencv_camera_export.hpp"
#include "vision/camera/opencv_camera_import.hpp"

namespace rangecal {
namespace {

// Max |cv::projectPoints − rangecal project| over world points spread across the image at depth z.
double max_projection_difference(const OpenCvCamera& oc, const Camera& cam, double z) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> U(0.02, 0.98);
  std::vector<cv::Point3d> world;
  std::vector<Eigen::Vector3d> wv;
  const Eigen::Matrix3d Rt = cam.pose.R.transpose();
  for (int i = 0; i < 400; ++i) {
    // A point on the ray of a random pixel through OpenCV's own inverse, at depth z.
    std::vector<cv::Point2d> px{{U(rng) * (oc.image_width - 1), U(rng) * (oc.image_height - 1)}}, n;
    cv::Mat K(3, 3, CV_64F);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) K.at<double>(r, c) = oc.camera_matrix(r, c);
    cv::undistortPoints(px, n, K, cv::Mat(oc.distortion_coefficients, true).reshape(1, 1), cv::noArray(),
                        cv::noArray(),
                        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 200, 1e-14));
    const Eigen::Vector3d Xc(n[0].x * z, n[0].y * z, z);
    const Eigen::Vector3d Xw = Rt * (Xc - cam.pose.T);
    world.emplace_back(Xw.x(), Xw.y(), Xw.z());
    wv.push_back(Xw);
  }
  cv::Mat K(3, 3, CV_64F), rvec(3, 1, CV_64F), tvec(3, 1, CV_64F);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) K.at<double>(r, c) = oc.camera_matrix(r, c);
    rvec.at<double>(r) = oc.rvec[r];
    tvec.at<double>(r) = oc.tvec[r];
  }
  std::vector<cv::Point2d> proj;
  cv::projectPoints(world, rvec, tvec, K, cv::Mat(oc.distortion_coefficients, true).reshape(1, 1), proj);
  double mx = 0;
  for (std::size_t i = 0; i < wv.size(); ++i) {
    Eigen::Vector2d uv;
    EXPECT_TRUE(project(cam, wv[i], &uv));
    mx = std::max(mx, std::hypot(uv.x() - proj[i].x, uv.y() - proj[i].y));
  }
  return mx;
}

OpenCvCamera lab_camera() {
  OpenCvCamera oc;
  oc.image_width = 1280;
  oc.image_height = 800;
  oc.camera_matrix << 1400.0, 0, 645.3, 0, 1398.2, 395.8, 0, 0, 1;
  oc.distortion_coefficients = {-0.12, 0.08, 5e-4, -3e-4, -0.01};
  oc.rvec = Eigen::Vector3d(0.3, -1.2, 0.4);
  oc.tvec = Eigen::Vector3d(1.5, -0.7, 60.0);
  return oc;
}

TEST(OpenCvCameraImport, IntrinsicsMapExactly) {
  const OpenCvCamera oc = lab_camera();
  const ImportedCamera r = camera_from_opencv(oc, 0.02, 0.02);
  EXPECT_DOUBLE_EQ(r.camera.intr.f_mm, 1398.2 * 0.02);
  EXPECT_NEAR(r.camera.intr.sx, 1400.0 / 1398.2, 1e-15);
  EXPECT_DOUBLE_EQ(r.camera.intr.u0_px, 645.3);
  EXPECT_DOUBLE_EQ(r.camera.intr.v0_px, 395.8);
  EXPECT_EQ(r.camera.pose.T, oc.tvec);
  EXPECT_NEAR((r.camera.pose.R * r.camera.pose.R.transpose() - Eigen::Matrix3d::Identity()).norm(), 0, 1e-14);
  // Barrel distortion in OpenCV's direction is pincushion-signed in rangecal's inverse direction.
  EXPECT_GT(r.camera.intr.dist.k1, 0);
}

TEST(OpenCvCameraImport, WideLensReproducesProjectPointsAndReportsItsFitError) {
  const OpenCvCamera oc = lab_camera();
  const ImportedCamera r = camera_from_opencv(oc, 0.02, 0.02);
  EXPECT_EQ(r.fit_points, 64 * 40);
  EXPECT_LT(r.fit_max_px, 0.1);
  EXPECT_LE(r.fit_rms_px, r.fit_max_px);
  const double measured = max_projection_difference(oc, r.camera, 40.0);
  EXPECT_LT(measured, 0.1);
  std::printf("wide lens: fit max %.4f px, rms %.4f px; cv::projectPoints vs rangecal max %.4f px\n",
              r.fit_max_px, r.fit_rms_px, measured);
  // The reported fit error is an honest bound on what a user sees (a little slack for sampling).
  EXPECT_LT(measured, 1.5 * r.fit_max_px + 1e-6);
}

TEST(OpenCvCameraImport, RoundTripOfANarrowRangeCameraThroughOpenCv) {
  Camera truth;
  truth.intr = {1280, 800, 0.02, 0.02, 136.12, 0.9966, 640.27, 399.67, {}};
  truth.intr.dist.k1 = -3.443e-4;
  truth.pose.R = Eigen::AngleAxisd(0.8, Eigen::Vector3d(0.2, 1, -0.1).normalized()).toRotationMatrix();
  truth.pose.T = Eigen::Vector3d(-4.2, -3.0, 63.8);
  const OpenCvCamera oc = fit_opencv_camera(truth);
  const ImportedCamera back = camera_from_opencv(oc, 0.02, 0.02);
  EXPECT_LT(back.fit_max_px, 0.01);
  EXPECT_NEAR(back.camera.intr.f_mm / truth.intr.f_mm, 1.0, 1e-4);
  EXPECT_NEAR(back.camera.intr.dist.k1 / truth.intr.dist.k1, 1.0, 0.01);
  // Projections of the round-tripped camera agree with the original within 0.02 px.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d Xc(U(rng) * 6.0, U(rng) * 3.8, 64.0 + 5 * U(rng));
    const Eigen::Vector3d Xw = truth.pose.R.transpose() * (Xc - truth.pose.T);
    Eigen::Vector2d a, b;
    ASSERT_TRUE(project(truth, Xw, &a));
    ASSERT_TRUE(project(back.camera, Xw, &b));
    EXPECT_LT((a - b).norm(), 0.02);
  }
}

TEST(OpenCvCameraImport, BadInputIsACalibrationError) {
  OpenCvCamera oc = lab_camera();
  EXPECT_THROW(camera_from_opencv(oc, 0.0, 0.02), Error);
  oc.camera_matrix(0, 0) = -1;
  EXPECT_THROW(camera_from_opencv(oc, 0.02, 0.02), Error);
  oc = lab_camera();
  oc.distortion_coefficients = {0.1, 0.2, 0.3};
  try {
    camera_from_opencv(oc, 0.02, 0.02);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.exit_code(), 4);
    EXPECT_NE(std::string(e.what()).find("distortion_coefficients"), std::string::npos);
  }
}

}  // namespace
}  // namespace rangecal
