// The export check (pipeline/steps/export_check.hpp): an export that cannot reproduce its camera is
// refused, one that can is kept; the figure it refuses by is what OpenCV's projection of the export
// really misses, measured here against rangecal's own projection over the image.
#include "pipeline/steps/export_check.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "support/synthetic_camera.hpp"

namespace rangecal {
namespace {

// Seed 002's camera (1280×800, 20 µm, 135 mm, k1 ≈ 7 % at the corner: tests/support/synthetic_camera.hpp).
Camera narrow_camera() {
  return test::range_camera(-3.443e-4);
}

/// The largest |OpenCV − rangecal| (px) of the export's projection over points seen across the image.
double worst_projection_error(const Camera& cam, const OpenCvCamera& oc) {
  double worst = 0;
  for (int i = 0; i <= 16; ++i)
    for (int j = 0; j <= 10; ++j) {
      const Eigen::Vector2d uv(cam.intr.width_px * i / 16.0 - 0.5, cam.intr.height_px * j / 10.0 - 0.5);
      const Eigen::Vector3d X = cam.pose.center() + 50.0 * pixel_ray_world(cam, uv);
      worst = std::max(worst, (project_opencv(oc, X) - uv).norm());
    }
  return worst;
}

TEST(ExportCheck, AnExportThatReproducesItsCameraIsWritten) {
  const Camera cam = narrow_camera();
  const ExportCheck x = check_exports(fit_opencv_camera(cam), dlt_camera(cam));
  EXPECT_FALSE(x.opencv_refused);
  EXPECT_FALSE(x.dlt_refused);
  EXPECT_TRUE(x.refused.empty());
  EXPECT_LT(x.opencv_fit_max_px, kOpenCvWarnPx);
}

TEST(ExportCheck, AnExportThatCannotReproduceItsCameraIsRefused) {
  // A skewed sensor (a2 = 0.1: x_u gains a tenth of y_d), which OpenCV's camera matrix, fitted
  // without skew, holds only in part: ~2 px left at the image's corners.
  Camera cam = narrow_camera();
  cam.intr.dist.a2 = 0.1;
  const OpenCvCamera oc = fit_opencv_camera(cam);
  const double actual = worst_projection_error(cam, oc);
  std::printf("OpenCV fit %.3f px (its report), %.3f px (measured here)\n", oc.fit_max_px, actual);
  ASSERT_GT(actual, kUnusableExportPx);
  const ExportCheck x = check_exports(oc, dlt_camera(cam));
  EXPECT_TRUE(x.opencv_refused);
  ASSERT_FALSE(x.refused.empty());
  EXPECT_EQ(x.refused[0].rfind("camera_opencv.yml: ", 0), 0u) << x.refused[0];
  EXPECT_NE(std::find(x.warnings.begin(), x.warnings.end(), "not written: " + x.refused[0]),
            x.warnings.end());
  // The figure refused by is the real miss (within the fit's own evaluation grid's reach).
  EXPECT_GT(std::max(x.opencv_fit_max_px, x.opencv_undistort_max_px), 0.5 * actual);
}

TEST(ExportCheck, AFailedFitIsRefused) {
  OpenCvCamera oc = fit_opencv_camera(narrow_camera());
  oc.fit_max_px = std::nan("");
  EXPECT_TRUE(check_exports(oc, dlt_camera(narrow_camera())).opencv_refused);
}

}  // namespace
}  // namespace rangecal
