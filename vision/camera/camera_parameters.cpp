#include "vision/camera/camera_parameters.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "config/error.hpp"
#include "config/json_view.hpp"

namespace rangecal {

using P = CameraParameter;

const std::array<CameraParameterInfo, kCameraParameterCount>& camera_parameter_table() {
  // search_scale: a change that moves the image by a fraction of a pixel to a few pixels for a
  // range camera (135 mm, 20 µm pixels, ~64 m); LM works in (x − x0)/scale (seed 000 §3).
  static const std::array<CameraParameterInfo, kCameraParameterCount> table = {{
      {P::f, "f", "mm", "focal length", 1.0},
      {P::sx, "sx", "", "scale factor", 1e-3},
      {P::u0, "u0", "px", "principal point u", 1.0},
      {P::v0, "v0", "px", "principal point v", 1.0},
      {P::k1, "k1", "mm^-2", "radial distortion r^2", 1e-5},
      {P::k2, "k2", "mm^-4", "radial distortion r^4", 1e-8},
      {P::k3, "k3", "mm^-6", "radial distortion r^6", 1e-11},
      {P::p1, "p1", "mm^-1", "decentring distortion", 1e-5},
      {P::p2, "p2", "mm^-1", "decentring distortion", 1e-5},
      {P::a1, "a1", "", "affine distortion", 1e-4},
      {P::a2, "a2", "", "affine distortion", 1e-4},
      {P::wx, "wx", "rad", "rotation about camera x", 1e-4},
      {P::wy, "wy", "rad", "rotation about camera y", 1e-4},
      {P::wz, "wz", "rad", "rotation about camera z", 1e-4},
      {P::CE, "CE", "m", "camera centre east", 0.1},
      {P::CN, "CN", "m", "camera centre north", 0.1},
      {P::CU, "CU", "m", "camera centre up", 0.1},
      {P::clock_offset, "clock_offset", "s", "camera clock - GNSS time", 1e-3},
      {P::Tx, "Tx", "m", "translation x", 0.1},
      {P::Ty, "Ty", "m", "translation y", 0.1},
      {P::Tz, "Tz", "m", "translation z", 0.1},
  }};
  return table;
}

std::optional<CameraParameter> parameter_from_name(std::string_view name) {
  for (const CameraParameterInfo& info : camera_parameter_table())
    if (name == info.name) return info.parameter;
  return std::nullopt;
}

std::vector<std::string> parameter_names(const std::vector<CameraParameter>& parameters) {
  std::vector<std::string> out;
  out.reserve(parameters.size());
  for (CameraParameter p : parameters) out.push_back(parameter_name(p));
  return out;
}

bool contains(const std::vector<CameraParameter>& parameters, CameraParameter p) {
  return std::find(parameters.begin(), parameters.end(), p) != parameters.end();
}

namespace {

// The groups a free list may name besides single parameters.
struct FreeGroup {
  const char* name;
  std::vector<CameraParameter> members;
};
const std::vector<FreeGroup>& free_groups() {
  static const std::vector<FreeGroup> groups = {
      {"pose", {P::wx, P::wy, P::wz, P::CE, P::CN, P::CU}},
      {"rotation", {P::wx, P::wy, P::wz}},
      {"center", {P::CE, P::CN, P::CU}},
  };
  return groups;
}

// Single names a free list accepts: the bundle's parameters except the rotation and centre
// components, which are free only as groups (a camera turned about one axis alone is no model).
bool free_as_single(CameraParameter p) {
  return index_of(p) < kBundleParameterCount && !is_rotation(p) && !is_center(p);
}

}  // namespace

const std::vector<std::string>& default_free_parameters() {
  static const std::vector<std::string> names = {parameter_name(P::f), parameter_name(P::k1),
                                                 free_groups().front().name};
  return names;
}

const std::vector<std::string>& free_parameter_choices() {
  static const std::vector<std::string> choices = [] {
    std::vector<std::string> v;
    for (const CameraParameterInfo& info : camera_parameter_table())
      if (free_as_single(info.parameter) && info.parameter != P::clock_offset) v.push_back(info.name);
    for (const FreeGroup& g : free_groups()) v.push_back(g.name);
    v.push_back(parameter_name(P::clock_offset));
    return v;
  }();
  return choices;
}

std::string free_parameter_names() {
  std::string s;
  for (const std::string& name : free_parameter_choices()) s += (s.empty() ? "" : ", ") + name;
  return s;
}

std::vector<CameraParameter> expand_free_parameters(const std::vector<std::string>& free,
                                                    const std::string& file, const std::string& field) {
  std::array<bool, kCameraParameterCount> on{};
  for (const std::string& name : free) {
    bool known = false;
    if (const auto p = parameter_from_name(name); p && free_as_single(*p)) on[index_of(*p)] = known = true;
    for (const FreeGroup& g : free_groups())
      if (name == g.name)
        for (CameraParameter m : g.members) on[index_of(m)] = known = true;
    if (!known)
      throw_config_error(file, field,
                         "unknown parameter '" + name + "'" + did_you_mean(name, free_parameter_choices()) +
                             " (expected " + free_parameter_names() + ")");
  }
  std::vector<CameraParameter> out;
  for (int i = 0; i < kCameraParameterCount; ++i)
    if (on[i]) out.push_back(parameter_at(i));
  return out;
}

double parameter_value(const Camera& cam, CameraParameter p, const Camera& reference, double clock_offset_s) {
  const CameraIntrinsics& in = cam.intr;
  if (is_distortion(p)) return in.dist.as_array()[index_of(p) - index_of(P::k1)];
  if (is_rotation(p)) {
    const Eigen::AngleAxisd aa(Eigen::Matrix3d(cam.pose.R * reference.pose.R.transpose()));
    if (aa.angle() < 1e-14) return 0.0;  // R·Rᵀ of the same camera: exactly 0, not rounding noise
    const Eigen::Vector3d w = aa.angle() * aa.axis();
    return w[index_of(p) - index_of(P::wx)];
  }
  if (is_center(p)) return cam.pose.center()[index_of(p) - index_of(P::CE)];
  if (is_translation(p)) return cam.pose.T[index_of(p) - index_of(P::Tx)];
  switch (p) {
    case P::f:
      return in.f_mm;
    case P::sx:
      return in.sx;
    case P::u0:
      return in.u0_px;
    case P::v0:
      return in.v0_px;
    case P::clock_offset:
      return clock_offset_s;
    default:
      return std::numeric_limits<double>::quiet_NaN();
  }
}

Eigen::VectorXd parameter_values(const Camera& cam, const std::vector<CameraParameter>& parameters,
                                 double clock_offset_s) {
  Eigen::VectorXd x(static_cast<Eigen::Index>(parameters.size()));
  for (std::size_t i = 0; i < parameters.size(); ++i)
    x[static_cast<Eigen::Index>(i)] =
        is_rotation(parameters[i]) ? 0.0 : parameter_value(cam, parameters[i], cam, clock_offset_s);
  return x;
}

Camera camera_with_parameters(const Camera& base, const std::vector<CameraParameter>& parameters,
                              const Eigen::VectorXd& x, double* clock_offset_s) {
  Camera c = base;
  double dist[7];
  const auto d0 = base.intr.dist.as_array();
  std::copy(d0.begin(), d0.end(), dist);
  Eigen::Vector3d w = Eigen::Vector3d::Zero(), C = base.pose.center(), T = base.pose.T;
  bool translation_form = false;
  for (std::size_t i = 0; i < parameters.size(); ++i) {
    const CameraParameter p = parameters[i];
    const double v = x[static_cast<Eigen::Index>(i)];
    if (is_distortion(p))
      dist[index_of(p) - index_of(P::k1)] = v;
    else if (is_rotation(p))
      w[index_of(p) - index_of(P::wx)] = v;
    else if (is_center(p))
      C[index_of(p) - index_of(P::CE)] = v;
    else if (is_translation(p))
      T[index_of(p) - index_of(P::Tx)] = v, translation_form = true;
    else if (p == P::f)
      c.intr.f_mm = v;
    else if (p == P::sx)
      c.intr.sx = v;
    else if (p == P::u0)
      c.intr.u0_px = v;
    else if (p == P::v0)
      c.intr.v0_px = v;
    else if (p == P::clock_offset && clock_offset_s)
      *clock_offset_s = v;
  }
  c.intr.dist = Distortion::from_array(dist);
  const double a = w.norm();
  if (a > 0) c.pose.R = Eigen::AngleAxisd(a, w / a).toRotationMatrix() * base.pose.R;
  c.pose.T = translation_form ? T : Eigen::Vector3d(-c.pose.R * C);
  return c;
}

void hold_fixed_intrinsics(const std::vector<CameraParameter>& free,
                           const Eigen::Vector2d& principal_point_px, CameraIntrinsics* in) {
  if (!contains(free, P::u0)) in->u0_px = principal_point_px.x();
  if (!contains(free, P::v0)) in->v0_px = principal_point_px.y();
  if (!contains(free, P::sx)) in->sx = 1.0;
  double d[7];
  const auto d0 = in->dist.as_array();
  for (std::size_t k = 0; k < 7; ++k) d[k] = contains(free, kDistortionParameters[k]) ? d0[k] : 0.0;
  in->dist = Distortion::from_array(d);
}

double parameter_range(CameraParameter p, const CameraIntrinsics& in, double scene_distance_m,
                       double max_speed_mps) {
  const double rmax = 0.5 * std::hypot(in.width_px * in.dx_mm, in.height_px * in.dy_mm);
  switch (p) {
    case P::f:
      return in.f_mm;
    case P::u0:
      return static_cast<double>(std::max(in.width_px, 1));
    case P::v0:
      return static_cast<double>(std::max(in.height_px, 1));
    case P::k1:
      return std::pow(rmax, -2);
    case P::k2:
      return std::pow(rmax, -4);
    case P::k3:
      return std::pow(rmax, -6);
    case P::p1:
    case P::p2:
      return 1 / rmax;
    case P::clock_offset:
      return scene_distance_m / std::max(max_speed_mps, 1e-3);
    default:
      return is_center(p) || is_translation(p) ? scene_distance_m : 1.0;
  }
}

}  // namespace rangecal
