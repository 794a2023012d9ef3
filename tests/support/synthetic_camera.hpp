#pragma once
// Synthetic cameras and point sets for calibration tests and benchmarks (shared by every
// calibration helper). Everything is deterministic by seed (config/deterministic_random.hpp).
//
// The range scene mirrors seed 002's experiment (docs/simulator.md): a 1280×800 camera with 20 µm pixels and
// a 135 mm lens (≈ 10.8° × 6.8° field of view) on a tripod at (0, 0, 1.5) ENU, looking roughly
// north and slightly up at three vertical lamp ascents 60–68 m away, plus a few surveyed pole tops;
// the points are non-coplanar because the ascents stand at different depths.
// Conventions are docs/conventions.md (world ENU m, Xc = R·Xw + T, camera x right / y down / z forward).
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "vision/calibration/point_correspondence.hpp"
#include "vision/calibration/tsai.hpp"
#include "vision/camera/camera_model.hpp"
#include "vision/camera/camera_parameters.hpp"

namespace rangecal::test {

/// The camera parameters of `names` (vision/camera/camera_parameters.hpp); throws
/// std::invalid_argument for a name that is none, so a typo in a test fails loudly.
std::vector<CameraParameter> parameters(const std::vector<std::string>& names);

/// A camera whose optical axis points from `center` at `target` (world ENU), image x axis kept
/// horizontal (camera x = forward × up, normalised), i.e. no roll; looking straight up or down,
/// north (+y) takes the place of up.
CameraPose look_at_pose(const Eigen::Vector3d& center, const Eigen::Vector3d& target);

/// A seed-002-like range camera named `id`: 1280×800, 20 µm pixels, f = 135 mm, sx = 1, radial k1
/// (mm⁻², distorted → undistorted) and the principal point given, at `center` looking at `target`
/// (look_at_pose). The one builder of the range cameras the tests use.
Camera range_camera_at(const std::string& id, const Eigen::Vector3d& center, const Eigen::Vector3d& target,
                       double k1_per_mm2 = -3.4e-4,
                       const Eigen::Vector2d& principal_point_px = Eigen::Vector2d(639.5, 399.5));

/// The paper-like range camera: 1280×800, 20 µm, f = 135 mm, u0 = 639.5 + du, v0 = 399.5 + dv,
/// given sx and k1 (mm⁻², distorted → undistorted), centre (0, 0, 1.5), looking at (0.5, 64, 7.5).
Camera range_camera(double k1_per_mm2 = 0.0, double sx = 1.0, double du_px = 0.0, double dv_px = 0.0);

/// Tsai's sensor description of `cam` (size, pixel pitch, principal point).
TsaiSensor tsai_sensor_of(const Camera& cam);

struct RangeSceneOptions {
  int points_per_ascent = 40;  ///< lamp points on each of the 3 vertical ascents (evenly in height)
  int n_poles = 4;             ///< pole tops (on the ground at several depths, ≈ 3.5–5 m tall)
  double margin_px = 20;       ///< points that project closer than this to the image edge are dropped
};

/// World points of the range scene, all visible in `cam` (projected inside the image minus margin):
/// three ascents at (E, N) = (−4.0, 60.0), (0.8, 67.5), (4.2, 63.0), heights spanning the field of
/// view, and pole tops at (−2.5, 62, 4.2), (2.0, 65, 3.6), (−0.6, 61, 4.8), (3.3, 66, 4.4), …
std::vector<Eigen::Vector3d> range_world_points(const Camera& cam, const RangeSceneOptions& opt = {});

/// Generic non-coplanar cloud: `n` points uniformly random inside the camera's view frustum between
/// depths zmin and zmax (camera z, world units), image margin `margin_px`.
std::vector<Eigen::Vector3d> frustum_points(const Camera& cam, int n, double zmin, double zmax,
                                            std::uint64_t seed, double margin_px = 10);

/// A planar grid in the world plane Z = 0: nx × ny points with spacing `pitch`, first at (0, 0).
std::vector<Eigen::Vector3d> planar_grid(int nx, int ny, double pitch);

/// A generic wide-ish camera (640×480, 10 µm, f = 8 mm ⇒ ≈ 44° FOV) at `center` looking at `target`.
Camera generic_camera(const Eigen::Vector3d& center, const Eigen::Vector3d& target,
                      const Distortion& dist = {}, double sx = 1.0);

/// Projects the points with the exact model (camera_model.hpp) and adds Gaussian noise: pixel_sd
/// per image axis (px) and world_sd per world axis (world units) on the returned world point (the
/// pixel stays the projection of the TRUE point, as with survey error). Points that do not project
/// (behind, distortion inverse failure) are dropped. Deterministic by seed.
std::vector<PointCorrespondence> observe(const Camera& cam, const std::vector<Eigen::Vector3d>& world,
                                         double pixel_sd = 0.0, double world_sd = 0.0,
                                         std::uint64_t seed = 1);

/// Largest / RMS pixel reprojection error of `cam` over `pts` (pixel distance per point).
double max_reprojection_px(const Camera& cam, const std::vector<PointCorrespondence>& pts);
double rms_reprojection_px(const Camera& cam, const std::vector<PointCorrespondence>& pts);

/// The stacked residuals project(cam, X[i]) − uv[i] (2 per point) into `r`, for a least-squares
/// search over a camera; false when a point does not project.
bool reprojection_residuals(const Camera& cam, const std::vector<Eigen::Vector3d>& X,
                            const std::vector<Eigen::Vector2d>& uv, Eigen::VectorXd* r);

/// Angle (rad) of the rotation Ra·Rbᵀ.
double rotation_angle_between(const Eigen::Matrix3d& Ra, const Eigen::Matrix3d& Rb);

}  // namespace rangecal::test
