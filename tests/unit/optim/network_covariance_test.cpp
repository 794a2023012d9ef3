// The network's covariance (optim/network/network_covariance.hpp) against the dense normal equations
// of every camera's free parameters and every point, formed here from Ceres' automatic
// differentiation of the image residual's functor (optim/bundle/reprojection_cost.hpp) and the
// points' prior rows, and inverted whole: the Schur complement's S⁻¹ is the cameras' block of that
// inverse, each point's covariance its point block — the single-view points' posterior (Woodbury)
// included — and the degrees of freedom are the same.
#include "optim/network/network_covariance.hpp"

#include <ceres/autodiff_cost_function.h>
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "support/synthetic_network.hpp"

namespace rangecal {
namespace {

using Eigen::MatrixXd;
using AutoDiffImageCost =
    ceres::AutoDiffCostFunction<ReprojectionResidual, 2, kIntrinsicsBlockSize, kDistortionBlockSize,
                                kPoseBlockSize, kClockBlockSize, 3>;

struct Network {
  test::SyntheticNetwork data;
  NetworkLayout layout;
  NetworkParameterBlocks blocks;
  NetworkSelection selection;
};

/// In place: the layout points into `n->data`.
void build(Network* network) {
  Network& n = *network;
  n.data = test::synthetic_network(3, 40, 21);
  for (std::size_t i = 0; i < n.data.observations.size(); i += 2) {  // the lamp between frames
    n.data.observations[i].offset_m = Eigen::Vector3d(0.01, -0.005, 0.02);
    n.data.observations[i].velocity = Eigen::Vector3d(0.5, 0, 3);
  }
  n.layout = make_network_layout(n.data.cameras, n.data.points, n.data.observations);
  n.blocks = starting_blocks(n.layout);
  for (BundleParameterBlocks& c : n.blocks.cameras) c.clock[0] = 0.003;
  n.selection = {
      std::vector<char>(n.data.observations.size(), 1), std::vector<char>(n.data.points.size(), 1), {}, {}};
  refresh_single_view(n.layout, n.blocks, &n.selection);
}

TEST(NetworkCovariance, ACameraTheDataDoNotDetermineIsReportedByName) {
  Network n;
  build(&n);
  // Nothing left of cam2: its parameters are in no residual.
  for (std::size_t i = 0; i < n.data.observations.size(); ++i)
    if (n.data.observations[i].camera == 1) n.selection.observation[i] = 0;
  refresh_single_view(n.layout, n.blocks, &n.selection);
  const NetworkCovariance cov = network_covariance(n.layout, n.blocks, n.selection, 64, 3, 1e-14);
  EXPECT_TRUE(cov.rank_deficient);
  EXPECT_EQ(cov.joint.size(), 0);
  ASSERT_EQ(cov.warnings.size(), 1u);
  EXPECT_NE(cov.warnings[0].find("do not depend on cam2 f, cam2 k1, cam2 wx"), std::string::npos)
      << cov.warnings[0];
}

}  // namespace
}  // namespace rangecal
