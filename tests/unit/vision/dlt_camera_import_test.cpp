// DLT-11 → rangecal camera (vision/calibration/dlt_camera_import.hpp). Truth: a projection matrix built in
// the test from K (with and without skew), R and C — P = K·[R | −R·C], turned to the tools' y-up
// pixel frame and normalised by P₃₄ as Abdel-Aziz & Karara's coefficients are — and rangecal's own
// export (vision/camera/dlt_export.hpp) round-tripped. The coefficient file's reader names the file
// for every malformed input, and the line and column where there is one.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>

#include "config/error.hpp"
#include "support/expect_error.hpp"
#include "support/paths.hpp"
#include "vision/calibration/dlt_camera_import.hpp"
#include "vision/camera/dlt_export.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;

constexpr int kW = 1920, kH = 1080;
const SensorGeometry kSensor{kW, kH, 0.0055, 0.0055};

struct Truth {
  Eigen::Matrix3d K, R;
  Eigen::Vector3d C;
};

Truth truth(double skew_px) {
  Truth t;
  t.K << 1650.0, skew_px, 981.4, 0, 1642.5, 528.9, 0, 0, 1;
  // A camera 40 m south-west of the origin, 4 m up, looking north-east and a little down: rangecal's
  // camera axes are x right, y down, z forward.
  const Eigen::Vector3d forward = Eigen::Vector3d(1, 1, -0.1).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  t.R.row(0) = right;
  t.R.row(1) = down;
  t.R.row(2) = forward;
  t.C = Eigen::Vector3d(-28.0, -29.0, 4.0);
  return t;
}

// L1 … L11 of the truth, written as the tools write them (origin bottom-left, y up).
std::array<double, 11> coefficients(const Truth& t) {
  Eigen::Matrix<double, 3, 4> P;
  P.leftCols<3>() = t.K * t.R;
  P.col(3) = -t.K * t.R * t.C;
  Eigen::Matrix3d to_tools;  // x = u + 0.5, y = H − 0.5 − v
  to_tools << 1, 0, 0.5, 0, -1, kH - 0.5, 0, 0, 1;
  P = (to_tools * P).eval();
  P /= P(2, 3);
  return {P(0, 0), P(0, 1), P(0, 2), P(0, 3), P(1, 0), P(1, 1), P(1, 2), P(1, 3), P(2, 0), P(2, 1), P(2, 2)};
}

TEST(DltCameraImport, APinholeComesBackExactly) {
  const Truth t = truth(0.0);
  double skew = 1;
  const ImportedCamera r = camera_from_dlt(coefficients(t), kSensor, &skew);
  EXPECT_NEAR(skew, 0, 1e-9);
  EXPECT_NEAR(r.camera.intr.f_mm, 1642.5 * 0.0055, 1e-9);
  EXPECT_NEAR(r.camera.intr.sx, 1650.0 / 1642.5, 1e-12);
  EXPECT_NEAR(r.camera.intr.u0_px, 981.4, 1e-8);
  EXPECT_NEAR(r.camera.intr.v0_px, 528.9, 1e-8);
  EXPECT_NEAR((r.camera.pose.R - t.R).norm(), 0, 1e-12);
  EXPECT_NEAR((r.camera.pose.center() - t.C).norm(), 0, 1e-9);
  EXPECT_LT(r.fit_max_px, 1e-8);
  // A world point projects where the truth's P puts it.
  const Eigen::Vector3d X(5, 7, 2);
  Eigen::Vector2d uv;
  ASSERT_TRUE(project(r.camera, X, &uv));
  const Eigen::Vector3d p = t.K * t.R * (X - t.C);
  EXPECT_NEAR(uv.x(), p.x() / p.z(), 1e-8);
  EXPECT_NEAR(uv.y(), p.y() / p.z(), 1e-8);
}

TEST(DltCameraImport, ADroppedSkewIsMeasuredAsTheFitError) {
  // A DLT fitted to noisy clicks has a small skew; rangecal's model has none. Without skew a pixel's
  // ray lands s·y' px to the side, y' = (v − cy)/fy the ray's normalised height: at most |s|·max|v − cy|/fy
  // over the image, computed here in closed form.
  const double s = 2.0;
  const Truth t = truth(s);
  double skew = 0;
  const ImportedCamera r = camera_from_dlt(coefficients(t), kSensor, &skew);
  EXPECT_NEAR(skew, s, 1e-8);
  const double bound = s * std::max(528.9, kH - 1 - 528.9) / 1642.5;
  std::printf("skew %.1f px: fit max %.4f px (closed-form bound %.4f), rms %.4f px\n", s, r.fit_max_px, bound,
              r.fit_rms_px);
  EXPECT_LT(r.fit_max_px, bound + 1e-9);
  EXPECT_GT(r.fit_max_px, 0.97 * bound);  // the evaluation grid reaches within 1.2 % of the rim
  EXPECT_GT(r.fit_rms_px, 0.4 * bound);
  EXPECT_NEAR((r.camera.pose.center() - t.C).norm(), 0, 1e-9);  // the centre does not depend on K
}

TEST(DltCameraImport, RangecalsOwnExportRoundTrips) {
  Camera cam;
  cam.id = "c1";
  cam.intr = {1280, 800, 0.02, 0.02, 136.12, 0.9966, 640.27, 399.67, {}};
  cam.pose.R = Eigen::AngleAxisd(0.8, Eigen::Vector3d(0.2, 1, -0.1).normalized()).toRotationMatrix();
  cam.pose.T = Eigen::Vector3d(-4.2, -3.0, 63.8);
  const DltCamera d = dlt_camera(cam);
  const ImportedCamera r = camera_from_dlt(d.L, SensorGeometry{1280, 800, 0.02, 0.02});
  EXPECT_NEAR(r.camera.intr.f_mm / cam.intr.f_mm, 1, 1e-9);
  EXPECT_NEAR(r.camera.intr.sx, cam.intr.sx, 1e-9);
  EXPECT_NEAR(r.camera.intr.u0_px, cam.intr.u0_px, 1e-6);
  EXPECT_NEAR(r.camera.intr.v0_px, cam.intr.v0_px, 1e-6);
  EXPECT_NEAR((r.camera.pose.center() - cam.pose.center()).norm(), 0, 1e-7);
  EXPECT_LT(r.fit_max_px, 1e-6);
}

TEST(DltCameraImport, CoefficientsWithoutACameraAreACalibrationError) {
  std::array<double, 11> L{};
  L[0] = 1;  // rank-deficient M3
  EXPECT_EQ(test::expect_error([&] { camera_from_dlt(L, kSensor); }).exit_code(), 4);
  std::array<double, 11> good = coefficients(truth(0));
  good[4] *= 5;  // fy five times fx: no camera's pixels
  good[5] *= 5;
  good[6] *= 5;
  good[7] *= 5;
  const Error e = test::expect_error([&] { camera_from_dlt(good, kSensor); });
  EXPECT_EQ(e.exit_code(), 4);
  EXPECT_NE(e.reason().find("square"), std::string::npos) << e.reason();
  // The same coefficients read for an image 600 px shorter: v0 moves 600 px up, off the image.
  const Error taller = test::expect_error([&] {
    camera_from_dlt(coefficients(truth(0)), {kW, kH - 600, 0.0055, 0.0055});
  });
  EXPECT_EQ(taller.exit_code(), 4);
  EXPECT_NE(taller.reason().find("lies off the 1920 × 480 image"), std::string::npos) << taller.reason();
}

std::string format_coefficient(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

TEST(DltCameraImport, TheCoefficientFileIsReadByColumn) {
  const fs::path dir = test::scratch_dir("dlt_import_read");
  const std::array<double, 11> a = coefficients(truth(0)), b = coefficients(truth(1));
  std::string text = "\xEF\xBB\xBF";
  for (int i = 0; i < 11; ++i) text += format_coefficient(a[i]) + ", " + format_coefficient(b[i]) + "\r\n";
  text += "\n\n";
  test::write_text(dir / "dlt.csv", text);
  const std::array<double, 11> back = read_dlt_coefficients_csv((dir / "dlt.csv").string(), 2);
  for (int i = 0; i < 11; ++i) EXPECT_DOUBLE_EQ(back[i], b[i]) << "L" << i + 1;
}

TEST(DltCameraImport, AMalformedCoefficientFileNamesFileLineAndColumn) {
  const fs::path dir = test::scratch_dir("dlt_import_bad");
  std::string ten;
  for (int i = 0; i < 10; ++i) ten += "1.5,2.5\n";
  test::write_text(dir / "ten.csv", ten);
  Error e = test::expect_error([&] { read_dlt_coefficients_csv((dir / "ten.csv").string(), 1); });
  EXPECT_EQ(e.exit_code(), 3);
  EXPECT_NE(e.reason().find("10 coefficient lines"), std::string::npos) << e.what();
  EXPECT_EQ(e.file(), (dir / "ten.csv").string());

  test::write_text(dir / "twelve.csv", ten + "1,2\n1,2\n");
  e = test::expect_error([&] { read_dlt_coefficients_csv((dir / "twelve.csv").string(), 1); });
  EXPECT_EQ(e.line(), 12);

  std::string word = ten;
  word.insert(8 * 3, "1,x\n");  // line 4
  test::write_text(dir / "word.csv", word);
  e = test::expect_error([&] { read_dlt_coefficients_csv((dir / "word.csv").string(), 2); });
  EXPECT_EQ(e.line(), 4);
  EXPECT_EQ(e.field(), "column 2");
  EXPECT_NE(e.reason().find("'x'"), std::string::npos);

  e = test::expect_error([&] { read_dlt_coefficients_csv((dir / "ten.csv").string(), 3); });
  EXPECT_EQ(e.line(), 1);
  EXPECT_EQ(e.field(), "column 3");

  e = test::expect_error([&] { read_dlt_coefficients_csv((dir / "missing.csv").string(), 1); });
  EXPECT_EQ(e.exit_code(), 3);
  EXPECT_NE(std::string(e.what()).find("missing.csv"), std::string::npos);
}

}  // namespace
}  // namespace rangecal
