// A distortion a lens can have over its image (vision/camera/distortion_validity.hpp): the limits
// against their closed forms. For the radial model r_u = r (1 + k1 r²) the map folds where
// d r_u / dr = 1 + 3 k1 r² = 0, r_f = 1 / √(−3 k1), and moves a point by |k1| r² of its radius.
#include <gtest/gtest.h>

#include <cmath>

#include "vision/camera/distortion_validity.hpp"

namespace rangecal {
namespace {

// 1000 × 800 px of 10 µm about the image centre: the farthest corner (pixel (−0.5, −0.5)) lies
// 5 mm × 4 mm from the principal point, r = √41 mm.
CameraIntrinsics sensor() {
  CameraIntrinsics in;
  in.width_px = 1000;
  in.height_px = 800;
  in.dx_mm = in.dy_mm = 0.01;
  in.f_mm = 25;
  in.u0_px = 499.5;
  in.v0_px = 399.5;
  return in;
}

const double kCorner2 = 41.0;  // r² at the farthest corner (mm²)

DistortionFault check(const CameraIntrinsics& in, bool* ok) {
  DistortionFault f;
  *ok = distortion_is_physical(in, &f);
  return f;
}

TEST(DistortionValidity, NoDistortionAndTheSamplesOfRealLensesPass) {
  bool ok = false;
  check(sensor(), &ok);
  EXPECT_TRUE(ok);
  CameraIntrinsics in = sensor();
  in.dist.k1 = -3.4e-4;  // the project tests' 135 mm lens, 1280 × 800 px of 20 µm
  in.dist.p1 = 2e-5;
  in.dist.a1 = 1e-4;
  check(in, &ok);
  EXPECT_TRUE(ok);
}

TEST(DistortionValidity, BarrelFoldInsideTheImageIsRefusedAndJustOutsideIsAccepted) {
  for (const double r_fold : {3.0, 6.0, 6.35}) {  // mm, all inside √41 = 6.403 mm
    SCOPED_TRACE(r_fold);
    CameraIntrinsics in = sensor();
    in.dist.k1 = -1 / (3 * r_fold * r_fold);
    bool ok = true;
    const DistortionFault f = check(in, &ok);
    EXPECT_FALSE(ok);
    EXPECT_EQ(f.coefficient, 0);  // k1
    EXPECT_NE(f.reason.find("folds"), std::string::npos) << f.reason;
  }
  CameraIntrinsics in = sensor();
  in.dist.k1 = -1 / (3 * 6.45 * 6.45);  // folds 0.05 mm beyond the corner: invertible, |Δ| 33 % of r
  bool ok = false;
  check(in, &ok);
  EXPECT_TRUE(ok);
}

TEST(DistortionValidity, DisplacementBeyondThePointsOwnRadiusIsRefused) {
  CameraIntrinsics in = sensor();
  in.dist.k1 = 0.99 / kCorner2;  // the corner moves 0.99 of its radius: accepted
  bool ok = false;
  check(in, &ok);
  EXPECT_TRUE(ok);
  in.dist.k1 = 1.01 / kCorner2;
  DistortionFault f = check(in, &ok);
  EXPECT_FALSE(ok);
  EXPECT_EQ(f.coefficient, 0);
  EXPECT_NE(f.reason.find("pixel (-0.5, -0.5)"), std::string::npos) << f.reason;
  in.dist.k1 = 1e6;  // the unit mistake: every point would land near the centre
  f = check(in, &ok);
  EXPECT_FALSE(ok);
  EXPECT_EQ(f.coefficient, 0);
}

TEST(DistortionValidity, TheDominantTermIsNamed) {
  CameraIntrinsics in = sensor();
  in.dist.k2 = -1 / (5 * std::pow(5.0, 4));  // 1 + 5 k2 r⁴ = 0 at r = 5 mm, inside the image
  bool ok = true;
  DistortionFault f = check(in, &ok);
  EXPECT_FALSE(ok);
  EXPECT_EQ(f.coefficient, 1);  // k2
  in = sensor();
  in.dist.a2 = -1.2;  // ∂yu/∂yd = 1 + a2 < 0 everywhere: the image is mirrored, det J < 0
  f = check(in, &ok);
  EXPECT_FALSE(ok);
  EXPECT_EQ(f.coefficient, 6);  // a2
  EXPECT_NE(f.reason.find("det J"), std::string::npos) << f.reason;
}

}  // namespace
}  // namespace rangecal
