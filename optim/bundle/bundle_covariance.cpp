#include "optim/bundle/bundle_covariance.hpp"

#include <ceres/ceres.h>

#include <algorithm>

#include "config/error.hpp"
#include "optim/bundle/reprojection_cost_function.hpp"
#include "optim/estimation/rank_tested_inverse.hpp"

namespace rangecal {

using Eigen::MatrixXd;
using Eigen::VectorXd;

WhitenedSystem whitened_system(const BundleParameterBlocks& st, const Camera& base,
                               const std::vector<BundleObservation>& obs, const std::vector<char>& used,
                               const std::vector<Eigen::Matrix2d>& W, const BundleSetup& setup,
                               const BundleOptions& opt) {
  constexpr int kPose0 = index_of(CameraParameter::wx);
  int rows = 0;
  for (char u : used) rows += u ? 2 : 0;
  rows += (setup.principal_point_prior ? 2 : 0) + (setup.center_prior ? 3 : 0);
  MatrixXd Jall = MatrixXd::Zero(rows, kBundleParameterCount);  // every bundle parameter's column
  WhitenedSystem sys;
  sys.r.setZero(rows);
  const double* params[4] = {st.intr, st.dist, st.pose, st.clock};
  int row = 0;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    if (!used[i]) continue;
    ReprojectionCostFunction cost(ReprojectionResidual{obs[i].world, obs[i].velocity, obs[i].pixel, W[i],
                                                       st.R0, base.intr.dx_mm, base.intr.dy_mm});
    Eigen::Matrix<double, 2, kIntrinsicsBlockSize, Eigen::RowMajor> j0;
    Eigen::Matrix<double, 2, kDistortionBlockSize, Eigen::RowMajor> j1;
    Eigen::Matrix<double, 2, kPoseBlockSize, Eigen::RowMajor> j2;
    Eigen::Matrix<double, 2, kClockBlockSize> j3;  // one column: row-major is not allowed (and the same)
    double* jac[4] = {j0.data(), j1.data(), j2.data(), j3.data()};
    double res[2];
    if (!cost.Evaluate(params, res, jac))
      throw_calibration_error("bundle",
                              "observation " + std::to_string(i) + " cannot be projected at the solution");
    Jall.block(row, 0, 2, kIntrinsicsBlockSize) = j0;
    Jall.block(row, kIntrinsicsBlockSize, 2, kDistortionBlockSize) = j1;
    Jall.block(row, kPose0, 2, kPoseBlockSize) = j2;
    Jall.block(row, index_of(CameraParameter::clock_offset), 2, kClockBlockSize) = j3;
    sys.r[row] = res[0], sys.r[row + 1] = res[1];
    row += 2;
  }
  if (setup.principal_point_prior) {
    const double s = opt.priors.principal_point_sigma_px;
    Jall(row, index_of(CameraParameter::u0)) = 1 / s, Jall(row + 1, index_of(CameraParameter::v0)) = 1 / s;
    sys.r[row] = (st.intr[2] - opt.priors.principal_point_px.x()) / s;
    sys.r[row + 1] = (st.intr[3] - opt.priors.principal_point_px.y()) / s;
    row += 2;
  }
  if (setup.center_prior) {
    for (int a = 0; a < 3; ++a) {
      const double s = opt.priors.center_sigma_m[a];
      Jall(row + a, index_of(CameraParameter::CE) + a) = 1 / s;
      sys.r[row + a] = (st.pose[3 + a] - opt.priors.center_enu_m[a]) / s;
    }
  }
  const std::vector<CameraParameter> free = setup.free_parameters();
  sys.J.resize(rows, static_cast<Eigen::Index>(free.size()));
  for (std::size_t k = 0; k < free.size(); ++k)
    sys.J.col(static_cast<Eigen::Index>(k)) = Jall.col(index_of(free[k]));
  return sys;
}

double bundle_scene_distance(const Camera& cam, const std::vector<BundleObservation>& obs) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& ob : obs) mean += ob.world / static_cast<double>(obs.size());
  return std::max(1.0, (cam.pose.center() - mean).norm());
}

double bundle_max_speed(const std::vector<BundleObservation>& obs) {
  double max_speed = 0;
  for (const auto& o : obs) max_speed = std::max(max_speed, o.velocity.norm());
  return max_speed;
}

RankTestedInverse estimate_covariance(const MatrixXd& J, const std::vector<CameraParameter>& free,
                                      const Camera& cam, double scene_distance_m, double max_speed_mps,
                                      double rank_tolerance) {
  const auto p = static_cast<Eigen::Index>(free.size());
  VectorXd range(p);
  std::vector<std::string> names;
  for (Eigen::Index k = 0; k < p; ++k) {
    const CameraParameter parameter = free[static_cast<std::size_t>(k)];
    range[k] = parameter_range(parameter, cam.intr, scene_distance_m, max_speed_mps);
    names.emplace_back(parameter_name(parameter));
  }
  return rank_tested_inverse(J.transpose() * J, range, names, rank_tolerance);
}

}  // namespace rangecal
