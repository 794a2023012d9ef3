#pragma once
// The calibration parameters of the camera model (vision/camera/camera_model.hpp), declared once
// in the manner of COLMAP's sensor/models.h (params_info, *_idxs): each parameter's name as it is
// written in configs and output files, its unit, what it means, the scale a search conditions it
// with, and how it is read from and written to a Camera. Every method, the bundle, the Monte Carlo,
// the triangulation σ and the route planner read this table; none spells a name itself.
//
//   name          unit    meaning
//   f             mm      effective focal length
//   sx            1       horizontal scale factor (Tsai's sx)
//   u0 v0         px      principal point
//   k1 k2 k3      mm⁻² mm⁻⁴ mm⁻⁶   radial distortion, distorted → undistorted sensor mm (seed 000 eq. 7)
//   p1 p2         mm⁻¹    decentring distortion
//   a1 a2         1       affine distortion
//   wx wy wz      rad     rotation perturbation: R = exp([w]×)·R̂, a left perturbation in camera axes
//                         about the reference rotation R̂ (the final estimate, or a trial's truth)
//   CE CN CU      m       camera centre in site ENU (Xc = R·(Xw − C))
//   clock_offset  s       camera clock − GNSS time: frame stamp − true exposure time
//   Tx Ty Tz      m       translation (Xc = R·Xw + T), for methods that estimate T instead of C (Tsai)
//
// The canonical order is the enum's. The bundle's parameter layout is its first
// kBundleParameterCount entries (optim/bundle/bundle_parameters.hpp). A rotation perturbation turns
// the camera about its centre when the centre (or neither C nor T) is in a parameter set, and about
// the world origin when the translation is; one set never holds both C and T.
#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vision/camera/camera_model.hpp"

namespace rangecal {

// clang-format off
enum class CameraParameter : int {
  f, sx, u0, v0,               // intrinsics
  k1, k2, k3, p1, p2, a1, a2,  // distortion, Distortion::as_array() order
  wx, wy, wz,                  // rotation perturbation
  CE, CN, CU,                  // camera centre
  clock_offset,                // camera clock
  Tx, Ty, Tz,                  // translation
};
// clang-format on
inline constexpr int kCameraParameterCount = 21;
/// f … clock_offset: the parameters the bundle adjusts (centre form of the pose).
inline constexpr int kBundleParameterCount = 18;

/// Position of a parameter in the canonical order.
constexpr int index_of(CameraParameter p) {
  return static_cast<int>(p);
}
constexpr CameraParameter parameter_at(int index) {
  return static_cast<CameraParameter>(index);
}

struct CameraParameterInfo {
  CameraParameter parameter;
  const char* name;     ///< as in calibrate.free, calibration.json and montecarlo.csv
  const char* unit;     ///< "mm", "px", "mm^-2", "rad", "m", "s"; "" when dimensionless
  const char* meaning;  ///< a few words for tables
  /// Typical size of a change (in the unit): the conditioning scale of a search that works in
  /// z = (x − x0)/scale, so Levenberg–Marquardt's damping μI treats every parameter alike.
  double search_scale;
};

/// The table, in canonical order.
const std::array<CameraParameterInfo, kCameraParameterCount>& camera_parameter_table();
inline const CameraParameterInfo& parameter_info(CameraParameter p) {
  return camera_parameter_table()[static_cast<std::size_t>(index_of(p))];
}
inline const char* parameter_name(CameraParameter p) {
  return parameter_info(p).name;
}
inline const char* parameter_unit(CameraParameter p) {
  return parameter_info(p).unit;
}

/// The parameter called `name`, or nothing.
std::optional<CameraParameter> parameter_from_name(std::string_view name);
std::vector<std::string> parameter_names(const std::vector<CameraParameter>& parameters);

// Groups (COLMAP's *_idxs).
inline constexpr std::array<CameraParameter, 4> kIntrinsicParameters = {
    CameraParameter::f, CameraParameter::sx, CameraParameter::u0, CameraParameter::v0};
inline constexpr std::array<CameraParameter, 7> kDistortionParameters = {
    CameraParameter::k1, CameraParameter::k2, CameraParameter::k3, CameraParameter::p1,
    CameraParameter::p2, CameraParameter::a1, CameraParameter::a2};
inline constexpr std::array<CameraParameter, 3> kRotationParameters = {
    CameraParameter::wx, CameraParameter::wy, CameraParameter::wz};
inline constexpr std::array<CameraParameter, 3> kCenterParameters = {CameraParameter::CE, CameraParameter::CN,
                                                                     CameraParameter::CU};
inline constexpr std::array<CameraParameter, 3> kTranslationParameters = {
    CameraParameter::Tx, CameraParameter::Ty, CameraParameter::Tz};

inline bool is_distortion(CameraParameter p) {
  return index_of(p) >= index_of(CameraParameter::k1) && index_of(p) <= index_of(CameraParameter::a2);
}
inline bool is_rotation(CameraParameter p) {
  return index_of(p) >= index_of(CameraParameter::wx) && index_of(p) <= index_of(CameraParameter::wz);
}
inline bool is_center(CameraParameter p) {
  return index_of(p) >= index_of(CameraParameter::CE) && index_of(p) <= index_of(CameraParameter::CU);
}
inline bool is_translation(CameraParameter p) {
  return index_of(p) >= index_of(CameraParameter::Tx) && index_of(p) <= index_of(CameraParameter::Tz);
}

/// Expands a free-parameter list (calibrate.free): single names f … a2 and clock_offset, and the
/// groups "pose" (rotation + center), "rotation" (wx wy wz) and "center" (CE CN CU). The result is
/// in canonical order without repeats. Throws rangecal::Error (usage) for any other name, naming
/// `file` and `field` (the JSON path) and listing the accepted names.
std::vector<CameraParameter> expand_free_parameters(const std::vector<std::string>& free,
                                                    const std::string& file = "",
                                                    const std::string& field = "calibrate.free");
/// The bundle's default free set (docs/optimisation.md): f, k1, pose; u0, v0 stay at the image centre
/// (or their prior) and sx at 1. A mission's calibrate.free frees u0, v0 as well, under a prior
/// (docs/config.md "The principal point": a wrong fixed centre biases the intersection).
const std::vector<std::string>& default_free_parameters();

/// The names expand_free_parameters accepts, in canonical order, groups after the intrinsics and
/// distortion: f, sx, u0, v0, k1, k2, k3, p1, p2, a1, a2, pose, rotation, center, clock_offset.
const std::vector<std::string>& free_parameter_choices();
/// The same, comma separated (for messages and --help).
std::string free_parameter_names();
/// True when `parameters` holds p.
bool contains(const std::vector<CameraParameter>& parameters, CameraParameter p);

/// The value of parameter `p` of `cam`, in its unit. Rotations are the perturbation w with
/// cam.R = exp([w]×)·reference.R, i.e. the rotation vector of cam.R·reference.Rᵀ (exactly 0 for the
/// reference itself); clock_offset is `clock_offset_s` (a calibration result's, not the camera's).
double parameter_value(const Camera& cam, CameraParameter p, const Camera& reference,
                       double clock_offset_s = 0);

/// `base` with the parameters `parameters` set to the values `x` (same order): intrinsics and
/// distortion as given; R = exp([w]×)·base.R; then the pose: with any translation parameter in the
/// set, T = base.T with those components replaced (the rotation turns about the world origin),
/// otherwise C = base's centre with the centre components replaced and T = −R·C (the rotation
/// turns about the centre). A clock_offset entry goes to *clock_offset_s when that is non-null.
Camera camera_with_parameters(const Camera& base, const std::vector<CameraParameter>& parameters,
                              const Eigen::VectorXd& x, double* clock_offset_s = nullptr);

/// The values of `parameters` of `cam` (rotations 0: the perturbation about cam itself).
Eigen::VectorXd parameter_values(const Camera& cam, const std::vector<CameraParameter>& parameters,
                                 double clock_offset_s = 0);

/// Holds every intrinsic parameter that is not in `free` at its fixed value (docs/optimisation.md; with a
/// narrow field of view the principal point, rotation, f and Tz are nearly inseparable, so by
/// default they are not estimated): u0, v0 = `principal_point_px` (the prior, else the image
/// centre), sx = 1, distortion terms 0.
void hold_fixed_intrinsics(const std::vector<CameraParameter>& free,
                           const Eigen::Vector2d& principal_point_px, CameraIntrinsics* in);

/// The full range of each parameter for a camera (a change of this size moves the image by about
/// its own size): f; 1 for sx; the image width and height for u0, v0; r_max^−2, r_max^−4, r_max^−6
/// for k1 k2 k3 and r_max^−1 for p1 p2 (r_max the sensor half-diagonal, mm); 1 for a1 a2 and the
/// rotations (rad); the camera-to-scene distance for C and T (m); and for the clock offset the time
/// the fastest lamp point takes to cross that distance. Scales the normal matrix in rank tests, so a
/// column that holds only rounding noise is not rescued by Jacobi scaling.
double parameter_range(CameraParameter p, const CameraIntrinsics& in, double scene_distance_m,
                       double max_speed_mps);

}  // namespace rangecal
