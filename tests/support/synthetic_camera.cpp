#include "support/synthetic_camera.hpp"

#include <stdexcept>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>

#include "config/deterministic_random.hpp"

namespace rangecal::test {

std::vector<CameraParameter> parameters(const std::vector<std::string>& names) {
  std::vector<CameraParameter> out;
  for (const std::string& n : names) {
    const auto p = parameter_from_name(n);
    if (!p) throw std::invalid_argument("no camera parameter '" + n + "'");
    out.push_back(*p);
  }
  return out;
}

CameraPose look_at_pose(const Eigen::Vector3d& center, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - center).normalized();  // optical axis
  // Image right = forward × up (horizontal); looking straight up or down, north serves as "up".
  const Eigen::Vector3d up =
      std::abs(z.z()) > 1 - 1e-12 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d x = z.cross(up).normalized();
  const Eigen::Vector3d y = z.cross(x);  // image down
  CameraPose pose;
  pose.R.row(0) = x.transpose();
  pose.R.row(1) = y.transpose();
  pose.R.row(2) = z.transpose();
  pose.T = -pose.R * center;
  return pose;
}

Camera range_camera_at(const std::string& id, const Eigen::Vector3d& center, const Eigen::Vector3d& target,
                       double k1_per_mm2, const Eigen::Vector2d& principal_point_px) {
  Camera cam;
  cam.id = id;
  cam.intr.width_px = 1280;
  cam.intr.height_px = 800;
  cam.intr.dx_mm = 0.020;
  cam.intr.dy_mm = 0.020;
  cam.intr.f_mm = 135.0;
  cam.intr.sx = 1.0;
  cam.intr.u0_px = principal_point_px.x();
  cam.intr.v0_px = principal_point_px.y();
  cam.intr.dist.k1 = k1_per_mm2;
  cam.pose = look_at_pose(center, target);
  return cam;
}

TsaiSensor tsai_sensor_of(const Camera& cam) {
  TsaiSensor s;
  s.width_px = cam.intr.width_px;
  s.height_px = cam.intr.height_px;
  s.dx_mm = cam.intr.dx_mm;
  s.dy_mm = cam.intr.dy_mm;
  s.u0_px = cam.intr.u0_px;
  s.v0_px = cam.intr.v0_px;
  return s;
}

Camera range_camera(double k1_per_mm2, double sx, double du_px, double dv_px) {
  Camera cam = range_camera_at("range_cam", {0.0, 0.0, 1.5}, {0.5, 64.0, 7.5}, k1_per_mm2,
                               {639.5 + du_px, 399.5 + dv_px});
  cam.intr.sx = sx;
  return cam;
}

namespace {

bool visible(const Camera& cam, const Eigen::Vector3d& X, double margin_px) {
  Eigen::Vector2d uv;
  if (!project(cam, X, &uv)) return false;
  return uv.x() >= margin_px && uv.y() >= margin_px && uv.x() <= cam.intr.width_px - 1 - margin_px &&
         uv.y() <= cam.intr.height_px - 1 - margin_px;
}

}  // namespace

std::vector<Eigen::Vector3d> range_world_points(const Camera& cam, const RangeSceneOptions& opt) {
  const Eigen::Vector2d ascents[3] = {{-4.0, 60.0}, {0.8, 67.5}, {4.2, 63.0}};
  std::vector<Eigen::Vector3d> out;
  for (const auto& en : ascents) {
    // Visible height range of this vertical line, found on a 1 cm grid.
    double lo = 1e9, hi = -1e9;
    for (double h = 0.0; h <= 20.0; h += 0.01) {
      if (visible(cam, {en.x(), en.y(), h}, opt.margin_px)) {
        lo = std::min(lo, h);
        hi = std::max(hi, h);
      }
    }
    if (lo > hi) continue;
    for (int i = 0; i < opt.points_per_ascent; ++i) {
      const double t = opt.points_per_ascent == 1 ? 0.5 : double(i) / (opt.points_per_ascent - 1);
      out.emplace_back(en.x(), en.y(), lo + t * (hi - lo));
    }
  }
  // Pole tops spread across the lower part of the view, at several depths.
  const Eigen::Vector3d poles[8] = {{-2.5, 62.0, 4.6}, {2.0, 65.0, 4.9},  {-0.6, 61.0, 4.4},
                                    {3.3, 66.0, 5.0},  {-4.5, 64.0, 5.2}, {5.0, 61.5, 4.7},
                                    {1.2, 62.5, 4.5},  {-3.2, 66.5, 5.1}};
  for (int i = 0; i < std::min(opt.n_poles, 8); ++i)
    if (visible(cam, poles[i], opt.margin_px)) out.push_back(poles[i]);
  return out;
}

std::vector<Eigen::Vector3d> frustum_points(const Camera& cam, int n, double zmin, double zmax,
                                            std::uint64_t seed, double margin_px) {
  DeterministicRandom rng(seed);
  std::vector<Eigen::Vector3d> out;
  const auto& in = cam.intr;
  while (static_cast<int>(out.size()) < n) {
    const double u = rng.uniform(margin_px, in.width_px - 1 - margin_px);
    const double v = rng.uniform(margin_px, in.height_px - 1 - margin_px);
    const double z = rng.uniform(zmin, zmax);
    // Back-project the (distorted) pixel exactly, so the point projects to (u, v).
    const Eigen::Vector2d s = pixel_to_undistorted_sensor(in, {u, v});
    const Eigen::Vector3d xc(s.x() / in.f_mm * z, s.y() / in.f_mm * z, z);
    out.push_back(cam.pose.R.transpose() * (xc - cam.pose.T));
  }
  return out;
}

std::vector<Eigen::Vector3d> planar_grid(int nx, int ny, double pitch) {
  std::vector<Eigen::Vector3d> out;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) out.emplace_back(i * pitch, j * pitch, 0.0);
  return out;
}

Camera generic_camera(const Eigen::Vector3d& center, const Eigen::Vector3d& target, const Distortion& dist,
                      double sx) {
  Camera cam;
  cam.id = "generic_cam";
  cam.intr.width_px = 640;
  cam.intr.height_px = 480;
  cam.intr.dx_mm = 0.010;
  cam.intr.dy_mm = 0.010;
  cam.intr.f_mm = 8.0;
  cam.intr.sx = sx;
  cam.intr.u0_px = 325.3;
  cam.intr.v0_px = 236.8;
  cam.intr.dist = dist;
  cam.pose = look_at_pose(center, target);
  return cam;
}

std::vector<PointCorrespondence> observe(const Camera& cam, const std::vector<Eigen::Vector3d>& world,
                                         double pixel_sd, double world_sd, std::uint64_t seed) {
  DeterministicRandom rng(seed);
  std::vector<PointCorrespondence> out;
  out.reserve(world.size());
  for (const auto& X : world) {
    Eigen::Vector2d uv;
    if (!project(cam, X, &uv)) continue;
    PointCorrespondence pc;
    pc.pixel = uv + pixel_sd * Eigen::Vector2d(rng.normal(), rng.normal());
    pc.world = X + world_sd * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    out.push_back(pc);
  }
  return out;
}

double max_reprojection_px(const Camera& cam, const std::vector<PointCorrespondence>& pts) {
  double worst = 0;
  for (const auto& p : pts) {
    Eigen::Vector2d uv;
    if (!project(cam, p.world, &uv)) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, (uv - p.pixel).norm());
  }
  return worst;
}

double rms_reprojection_px(const Camera& cam, const std::vector<PointCorrespondence>& pts) {
  double ss = 0;
  for (const auto& p : pts) {
    Eigen::Vector2d uv;
    if (!project(cam, p.world, &uv)) return std::numeric_limits<double>::infinity();
    ss += (uv - p.pixel).squaredNorm();
  }
  return pts.empty() ? 0.0 : std::sqrt(ss / pts.size());
}

bool reprojection_residuals(const Camera& cam, const std::vector<Eigen::Vector3d>& X,
                            const std::vector<Eigen::Vector2d>& uv, Eigen::VectorXd* r) {
  r->resize(2 * static_cast<Eigen::Index>(X.size()));
  for (std::size_t i = 0; i < X.size(); ++i) {
    Eigen::Vector2d p;
    if (!project(cam, X[i], &p)) return false;
    r->segment<2>(2 * static_cast<Eigen::Index>(i)) = p - uv[i];
  }
  return true;
}

double rotation_angle_between(const Eigen::Matrix3d& Ra, const Eigen::Matrix3d& Rb) {
  return Eigen::AngleAxisd(Ra * Rb.transpose()).angle();
}

}  // namespace rangecal::test
