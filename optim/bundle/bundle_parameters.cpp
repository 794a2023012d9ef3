#include "optim/bundle/bundle_parameters.hpp"

#include <ceres/rotation.h>

#include <algorithm>

namespace rangecal {

BundleParameterBlocks BundleParameterBlocks::from_camera(const Camera& c, double clock_offset_s) {
  BundleParameterBlocks s;
  s.clock[0] = clock_offset_s;
  s.intr[0] = c.intr.f_mm, s.intr[1] = c.intr.sx, s.intr[2] = c.intr.u0_px, s.intr[3] = c.intr.v0_px;
  const auto d = c.intr.dist.as_array();
  std::copy(d.begin(), d.end(), s.dist);
  const Eigen::Vector3d C = c.pose.center();
  s.pose[0] = s.pose[1] = s.pose[2] = 0;
  s.pose[3] = C.x(), s.pose[4] = C.y(), s.pose[5] = C.z();
  s.R0 = c.pose.R;
  return s;
}

Camera BundleParameterBlocks::to_camera(const Camera& base) const {
  Camera c = base;
  c.intr.f_mm = intr[0], c.intr.sx = intr[1], c.intr.u0_px = intr[2], c.intr.v0_px = intr[3];
  c.intr.dist = Distortion::from_array(dist);
  Eigen::Matrix3d dR;
  ceres::AngleAxisToRotationMatrix(pose, ceres::ColumnMajorAdapter3x3(dR.data()));
  c.pose.R = dR * R0;
  const Eigen::Vector3d C(pose[3], pose[4], pose[5]);
  c.pose.T = -c.pose.R * C;
  return c;
}

void BundleParameterBlocks::rebase_rotation(const Camera& base) {
  const BundleParameterBlocks re = from_camera(to_camera(base));
  std::copy(re.pose, re.pose + kPoseBlockSize, pose);
  R0 = re.R0;
}

std::vector<CameraParameter> BundleSetup::free_parameters() const {
  std::vector<CameraParameter> out;
  for (int i = 0; i < kBundleParameterCount; ++i)
    if (free[static_cast<std::size_t>(i)]) out.push_back(parameter_at(i));
  return out;
}

BundleSetup bundle_setup(const BundleOptions& opt) {
  BundleSetup s;
  for (CameraParameter p : expand_free_parameters(opt.free))
    s.free[static_cast<std::size_t>(index_of(p))] = true;
  s.n_free = static_cast<int>(std::count(s.free.begin(), s.free.end(), true));
  s.principal_point_prior =
      opt.priors.use_principal_point && (s.is_free(CameraParameter::u0) || s.is_free(CameraParameter::v0));
  s.center_prior =
      opt.priors.use_center &&
      (s.is_free(CameraParameter::CE) || s.is_free(CameraParameter::CN) || s.is_free(CameraParameter::CU));
  return s;
}

Camera bundle_starting_camera(const Camera& initial, const BundleSetup& setup, const BundleOptions& opt) {
  Camera start = initial;
  if (opt.priors.use_principal_point && opt.priors.principal_point_px.allFinite()) {
    if (!setup.is_free(CameraParameter::u0)) start.intr.u0_px = opt.priors.principal_point_px.x();
    if (!setup.is_free(CameraParameter::v0)) start.intr.v0_px = opt.priors.principal_point_px.y();
  }
  return start;
}

}  // namespace rangecal
