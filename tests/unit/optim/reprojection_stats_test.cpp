// Reprojection statistics (optim/estimation/reprojection_stats.hpp) over residuals worked by hand.
#include "optim/estimation/reprojection_stats.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace rangecal {
namespace {

TEST(ReprojectionStats, RmsMeanAndMaxOverTheUsedResiduals) {
  const std::vector<Eigen::Vector2d> residuals = {{3, 4}, {0, -1}, {6, 8}, {0.6, 0.8}};
  const ReprojectionStats s = reprojection_stats(residuals, {1, 1, 0, 1});  // |e| = 5, 1, (10), 1
  EXPECT_EQ(s.n_used, 3);
  EXPECT_EQ(s.n_rejected, 1);
  EXPECT_DOUBLE_EQ(s.rms_px, std::sqrt(27.0 / 3));
  EXPECT_DOUBLE_EQ(s.mean_px, 7.0 / 3);
  EXPECT_DOUBLE_EQ(s.max_px, 5.0);
}

TEST(ReprojectionStats, NoneUsedLeavesTheStatisticsUnknown) {
  const ReprojectionStats s = reprojection_stats({{1, 0}, {0, 2}}, {0, 0});
  EXPECT_EQ(s.n_used, 0);
  EXPECT_EQ(s.n_rejected, 2);
  EXPECT_TRUE(std::isnan(s.rms_px));
  EXPECT_TRUE(std::isnan(s.mean_px));
  EXPECT_TRUE(std::isnan(s.max_px));
}

}  // namespace
}  // namespace rangecal
