// The network's outlier rules (optim/network/network_outliers.hpp): the χ²_m quantiles against
// tabulated values; the PPK test on a point whose adjusted position is moved off its fix (d² against
// rᵀ·Σ_prior⁻¹·r, which it approaches when many rays fix the point to a millimetre); the image test's
// residuals against vision's project() and its threshold against the robust scale of the camera's
// whitened norms.
#include "optim/network/network_outliers.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "optim/estimation/robust_scale.hpp"
#include "support/synthetic_network.hpp"

namespace rangecal {
namespace {

TEST(NetworkOutliers, Chi2QuantilesMatchTheTables) {
  // Abramowitz & Stegun table 26.8 / any χ² table.
  EXPECT_NEAR(chi2_upper_quantile(1, 0.05), 3.841458820694124, 1e-9);
  EXPECT_NEAR(chi2_upper_quantile(2, 0.05), 5.991464547107979, 1e-9);
  EXPECT_NEAR(chi2_upper_quantile(3, 0.05), 7.814727903251178, 1e-9);
  EXPECT_NEAR(chi2_upper_quantile(2, 1e-4), -2 * std::log(1e-4), 1e-9);
  EXPECT_NEAR(chi2_upper_quantile(1, 1e-4), 15.136705226623606, 1e-8);
  EXPECT_NEAR(chi2_upper_quantile(3, 1e-4), 21.10751347600523, 1e-8);
}

using Network = test::NetworkScene;

/// In place: the layout points into `n->data`.
void build(Network* network) {
  network->data = test::synthetic_network(4, 60, 13);
  test::lay_out_network(network);
}

/// A point seen by every camera.
std::size_t point_seen_by_all(const Network& n) {
  for (std::size_t k = 0; k < n.layout.by_point.size(); ++k)
    if (n.layout.by_point[k].size() == n.data.cameras.size()) return k;
  ADD_FAILURE() << "no point seen by every camera";
  return 0;
}

TEST(NetworkOutliers, PpkTestFlagsAnAdjustedPointFarFromItsFix) {
  Network n;
  build(&n);
  const std::size_t bad = point_seen_by_all(n), good = bad == 0 ? 1 : 0;
  ASSERT_GE(n.layout.by_point[good].size(), 2u);
  const Eigen::Vector3d r_bad(0.05, -0.03, 0.02), r_good(0.001, 0, 0);
  for (int a = 0; a < 3; ++a) {
    n.blocks.points[bad][a] = n.data.points[bad].prior_enu[a] + r_bad[a];
    n.blocks.points[good][a] = n.data.points[good].prior_enu[a] + r_good[a];
  }
  std::vector<NetworkPointResult> results(n.data.points.size());
  const std::vector<std::size_t> flagged =
      flag_ppk_outliers(n.layout, n.blocks, 1e-4, &n.selection, &results);
  ASSERT_EQ(flagged, std::vector<std::size_t>{bad});
  EXPECT_TRUE(results[bad].ppk_outlier);
  EXPECT_EQ(results[bad].ppk_test_dof, 3);
  // Σ_prior = 1 cm² per axis: d² = ‖r‖²/1e-4 = 38 with the rays' V⁻¹ ≪ Σ_prior (≲ 1 % of it).
  const double expected = r_bad.squaredNorm() / 1e-4;
  EXPECT_NEAR(results[bad].ppk_test_d2, expected, 0.03 * expected);
  EXPECT_GT(results[bad].ppk_test_d2, expected);  // Σ_r = Σ_prior − V⁻¹ is the smaller
  EXPECT_EQ(n.selection.prior[bad], 0);           // its prior leaves the solve
  EXPECT_FALSE(results[good].ppk_outlier);
  EXPECT_NEAR(results[good].ppk_test_d2, 0.01, 0.01 * 0.03);
  EXPECT_EQ(n.selection.prior[good], 1);
}

TEST(NetworkOutliers, ImageTestFlagsAPixelOffByTwentyPixels) {
  Network n;
  build(&n);
  const std::size_t bad = 7;
  n.data.observations[bad].pixel += Eigen::Vector2d(20, -5);
  n.layout = make_network_layout(n.data.cameras, n.data.points, n.data.observations);
  for (std::size_t c = 0; c < n.data.cameras.size(); ++c)  // residuals of the noise alone
    n.blocks.cameras[c] = BundleParameterBlocks::from_camera(n.data.truth[c]);
  const double k = 5;  // no false flag among these ~240 observations
  const ImageOutlierTest t = test_image_observations(n.layout, n.blocks, n.selection, k);
  for (std::size_t i = 0; i < n.data.observations.size(); ++i) {
    const NetworkObservation& o = n.data.observations[i];
    Eigen::Vector2d uv;
    ASSERT_TRUE(project(n.blocks.cameras[o.camera].to_camera(n.layout.starts[o.camera]),
                        n.data.points[o.point].prior_enu, &uv));
    EXPECT_LT((t.residual_px[i] - (uv - o.pixel)).norm(), 1e-9) << i;
    EXPECT_EQ(t.outlier[i], i == bad) << i << ": " << t.whitened_norm[i] << " σ";
  }
  for (std::size_t c = 0; c < n.data.cameras.size(); ++c) {
    std::vector<double> norms;
    for (std::size_t i = 0; i < n.data.observations.size(); ++i)
      if (n.data.observations[i].camera == c) norms.push_back(t.whitened_norm[i]);
    EXPECT_DOUBLE_EQ(t.threshold[c], robust_outlier_threshold(k, norms)) << c;
  }
}

}  // namespace
}  // namespace rangecal
