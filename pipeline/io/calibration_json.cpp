#include "pipeline/io/calibration_json.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "config/atomic_file.hpp"
#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/json_format.hpp"
#include "config/json_view.hpp"
#include "config/physical_ranges.hpp"

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

// A number or null (→ NaN).
double number_or_null(const JsonView& v, const std::string& expected) {
  if (v.json().is_null()) return kNaN;
  return v.number(expected);
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

CalibrationResult calibration_from_json_text(const std::string& text, const std::string& file) {
  const nlohmann::json doc = parse_json_text(text, file, ErrorKind::input);
  const JsonView root(doc, file, "", ErrorKind::input);
  root.require_object("a calibration.json object");
  root.check_keys({"format",
                   "camera",
                   "method",
                   "world_frame",
                   "image_size_px",
                   "pixel_size_um",
                   "pixel_pitch_mm",
                   "focal_mm",
                   parameter_name(CameraParameter::sx),
                   "principal_point_px",
                   "distortion",
                   "rotation_world_to_camera",
                   "translation_m",
                   "center_enu_m",
                   "clock_offset_s",
                   "sigma",
                   "covariance",
                   "reprojection",
                   "rejected",
                   "warnings",
                   "details"});
  CalibrationResult r;
  if (auto f = root.find("format")) {
    const std::string fmt = f->string(std::string("\"") + kFormat + "\"");
    if (fmt != kFormat) f->fail("unsupported format '" + fmt + "'; expected \"" + kFormat + "\"");
  }
  r.camera_id = root.at("camera", "the camera id (a string)").nonempty_string("the camera id (a string)");
  r.method = root.at("method", "the method name (a string)").nonempty_string("the method name (a string)");
  r.camera.id = r.camera_id;
  // Files written before the world frame was recorded have none: they still read, but their
  // poses cannot be placed on the Earth (rangecal project/intersect --geodetic say so).
  if (auto wf = root.find("world_frame")) {
    const std::string form =
        "an object {\"kind\": \"local_enu\", \"ellipsoid\": \"WGS84\", \"origin_lat_deg\", "
        "\"origin_lon_deg\", \"origin_h_m\", \"axes\"}";
    wf->require_object(form);
    wf->check_keys({"kind", "ellipsoid", "origin_lat_deg", "origin_lon_deg", "origin_h_m", "axes"});
    const JsonView kind = wf->at("kind", "\"local_enu\"");
    if (kind.string("\"local_enu\"") != kFrameKind) kind.fail_expected("\"local_enu\"");
    const JsonView ell = wf->at("ellipsoid", "\"WGS84\"");
    if (ell.string("\"WGS84\"") != kEllipsoid) ell.fail_expected("\"WGS84\"");
    GeodeticOrigin o;
    const auto number_in = [&](const char* key, double lo, double hi, const std::string& what) {
      const JsonView v = wf->at(key, what);
      const double x = v.number(what);
      if (!(x >= lo && x <= hi)) v.fail_expected(what);
      return x;
    };
    o.lat_deg = number_in("origin_lat_deg", -90, 90, "a WGS84 latitude in degrees, [-90, 90]");
    o.lon_deg = number_in("origin_lon_deg", -180, 180, "a WGS84 longitude in degrees, [-180, 180]");
    o.h_m = number_in("origin_h_m", ranges::kMinHeightM, ranges::kMaxHeightM,
                      "an ellipsoidal height in metres, [-1000, 20000]");
    if (auto ax = wf->find("axes")) ax->string("a description of the axes (text)");
    r.site_origin = o;
  }
  CameraIntrinsics& in = r.camera.intr;

  const std::string size_form = "an array of 2 positive integers [width, height] in pixels";
  const JsonView sz = root.at("image_size_px", size_form);
  sz.require_array(size_form, 2, 2);
  for (int i = 0; i < 2; ++i) {
    const std::int64_t n = sz.element(i).integer(size_form);
    if (n < 1 || n > 100000) sz.fail_expected(size_form);
    (i == 0 ? in.width_px : in.height_px) = static_cast<int>(n);
  }
  const std::string pix_form = "an array of 2 positive numbers (µm)";
  const JsonView pu = root.at("pixel_size_um", pix_form);
  const auto um = pu.numbers(2, pix_form);
  if (!(um[0] > 0 && um[1] > 0)) pu.fail_expected(pix_form);
  in.dx_mm = um[0] / 1000.0;
  in.dy_mm = um[1] / 1000.0;
  if (auto pm = root.find("pixel_pitch_mm")) {
    const std::string form = "an array of 2 positive numbers (mm) agreeing with pixel_size_um";
    const auto mm = pm->numbers(2, form);
    for (int i = 0; i < 2; ++i)
      if (!(mm[i] > 0) || std::abs(mm[i] * 1000.0 - um[i]) > 1e-9 * um[i]) pm->fail_expected(form);
    in.dx_mm = mm[0];
    in.dy_mm = mm[1];
  }
  const JsonView fv = root.at("focal_mm", "a positive focal length (mm)");
  in.f_mm = fv.number("a positive focal length (mm)");
  if (!(in.f_mm > 0)) fv.fail_expected("a positive focal length (mm)");
  const JsonView sxv = root.at(parameter_name(CameraParameter::sx), "a positive scale factor");
  in.sx = sxv.number("a positive scale factor");
  if (!(in.sx > 0)) sxv.fail_expected("a positive scale factor");
  const auto pp = root.at("principal_point_px", "an array of 2 numbers [u0, v0] (px)")
                      .numbers(2, "an array of 2 numbers [u0, v0] (px)");
  in.u0_px = pp[0];
  in.v0_px = pp[1];

  const JsonView dv = root.at("distortion", "an object {\"model\", \"k1_per_mm2\", ...}");
  dv.require_object("an object {\"model\", \"k1_per_mm2\", ...}");
  std::vector<std::string> dkeys = {"model", "direction"};
  for (const char* k : kDistKeys) dkeys.push_back(k);
  dv.check_keys(dkeys);
  const JsonView model_v = dv.at("model", "\"tsai_k1\" or \"seed000_eq7\"");
  const std::string model = model_v.string("\"tsai_k1\" or \"seed000_eq7\"");
  if (model != "tsai_k1" && model != "seed000_eq7")
    model_v.fail("unknown distortion model '" + model + "'" +
                 did_you_mean(model, {"tsai_k1", "seed000_eq7"}) +
                 "; expected \"tsai_k1\" or \"seed000_eq7\"");
  if (auto dir = dv.find("direction")) {
    const std::string s = dir->string("\"distorted_to_undistorted_sensor_mm\"");
    if (s != "distorted_to_undistorted_sensor_mm")
      dir->fail_expected("\"distorted_to_undistorted_sensor_mm\"");
  }
  double da[7] = {0, 0, 0, 0, 0, 0, 0};
  for (int i = 0; i < 7; ++i) {
    if (auto v = dv.find(kDistKeys[i]))
      da[i] = v->number("a number");
    else if (i == 0)
      dv.at(kDistKeys[0], "a number (mm⁻²)");
  }
  in.dist = Distortion::from_array(da);
  if (model == "tsai_k1" && !only_k1(in.dist))
    dv.fail("model \"tsai_k1\" has only k1; use model \"seed000_eq7\" for k2, k3, p1, p2, a1, a2");

  const std::string rform = "a 3x3 rotation matrix (array of 3 rows of 3 numbers), world ENU → camera";
  const JsonView rv = root.at("rotation_world_to_camera", rform);
  rv.require_array(rform, 3, 3);
  for (int i = 0; i < 3; ++i) {
    const auto row = rv.element(i).numbers(3, rform);
    for (int k = 0; k < 3; ++k) r.camera.pose.R(i, k) = row[k];
  }
  const Eigen::Matrix3d& R = r.camera.pose.R;
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9 || R.determinant() < 0)
    rv.fail("not a rotation matrix (RᵀR ≠ I within 1e-9 or det < 0); expected " + rform);
  const auto t =
      root.at("translation_m", "an array of 3 numbers (m)").numbers(3, "an array of 3 numbers (m)");
  r.camera.pose.T = Eigen::Vector3d(t[0], t[1], t[2]);
  if (auto cv = root.find("center_enu_m")) {
    const auto c = cv->numbers(3, "an array of 3 numbers (m)");
    const Eigen::Vector3d C(c[0], c[1], c[2]);
    const double tol = 1e-6 * std::max(1.0, r.camera.pose.T.norm());
    if ((C - r.camera.pose.center()).norm() > tol)
      cv->fail("inconsistent with rotation_world_to_camera and translation_m (C = −Rᵀ·T differs by " +
               std::to_string((C - r.camera.pose.center()).norm()) + " m)");
  }

  if (auto co = root.find("clock_offset_s")) {
    const std::string form = "a number of seconds, |x| ≤ 10 (camera clock − GNSS time)";
    r.clock_offset_s = co->number(form);
    if (!(std::abs(r.clock_offset_s) <= 10)) co->fail_expected(form);
  }
  if (auto sv = root.find("sigma")) {
    // σ are derived from the covariance; only their form is checked here.
    sv->require_object("an object of 1σ values");
  }
  if (auto cv = root.find("covariance")) {
    cv->require_object("an object {\"parameters\", \"matrix\", \"center_enu_m2\"}");
    cv->check_keys({"parameters", "matrix", "center_enu_m2"});
    const JsonView pv = cv->at("parameters", "an array of parameter names");
    const std::size_t n = pv.require_array("an array of parameter names");
    std::vector<std::string> choices;
    for (const CameraParameterInfo& info : camera_parameter_table()) choices.push_back(info.name);
    for (std::size_t i = 0; i < n; ++i) {
      const JsonView e = pv.element(i);
      const std::string name = e.nonempty_string("a parameter name");
      const auto p = parameter_from_name(name);
      if (!p) e.fail("unknown parameter '" + name + "'" + did_you_mean(name, choices));
      if (contains(r.parameters, *p)) e.fail("parameter '" + name + "' is listed twice");
      r.parameters.push_back(*p);
    }
    const bool has_t = std::any_of(r.parameters.begin(), r.parameters.end(), is_translation);
    const bool has_c = std::any_of(r.parameters.begin(), r.parameters.end(), is_center);
    if (has_t && has_c)
      pv.fail("mixes translation (Tx Ty Tz) and centre (CE CN CU) parameters; use one pose form");
    const std::string mform = "a symmetric " + std::to_string(n) + "x" + std::to_string(n) +
                              " matrix (one row per parameter), or [] when not computed";
    const JsonView mv = cv->at("matrix", mform);
    const std::size_t rows = mv.require_array(mform);
    if (rows != 0 && rows != n) mv.fail_expected(mform);
    r.covariance.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(rows));
    for (std::size_t i = 0; i < rows; ++i) {
      const auto row = mv.element(i).numbers(n, mform);
      for (std::size_t k = 0; k < n; ++k) r.covariance(Eigen::Index(i), Eigen::Index(k)) = row[k];
    }
    for (std::size_t i = 0; i < rows; ++i) {
      if (!(r.covariance(Eigen::Index(i), Eigen::Index(i)) >= 0))
        mv.fail("negative variance of '" + std::string(parameter_name(r.parameters[i])) + "'; expected " +
                mform);
      for (std::size_t k = 0; k < i; ++k)
        if (r.covariance(Eigen::Index(i), Eigen::Index(k)) != r.covariance(Eigen::Index(k), Eigen::Index(i)))
          mv.fail("not symmetric; expected " + mform);
    }
    if (auto cc = cv->find("center_enu_m2"); cc && !cc->json().is_null()) {
      const std::string cform = "a 3x3 covariance matrix (m²) or null";
      cc->require_array(cform, 3, 3);
      for (int i = 0; i < 3; ++i) {
        const auto row = cc->element(i).numbers(3, cform);
        for (int k = 0; k < 3; ++k) r.center_covariance_m2(i, k) = row[k];
      }
    }
  }
  if (auto rp = root.find("reprojection")) {
    rp->require_object("an object {\"rms_px\", \"mean_px\", \"max_px\", \"n_used\", \"n_rejected\"}");
    rp->check_keys({"rms_px", "mean_px", "max_px", "n_used", "n_rejected"});
    if (auto v = rp->find("rms_px")) r.reprojection.rms_px = number_or_null(*v, "a number of pixels or null");
    if (auto v = rp->find("mean_px"))
      r.reprojection.mean_px = number_or_null(*v, "a number of pixels or null");
    if (auto v = rp->find("max_px")) r.reprojection.max_px = number_or_null(*v, "a number of pixels or null");
    for (const char* k : {"n_used", "n_rejected"})
      if (auto v = rp->find(k)) {
        const std::int64_t n = v->integer("a non-negative count");
        if (n < 0 || n > std::numeric_limits<int>::max()) v->fail_expected("a non-negative count");
        (std::string(k) == "n_used" ? r.reprojection.n_used : r.reprojection.n_rejected) =
            static_cast<int>(n);
      }
  }
  if (auto rj = root.find("rejected")) {
    const std::size_t n = rj->require_array("an array of observation indices");
    for (std::size_t i = 0; i < n; ++i)
      r.rejected.push_back(static_cast<std::size_t>(rj->element(i).unsigned_integer("a non-negative index")));
  }
  if (auto w = root.find("warnings")) {
    const std::size_t n = w->require_array("an array of strings");
    for (std::size_t i = 0; i < n; ++i) r.warnings.push_back(w->element(i).string("a string"));
  }
  if (auto d = root.find("details")) {
    d->require_object("an object");
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
