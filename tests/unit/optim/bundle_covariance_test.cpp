// The bundle's covariance (optim/bundle/bundle_covariance.hpp): the whitened system's residuals
// against vision's project() and the whitening by hand, its Jacobian against central differences of
// those residuals, its prior rows; the covariance against (JᵀJ)⁻¹ by LU, and the rank test naming
// two parameters that move the image alike, by text and by code.
#include "optim/bundle/bundle_covariance.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include "optim/bundle/calibration_warning.hpp"
#include "optim/bundle/whitening.hpp"
#include "support/bundle_synthetic.hpp"

namespace rangecal {
namespace {

using Eigen::MatrixXd;
using Eigen::Vector2d;
using Eigen::Vector3d;

struct Scene {
  Camera cam;
  std::vector<BundleObservation> obs;
  std::vector<Eigen::Matrix2d> W;
  BundleOptions opt;
  BundleSetup setup;
};

Scene scene() {
  Scene s;
  s.cam = test::narrow_fov_camera();
  const test::SyntheticPoints pts = test::synthetic_points(s.cam, 12, 3);
  for (std::size_t i = 0; i < pts.world.size(); ++i) {
    BundleObservation o;
    o.world = pts.world[i];
    o.pixel = pts.pixel[i] + Vector2d(0.3 * std::sin(double(i)), -0.2 * std::cos(double(i)));
    o.world_cov = Eigen::Matrix3d::Identity() * 1e-4;
    o.velocity = Vector3d(0, 0, 3);
    s.obs.push_back(o);
  }
  s.opt.free = {"f", "k1", "u0", "v0", "pose"};
  s.opt.priors.use_principal_point = true;
  s.opt.priors.principal_point_px = Vector2d(640, 400);
  s.opt.priors.principal_point_sigma_px = 5;
  s.setup = bundle_setup(s.opt);
  s.W = whitening_matrices(s.cam, s.obs, s.opt.pixel_sigma_px);
  return s;
}

TEST(BundleCovariance, WhitenedResidualsAreTheWhitenedReprojectionErrors) {
  const Scene s = scene();
  ASSERT_TRUE(s.setup.principal_point_prior);
  const double clock = 0.004;
  const BundleParameterBlocks b = BundleParameterBlocks::from_camera(s.cam, clock);
  std::vector<char> used(s.obs.size(), 1);
  used[5] = 0;
  const WhitenedSystem sys = whitened_system(b, s.cam, s.obs, used, s.W, s.setup, s.opt);
  ASSERT_EQ(sys.r.size(), 2 * 11 + 2);
  ASSERT_EQ(sys.J.cols(), 10);  // f, u0, v0, k1, wx wy wz, CE CN CU
  int row = 0;
  for (std::size_t i = 0; i < s.obs.size(); ++i) {
    if (!used[i]) continue;
    Vector2d uv;
    ASSERT_TRUE(project(s.cam, s.obs[i].world - s.obs[i].velocity * clock, &uv));
    const Vector2d expected = s.W[i] * (uv - s.obs[i].pixel);
    EXPECT_NEAR(sys.r[row], expected.x(), 1e-6);
    EXPECT_NEAR(sys.r[row + 1], expected.y(), 1e-6);
    row += 2;
  }
  // The principal-point prior: (u0 − 640)/5, (v0 − 400)/5 with ∂/∂u0 = 1/5.
  EXPECT_NEAR(sys.r[row], (s.cam.intr.u0_px - 640) / 5, 1e-12);
  EXPECT_NEAR(sys.r[row + 1], (s.cam.intr.v0_px - 400) / 5, 1e-12);
  EXPECT_EQ(sys.J(row, 1), 0.2);
  EXPECT_EQ(sys.J(row + 1, 2), 0.2);
  EXPECT_EQ(sys.J(row, 0), 0.0);
}

TEST(BundleCovariance, JacobianMatchesFiniteDifferences) {
  const Scene s = scene();
  const BundleParameterBlocks b = BundleParameterBlocks::from_camera(s.cam);
  const std::vector<char> used(s.obs.size(), 1);
  const WhitenedSystem sys = whitened_system(b, s.cam, s.obs, used, s.W, s.setup, s.opt);
  // Column k of the free parameters (canonical order f u0 v0 k1 wx wy wz CE CN CU) and where it lives.
  struct Column {
    int k;
    int block;
    int index;
    double h;
  };
  for (const Column c :
       {Column{0, 0, 0, 1e-4}, Column{3, 1, 0, 1e-9}, Column{4, 2, 0, 1e-7}, Column{7, 2, 3, 1e-4}}) {
    BundleParameterBlocks plus = b, minus = b;
    plus.block(c.block)[c.index] += c.h;
    minus.block(c.block)[c.index] -= c.h;
    const Eigen::VectorXd d = (whitened_system(plus, s.cam, s.obs, used, s.W, s.setup, s.opt).r -
                               whitened_system(minus, s.cam, s.obs, used, s.W, s.setup, s.opt).r) /
                              (2 * c.h);
    EXPECT_LT((sys.J.col(c.k) - d).norm(), 1e-5 * d.norm()) << "column " << c.k;
  }
}

// The oracle is the inverse by LU of the normal matrix of the same rows, the principal-point prior's
// two among them (an oracle without them is not the scene's covariance).
TEST(BundleCovariance, CovarianceIsTheInverseNormalMatrix) {
  const Scene s = scene();
  const BundleParameterBlocks b = BundleParameterBlocks::from_camera(s.cam);
  const WhitenedSystem sys =
      whitened_system(b, s.cam, s.obs, std::vector<char>(s.obs.size(), 1), s.W, s.setup, s.opt);
  const std::vector<CameraParameter> free = s.setup.free_parameters();
  const RankTestedInverse cov = estimate_covariance(sys.J, free, s.cam, 64, 3, 1e-14);
  ASSERT_FALSE(cov.rank_deficient);
  const MatrixXd expected = (sys.J.transpose() * sys.J).fullPivLu().inverse();
  for (int a = 0; a < expected.rows(); ++a)
    for (int c = 0; c < expected.cols(); ++c)
      EXPECT_NEAR(cov.covariance(a, c), expected(a, c), 1e-8 * std::sqrt(expected(a, a) * expected(c, c)))
          << parameter_name(free[a]) << ", " << parameter_name(free[c]);
  // The prior bounds σ_u0 by its own 5 px.
  EXPECT_LT(std::sqrt(cov.covariance(1, 1)), 5.0);
}

TEST(BundleCovariance, TwoParametersMovingTheImageAlikeAreNamed) {
  const Scene s = scene();
  const BundleParameterBlocks b = BundleParameterBlocks::from_camera(s.cam);
  WhitenedSystem sys =
      whitened_system(b, s.cam, s.obs, std::vector<char>(s.obs.size(), 1), s.W, s.setup, s.opt);
  const std::vector<CameraParameter> free = s.setup.free_parameters();
  sys.J.col(9) = 2 * sys.J.col(8);  // CU only ever as CN
  const RankTestedInverse cov = estimate_covariance(sys.J, free, s.cam, 64, 3, 1e-14);
  EXPECT_TRUE(cov.rank_deficient);
  EXPECT_EQ(cov.covariance.size(), 0);
  ASSERT_EQ(cov.warnings.size(), 1u);
  EXPECT_NE(cov.warnings[0].find("CN, CU cannot be determined"), std::string::npos) << cov.warnings[0];
  // The same two as a typed code (optim/bundle/calibration_warning.hpp), read from the indices.
  const std::vector<CalibrationWarning> codes =
      rank_deficiency_warnings(cov.warnings, cov.named, free, "cam1");
  ASSERT_EQ(codes.size(), 1u);
  EXPECT_EQ(codes[0].kind, CalibrationWarningKind::rank_deficient);
  EXPECT_EQ(codes[0].camera, "cam1");
  EXPECT_EQ(codes[0].parameters, (std::vector<CameraParameter>{CameraParameter::CN, CameraParameter::CU}));
  EXPECT_EQ(codes[0].text, cov.warnings[0]);
}

}  // namespace
}  // namespace rangecal
