#include "pipeline/io/calibration_json.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "config/atomic_file.hpp"
#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/json_format.hpp"
#include "config/json_view.hpp"
#include "config/number_format.hpp"
#include "config/physical_ranges.hpp"
#include "vision/camera/distortion_validity.hpp"

namespace rangecal {
namespace {

using ojson = nlohmann::ordered_json;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr const char* kFormat = "rangecal.calibration/1";
// The world frame's description (docs/outputs.md "world_frame"): the local ENU frame of
// gnss/geodesy/local_enu.hpp, GeographicLib::LocalCartesian about the site origin.
constexpr const char* kFrameKind = "local_enu";
constexpr const char* kEllipsoid = "WGS84";
constexpr const char* kFrameAxes =
    "x east, y north, z up along the ellipsoid normal at the origin, metres; the tangent frame at "
    "the origin (GeographicLib LocalCartesian)";

const std::array<const char*, 7>& kDistKeys = distortion_json_keys();

// NaN → null (nlohmann would print null anyway; being explicit keeps the intent visible).
ojson num(double x) {
  return std::isfinite(x) ? ojson(x) : ojson(nullptr);
}

ojson vec(const double* x, int n) {
  ojson a = ojson::array();
  for (int i = 0; i < n; ++i) a.push_back(num(x[i]));
  return a;
}

ojson matrix(const Eigen::MatrixXd& m) {
  ojson a = ojson::array();
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    ojson row = ojson::array();
    for (Eigen::Index c = 0; c < m.cols(); ++c) row.push_back(num(m(r, c)));
    a.push_back(row);
  }
  return a;
}

bool only_k1(const Distortion& d) {
  return d.k2 == 0 && d.k3 == 0 && d.p1 == 0 && d.p2 == 0 && d.a1 == 0 && d.a2 == 0;
}

}  // namespace

const std::array<const char*, 7>& distortion_json_keys() {
  // The affine terms are dimensionless: their keys are their names.
  static const std::array<const char*, 7> keys = {"k1_per_mm2",
                                                  "k2_per_mm4",
                                                  "k3_per_mm6",
                                                  "p1_per_mm",
                                                  "p2_per_mm",
                                                  parameter_name(CameraParameter::a1),
                                                  parameter_name(CameraParameter::a2)};
  return keys;
}

ojson calibration_to_json(const CalibrationResult& r) {
  const CameraIntrinsics& in = r.camera.intr;
  const CameraPose& pose = r.camera.pose;
  ojson j;
  j["format"] = kFormat;
  j["camera"] = r.camera_id;
  j["method"] = r.method;
  if (r.site_origin) {
    ojson w;
    w["kind"] = kFrameKind;
    w["ellipsoid"] = kEllipsoid;
    w["origin_lat_deg"] = r.site_origin->lat_deg;
    w["origin_lon_deg"] = r.site_origin->lon_deg;
    w["origin_h_m"] = r.site_origin->h_m;
    w["axes"] = kFrameAxes;
    j["world_frame"] = w;
  }
  j["image_size_px"] = {in.width_px, in.height_px};
  j["pixel_size_um"] = {num(in.dx_mm * 1000.0), num(in.dy_mm * 1000.0)};
  // The exact pitch the model uses (µm → mm is not exact in binary floating point).
  j["pixel_pitch_mm"] = {num(in.dx_mm), num(in.dy_mm)};
  j["focal_mm"] = num(in.f_mm);
  j[parameter_name(CameraParameter::sx)] = num(in.sx);
  j["principal_point_px"] = {num(in.u0_px), num(in.v0_px)};
  ojson d;
  d["model"] = only_k1(in.dist) ? "tsai_k1" : "seed000_eq7";
  d["direction"] = "distorted_to_undistorted_sensor_mm";
  const auto da = in.dist.as_array();
  for (int i = 0; i < 7; ++i) d[kDistKeys[i]] = num(da[i]);
  j["distortion"] = d;
  j["rotation_world_to_camera"] = matrix(pose.R);
  j["translation_m"] = vec(pose.T.data(), 3);
  const Eigen::Vector3d C = pose.center();
  j["center_enu_m"] = vec(C.data(), 3);
  j["clock_offset_s"] = num(r.clock_offset_s);

  ojson s;
  using P = CameraParameter;
  s["focal_mm"] = num(r.sigma(P::f));
  s["principal_point_px"] = {num(r.sigma(P::u0)), num(r.sigma(P::v0))};
  s[parameter_name(P::sx)] = num(r.sigma(P::sx));
  for (int i = 0; i < 7; ++i) s[kDistKeys[i]] = num(r.sigma(kDistortionParameters[i]));
  s["rotation_rad"] = {num(r.sigma(P::wx)), num(r.sigma(P::wy)), num(r.sigma(P::wz))};
  s["translation_m"] = {num(r.sigma(P::Tx)), num(r.sigma(P::Ty)), num(r.sigma(P::Tz))};
  const Eigen::Vector3d cs = r.center_sigma_m();
  s["center_enu_m"] = vec(cs.data(), 3);
  s["clock_offset_s"] = num(r.sigma(P::clock_offset));
  j["sigma"] = s;

  ojson cov;
  cov["parameters"] = parameter_names(r.parameters);
  cov["matrix"] = matrix(r.covariance);
  cov["center_enu_m2"] = r.center_covariance_m2.allFinite() ? matrix(r.center_covariance_m2) : ojson(nullptr);
  j["covariance"] = cov;

  ojson rp;
  rp["rms_px"] = num(r.reprojection.rms_px);
  rp["mean_px"] = num(r.reprojection.mean_px);
  rp["max_px"] = num(r.reprojection.max_px);
  rp["n_used"] = r.reprojection.n_used;
  rp["n_rejected"] = r.reprojection.n_rejected;
  j["reprojection"] = rp;
  j["rejected"] = r.rejected;
  j["warnings"] = r.warnings;
  j["details"] = ojson::parse(r.details.dump());  // keeps nlohmann::json's (sorted) key order
  return j;
}

std::string calibration_to_json_text(const CalibrationResult& r) {
  return dump_json_compact_arrays(calibration_to_json(r));
}

namespace {

// --- calibration.json's schema (docs/outputs.md) ---------------------------------------------------
// Each value once: its key, whether it is required, the form it must have (the text completing
// "expected …" in every message about it) and, for numbers, the range it must lie in. The limits
// that are physical come from config/physical_ranges.hpp, so this reader refuses what every other
// format refuses.

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Largest |camera clock − GNSS time| (s) a calibration may carry.
constexpr double kMaxClockOffsetS = 10;

enum class Range {
  any,       ///< any finite number
  positive,  ///< x > 0
  closed,    ///< lo ≤ x ≤ hi
};

struct Field {
  const char* key;
  bool required;
  std::string expected;
  Range range = Range::any;
  double lo = -kInf;
  double hi = kInf;

  bool accepts(double x) const {
    switch (range) {
      case Range::any:
        return true;
      case Range::positive:
        return x > 0;
      case Range::closed:
        return x >= lo && x <= hi;
    }
    return false;
  }
};

std::string g(double x) {
  return format_number("%.10g", x);
}
std::string interval(double lo, double hi) {
  return "[" + g(lo) + ", " + g(hi) + "]";
}

using Schema = std::vector<Field>;

struct CalibrationSchema {
  Schema root, world_frame, distortion, covariance, reprojection;
};

const CalibrationSchema& schema() {
  static const CalibrationSchema s = [] {
    CalibrationSchema c;
    const std::string three_m = "an array of 3 numbers (m)";
    c.root = {
        {"format", false, std::string("\"") + kFormat + "\""},
        {"camera", true, "the camera id (a string)"},
        {"method", true, "the method name (a string)"},
        {"world_frame", false,
         "an object {\"kind\": \"local_enu\", \"ellipsoid\": \"WGS84\", \"origin_lat_deg\", "
         "\"origin_lon_deg\", \"origin_h_m\", \"axes\"}"},
        {"image_size_px", true,
         "an array of 2 positive integers [width, height] in pixels, each ≤ " + g(ranges::kMaxImageSidePx),
         Range::closed, 1, ranges::kMaxImageSidePx},
        {"pixel_size_um", true, "an array of 2 positive numbers (µm)", Range::positive},
        {"pixel_pitch_mm", false, "an array of 2 positive numbers (mm) agreeing with pixel_size_um",
         Range::positive},
        {"focal_mm", true, "a positive focal length (mm)", Range::positive},
        {parameter_name(CameraParameter::sx), true, "a positive scale factor", Range::positive},
        {"principal_point_px", true, "an array of 2 numbers [u0, v0] (px)"},
        {"distortion", true, "an object {\"model\", \"k1_per_mm2\", ...}"},
        {"rotation_world_to_camera", true,
         "a 3x3 rotation matrix (array of 3 rows of 3 numbers), world ENU → camera"},
        {"translation_m", true, three_m},
        {"center_enu_m", false, three_m},
        {"clock_offset_s", false,
         "a number of seconds, |x| ≤ " + g(kMaxClockOffsetS) + " (camera clock − GNSS time)", Range::closed,
         -kMaxClockOffsetS, kMaxClockOffsetS},
        {"sigma", false, "an object of 1σ values"},
        {"covariance", false, "an object {\"parameters\", \"matrix\", \"center_enu_m2\"}"},
        {"reprojection", false,
         "an object {\"rms_px\", \"mean_px\", \"max_px\", \"n_used\", \"n_rejected\"}"},
        {"rejected", false, "an array of observation indices"},
        {"warnings", false, "an array of strings"},
        {"details", false, "an object"},
    };
    c.world_frame = {
        {"kind", true, std::string("\"") + kFrameKind + "\""},
        {"ellipsoid", true, std::string("\"") + kEllipsoid + "\""},
        {"origin_lat_deg", true, "a WGS84 latitude in degrees, " + interval(-90, 90), Range::closed, -90, 90},
        {"origin_lon_deg", true, "a WGS84 longitude in degrees, " + interval(-180, 180), Range::closed, -180,
         180},
        {"origin_h_m", true,
         "an ellipsoidal height in metres, " + interval(ranges::kMinHeightM, ranges::kMaxHeightM),
         Range::closed, ranges::kMinHeightM, ranges::kMaxHeightM},
        {"axes", false, "a description of the axes (text)"},
    };
    c.distortion = {{"model", true, "\"tsai_k1\" or \"seed000_eq7\""},
                    {"direction", false, "\"distorted_to_undistorted_sensor_mm\""}};
    for (int i = 0; i < 7; ++i)
      c.distortion.push_back({kDistKeys[i], i == 0, i == 0 ? "a number (mm⁻²)" : "a number"});
    c.covariance = {{"parameters", true, "an array of parameter names"},
                    {"matrix", true, ""},  // its form names the parameter count, see read_covariance
                    {"center_enu_m2", false, "a 3x3 covariance matrix (m²) or null"}};
    c.reprojection = {
        {"rms_px", false, "a number of pixels or null"},
        {"mean_px", false, "a number of pixels or null"},
        {"max_px", false, "a number of pixels or null"},
        {"n_used", false, "a non-negative count", Range::closed, 0, std::numeric_limits<int>::max()},
        {"n_rejected", false, "a non-negative count", Range::closed, 0, std::numeric_limits<int>::max()},
    };
    return c;
  }();
  return s;
}

const Field& field(const Schema& schema, std::string_view key) {
  for (const Field& f : schema)
    if (key == f.key) return f;
  throw std::logic_error("calibration.json schema has no key " + std::string(key));
}

/// `obj` must be `what`, an object whose keys are all in `schema`.
void check_object(const JsonView& obj, const std::string& what, const Schema& schema) {
  obj.require_object(what);
  std::vector<std::string> keys;
  for (const Field& f : schema) keys.push_back(f.key);
  obj.check_keys(keys);
}

/// The member `f` of `obj`: nullopt when absent and optional; missing and required → error.
std::optional<JsonView> member(const JsonView& obj, const Field& f) {
  if (f.required) return obj.at(f.key, f.expected);
  return obj.find(f.key);
}

double checked(const JsonView& v, const Field& f, double x) {
  if (!f.accepts(x)) v.fail_expected(f.expected);
  return x;
}

double number(const JsonView& v, const Field& f) {
  return checked(v, f, v.number(f.expected));
}

std::vector<double> numbers(const JsonView& v, const Field& f, std::size_t n) {
  std::vector<double> x = v.numbers(n, f.expected);
  for (double xi : x) checked(v, f, xi);
  return x;
}

std::int64_t integer(const JsonView& v, const Field& f, const JsonView& blame) {
  const std::int64_t n = v.integer(f.expected);
  checked(blame, f, static_cast<double>(n));
  return n;
}

/// A string that must be exactly `value`.
void fixed_string(const JsonView& obj, const Field& f, const char* value) {
  if (auto v = member(obj, f))
    if (v->string(f.expected) != value) v->fail_expected(f.expected);
}

GeodeticOrigin read_world_frame(const JsonView& wf) {
  const Schema& s = schema().world_frame;
  check_object(wf, field(schema().root, "world_frame").expected, s);
  fixed_string(wf, field(s, "kind"), kFrameKind);
  fixed_string(wf, field(s, "ellipsoid"), kEllipsoid);
  GeodeticOrigin o;
  for (auto [key, out] : {std::pair{"origin_lat_deg", &o.lat_deg}, std::pair{"origin_lon_deg", &o.lon_deg},
                          std::pair{"origin_h_m", &o.h_m}}) {
    const Field& f = field(s, key);
    *out = number(*member(wf, f), f);
  }
  const Field& axes = field(s, "axes");
  if (auto ax = member(wf, axes)) ax->string(axes.expected);
  return o;
}

void read_sensor(const JsonView& root, CameraIntrinsics* in) {
  const Schema& s = schema().root;
  const Field& size = field(s, "image_size_px");
  const JsonView sz = *member(root, size);
  sz.require_array(size.expected, 2, 2);
  for (int i = 0; i < 2; ++i)
    (i == 0 ? in->width_px : in->height_px) = static_cast<int>(integer(sz.element(i), size, sz));
  const Field& um_f = field(s, "pixel_size_um");
  const auto um = numbers(*member(root, um_f), um_f, 2);
  in->dx_mm = um[0] / 1000.0;
  in->dy_mm = um[1] / 1000.0;
  const Field& mm_f = field(s, "pixel_pitch_mm");
  if (auto pm = member(root, mm_f)) {
    const auto mm = numbers(*pm, mm_f, 2);
    for (int i = 0; i < 2; ++i)
      if (std::abs(mm[i] * 1000.0 - um[i]) > 1e-9 * um[i]) pm->fail_expected(mm_f.expected);
    in->dx_mm = mm[0];
    in->dy_mm = mm[1];
  }
  const Field& focal = field(s, "focal_mm");
  in->f_mm = number(*member(root, focal), focal);
  const Field& sx = field(s, parameter_name(CameraParameter::sx));
  in->sx = number(*member(root, sx), sx);
  const Field& pp_f = field(s, "principal_point_px");
  const auto pp = numbers(*member(root, pp_f), pp_f, 2);
  in->u0_px = pp[0];
  in->v0_px = pp[1];
}

Distortion read_distortion(const JsonView& root) {
  const Schema& s = schema().distortion;
  const JsonView dv = *member(root, field(schema().root, "distortion"));
  check_object(dv, field(schema().root, "distortion").expected, s);
  const Field& model_f = field(s, "model");
  const JsonView model_v = *member(dv, model_f);
  const std::string model = model_v.string(model_f.expected);
  if (model != "tsai_k1" && model != "seed000_eq7")
    model_v.fail("unknown distortion model '" + model + "'" +
                 did_you_mean(model, {"tsai_k1", "seed000_eq7"}) + "; expected " + model_f.expected);
  fixed_string(dv, field(s, "direction"), "distorted_to_undistorted_sensor_mm");
  double da[7] = {0, 0, 0, 0, 0, 0, 0};
  for (int i = 0; i < 7; ++i) {
    const Field& f = field(s, kDistKeys[i]);
    if (auto v = member(dv, f)) da[i] = number(*v, f);
  }
  const Distortion d = Distortion::from_array(da);
  if (model == "tsai_k1" && !only_k1(d))
    dv.fail("model \"tsai_k1\" has only k1; use model \"seed000_eq7\" for k2, k3, p1, p2, a1, a2");
  return d;
}

/// A distortion no lens can have over this image (vision/camera/distortion_validity.hpp) is refused
/// naming the coefficient that dominates where it fails.
void check_distortion(const JsonView& root, const CameraIntrinsics& in) {
  DistortionFault fault;
  if (distortion_is_physical(in, &fault)) return;
  const JsonView dv = *member(root, field(schema().root, "distortion"));
  const Field& f = field(schema().distortion, kDistKeys[fault.coefficient]);
  const std::string reason = fault.reason + "; a calibration must be invertible over its image";
  if (auto v = member(dv, f)) v->fail(reason);
  dv.fail(reason);
}

void read_pose(const JsonView& root, CameraPose* pose) {
  const Schema& s = schema().root;
  const Field& rf = field(s, "rotation_world_to_camera");
  const JsonView rv = *member(root, rf);
  rv.require_array(rf.expected, 3, 3);
  for (int i = 0; i < 3; ++i) {
    const auto row = numbers(rv.element(i), rf, 3);
    for (int k = 0; k < 3; ++k) pose->R(i, k) = row[k];
  }
  const Eigen::Matrix3d& R = pose->R;
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9 || R.determinant() < 0)
    rv.fail("not a rotation matrix (RᵀR ≠ I within 1e-9 or det < 0); expected " + rf.expected);
  const Field& tf = field(s, "translation_m");
  const auto t = numbers(*member(root, tf), tf, 3);
  pose->T = Eigen::Vector3d(t[0], t[1], t[2]);
  const Field& cf = field(s, "center_enu_m");
  if (auto cv = member(root, cf)) {
    const auto c = numbers(*cv, cf, 3);
    const Eigen::Vector3d C(c[0], c[1], c[2]);
    const double tol = 1e-6 * std::max(1.0, pose->T.norm());
    if ((C - pose->center()).norm() > tol)
      cv->fail("inconsistent with rotation_world_to_camera and translation_m (C = −Rᵀ·T differs by " +
               std::to_string((C - pose->center()).norm()) + " m)");
  }
}

std::vector<CameraParameter> read_parameter_names(const JsonView& pv, const Field& f) {
  const std::size_t n = pv.require_array(f.expected);
  std::vector<std::string> choices;
  for (const CameraParameterInfo& info : camera_parameter_table()) choices.push_back(info.name);
  std::vector<CameraParameter> params;
  for (std::size_t i = 0; i < n; ++i) {
    const JsonView e = pv.element(i);
    const std::string name = e.nonempty_string("a parameter name");
    const auto p = parameter_from_name(name);
    if (!p) e.fail("unknown parameter '" + name + "'" + did_you_mean(name, choices));
    if (contains(params, *p)) e.fail("parameter '" + name + "' is listed twice");
    params.push_back(*p);
  }
  const bool has_t = std::any_of(params.begin(), params.end(), is_translation);
  const bool has_c = std::any_of(params.begin(), params.end(), is_center);
  if (has_t && has_c)
    pv.fail("mixes translation (Tx Ty Tz) and centre (CE CN CU) parameters; use one pose form");
  return params;
}

void read_covariance(const JsonView& cv, CalibrationResult* r) {
  const Schema& s = schema().covariance;
  check_object(cv, field(schema().root, "covariance").expected, s);
  const Field& pf = field(s, "parameters");
  r->parameters = read_parameter_names(*member(cv, pf), pf);
  const std::size_t n = r->parameters.size();
  Field mf = field(s, "matrix");
  mf.expected = "a symmetric " + std::to_string(n) + "x" + std::to_string(n) +
                " matrix (one row per parameter), or [] when not computed";
  const JsonView mv = *member(cv, mf);
  const std::size_t rows = mv.require_array(mf.expected);
  if (rows != 0 && rows != n) mv.fail_expected(mf.expected);
  Eigen::MatrixXd& P = r->covariance;
  P.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(rows));
  for (std::size_t i = 0; i < rows; ++i) {
    const auto row = numbers(mv.element(i), mf, n);
    for (std::size_t k = 0; k < n; ++k) P(Eigen::Index(i), Eigen::Index(k)) = row[k];
  }
  for (std::size_t i = 0; i < rows; ++i) {
    if (!(P(Eigen::Index(i), Eigen::Index(i)) >= 0))
      mv.fail("negative variance of '" + std::string(parameter_name(r->parameters[i])) + "'; expected " +
              mf.expected);
    for (std::size_t k = 0; k < i; ++k)
      if (P(Eigen::Index(i), Eigen::Index(k)) != P(Eigen::Index(k), Eigen::Index(i)))
        mv.fail("not symmetric; expected " + mf.expected);
  }
  const Field& cf = field(s, "center_enu_m2");
  if (auto cc = member(cv, cf); cc && !cc->json().is_null()) {
    cc->require_array(cf.expected, 3, 3);
    for (int i = 0; i < 3; ++i) {
      const auto row = numbers(cc->element(i), cf, 3);
      for (int k = 0; k < 3; ++k) r->center_covariance_m2(i, k) = row[k];
    }
  }
}

ReprojectionStats read_reprojection(const JsonView& rp) {
  const Schema& s = schema().reprojection;
  check_object(rp, field(schema().root, "reprojection").expected, s);
  ReprojectionStats st;
  for (auto [key, out] : {std::pair{"rms_px", &st.rms_px}, std::pair{"mean_px", &st.mean_px},
                          std::pair{"max_px", &st.max_px}}) {
    const Field& f = field(s, key);
    if (auto v = member(rp, f)) *out = v->json().is_null() ? kNaN : number(*v, f);
  }
  for (auto [key, out] : {std::pair{"n_used", &st.n_used}, std::pair{"n_rejected", &st.n_rejected}}) {
    const Field& f = field(s, key);
    if (auto v = member(rp, f)) *out = static_cast<int>(integer(*v, f, *v));
  }
  return st;
}

}  // namespace

CalibrationResult calibration_from_json_text(const std::string& text, const std::string& file) {
  const nlohmann::json doc = parse_json_text(text, file, ErrorKind::input);
  const JsonView root(doc, file, "", ErrorKind::input);
  const Schema& s = schema().root;
  check_object(root, "a calibration.json object", s);
  CalibrationResult r;
  const Field& format = field(s, "format");
  if (auto f = member(root, format)) {
    const std::string fmt = f->string(format.expected);
    if (fmt != kFormat) f->fail("unsupported format '" + fmt + "'; expected " + format.expected);
  }
  for (auto [key, out] : {std::pair{"camera", &r.camera_id}, std::pair{"method", &r.method}}) {
    const Field& f = field(s, key);
    *out = member(root, f)->nonempty_string(f.expected);
  }
  r.camera.id = r.camera_id;
  // Files written before the world frame was recorded have none: they still read, but their
  // poses cannot be placed on the Earth (rangecal project/intersect --geodetic say so).
  if (auto wf = member(root, field(s, "world_frame"))) r.site_origin = read_world_frame(*wf);
  read_sensor(root, &r.camera.intr);
  r.camera.intr.dist = read_distortion(root);
  check_distortion(root, r.camera.intr);
  read_pose(root, &r.camera.pose);
  const Field& clock = field(s, "clock_offset_s");
  if (auto co = member(root, clock)) r.clock_offset_s = number(*co, clock);
  // σ are derived from the covariance; only their form is checked here.
  const Field& sigma = field(s, "sigma");
  if (auto sv = member(root, sigma)) sv->require_object(sigma.expected);
  if (auto cv = member(root, field(s, "covariance"))) read_covariance(*cv, &r);
  if (auto rp = member(root, field(s, "reprojection"))) r.reprojection = read_reprojection(*rp);
  const Field& rejected = field(s, "rejected");
  if (auto rj = member(root, rejected)) {
    const std::size_t n = rj->require_array(rejected.expected);
    for (std::size_t i = 0; i < n; ++i)
      r.rejected.push_back(static_cast<std::size_t>(rj->element(i).unsigned_integer("a non-negative index")));
  }
  const Field& warnings = field(s, "warnings");
  if (auto w = member(root, warnings)) {
    const std::size_t n = w->require_array(warnings.expected);
    for (std::size_t i = 0; i < n; ++i) r.warnings.push_back(w->element(i).string("a string"));
  }
  const Field& details = field(s, "details");
  if (auto d = member(root, details)) {
    d->require_object(details.expected);
    r.details = d->json();
  }
  return r;
}

void write_calibration_json(const std::string& path, const CalibrationResult& r) {
  write_file_atomic(path, calibration_to_json_text(r));
}

CalibrationResult read_calibration_json(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw_input_error(path, 0, "",
                      "calibration file not found (expected a calibration.json written by rangecal)");
  return calibration_from_json_text(read_file_text(path), path);
}

const GeodeticOrigin& require_site_origin(const CalibrationResult& r, const std::string& path) {
  if (!r.site_origin)
    throw_input_error(path, 0, "world_frame",
                      "has no world_frame (the site origin of its ENU frame; files written by older rangecal "
                      "versions lack it), so geodetic coordinates are unavailable: give E,N,U coordinates "
                      "without --geodetic, or rerun the calibrate stage");
  return *r.site_origin;
}

}  // namespace rangecal
