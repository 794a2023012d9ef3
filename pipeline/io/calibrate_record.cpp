#include "pipeline/io/calibrate_record.hpp"

#include "config/error.hpp"
#include "config/json_view.hpp"
#include "pipeline/io/record_fields.hpp"

namespace rangecal {
namespace {

// A camera's scalar keys, in the order they are read: `failed` stands between the two parts, and a
// camera that failed has only the first.
const RecordField<CalibrateCameraRecord> kInputFields[] = {
    {"pairs", &CalibrateCameraRecord::pairs},
    {"control_poles", &CalibrateCameraRecord::control_poles},
};
const RecordField<CalibrateCameraRecord> kFitFields[] = {
    {"method", &CalibrateCameraRecord::method},
    {"rms_px", &CalibrateCameraRecord::rms_px},  // NaN is written as null
    {"n_used", &CalibrateCameraRecord::n_used},
    {"n_rejected", &CalibrateCameraRecord::n_rejected},
    {"opencv_fit_max_px", &CalibrateCameraRecord::opencv_fit_max_px},
    {"opencv_undistort_max_px", &CalibrateCameraRecord::opencv_undistort_max_px},
    {"dlt_only_rms_px", &CalibrateCameraRecord::dlt_only_rms_px},
    {"dlt_only_max_px", &CalibrateCameraRecord::dlt_only_max_px},
    {"dlt_profile_max_px", &CalibrateCameraRecord::dlt_profile_max_px},
};
const RecordField<MethodChoiceRecord> kMethodChoiceFields[] = {
    {"method", &MethodChoiceRecord::method},
    {"shared_epochs", &MethodChoiceRecord::shared_epochs},
    {"why", &MethodChoiceRecord::why},
};

nlohmann::json calibrate_camera_json(const CalibrateCameraRecord& c) {
  nlohmann::json j;
  write_fields(kInputFields, c, &j);
  if (!c.failed.empty()) {
    j["failed"] = c.failed;
    return j;
  }
  write_fields(kFitFields, c, &j);
  if (!c.exports_refused.empty()) j["exports_refused"] = c.exports_refused;
  j["method_time_s"] = nlohmann::json::object();
  for (const auto& [m, s] : c.method_time_s) j["method_time_s"][m] = s;
  j["warnings"] = nlohmann::json::array();
  for (const WarningCodeRecord& w : c.warnings)
    j["warnings"].push_back({{"kind", warning_kind_name(w.kind)},
                             {"camera", w.camera},
                             {"parameters", parameter_names(w.parameters)}});
  return j;
}

WarningCodeRecord parse_warning_code(const JsonView& v) {
  v.require_object("an object {kind, camera, parameters}");
  WarningCodeRecord w;
  const JsonView kind = v.at("kind", "a warning kind");
  const auto k = warning_kind_from_name(kind.string("a warning kind"));
  if (!k) kind.fail_expected("a warning kind (optim/bundle/calibration_warning.hpp)");
  w.kind = *k;
  w.camera = v.at("camera", "a camera id").string("a camera id");
  if (const auto ps = v.find("parameters")) {
    const std::size_t n = ps->require_array("an array of parameter names");
    for (std::size_t i = 0; i < n; ++i) {
      const JsonView e = ps->element(i);
      const auto p = parameter_from_name(e.string("a parameter name"));
      if (!p) e.fail_expected("a parameter name (vision/camera/camera_parameters.hpp)");
      w.parameters.push_back(*p);
    }
  }
  return w;
}

CalibrateCameraRecord parse_calibrate_camera(const JsonView& v) {
  v.require_object("an object {pairs, control_poles, ...}");
  CalibrateCameraRecord c;
  read_fields(kInputFields, v, &c);
  c.failed = string_field(v, "failed");
  if (!c.failed.empty()) return c;
  read_fields(kFitFields, v, &c);
  if (const auto e = v.find("exports_refused")) {
    const std::size_t n = e->require_array("an array of strings");
    for (std::size_t i = 0; i < n; ++i) c.exports_refused.push_back(e->element(i).string("a string"));
  }
  if (const auto t = v.find("method_time_s")) {
    t->require_object("an object {method: seconds}");
    for (const auto& [m, s] : t->json().items())
      c.method_time_s[m] = JsonView(s, v.file(), t->path() + "." + m, ErrorKind::input).number("seconds");
  }
  if (const auto ws = v.find("warnings")) {
    const std::size_t n = ws->require_array("an array of {kind, camera, parameters}");
    for (std::size_t i = 0; i < n; ++i) c.warnings.push_back(parse_warning_code(ws->element(i)));
  }
  return c;
}

}  // namespace

std::vector<WarningCodeRecord> warning_codes(const std::vector<CalibrationWarning>& warnings) {
  std::vector<WarningCodeRecord> codes;
  for (const CalibrationWarning& w : warnings) codes.push_back({w.kind, w.camera, w.parameters});
  return codes;
}

nlohmann::json calibrate_record_json(const CalibrateRecord& r) {
  nlohmann::json j = nlohmann::json::object();
  j["cameras"] = by_camera_json(r.cameras, calibrate_camera_json);
  if (!r.network.is_null()) j["network"] = r.network;
  if (r.method_choice) write_fields(kMethodChoiceFields, *r.method_choice, &j["method_choice"]);
  if (!r.held_out.is_null()) j["held_out"] = r.held_out;
  if (!r.lens_selection.is_null()) j["lens_selection"] = r.lens_selection;
  return j;
}

CalibrateRecord parse_calibrate_record(const nlohmann::json& j, const std::string& path,
                                       const std::string& field) {
  const JsonView v(j, path, field, ErrorKind::input);
  v.require_object("an object {cameras, network, method_choice}");
  CalibrateRecord r;
  if (const auto cams = v.find("cameras"))
    r.cameras = parse_by_camera<CalibrateCameraRecord>(*cams, parse_calibrate_camera);
  if (const auto n = v.find("network")) r.network = n->json();
  if (const auto h = v.find("held_out")) r.held_out = h->json();
  if (const auto h = v.find("lens_selection")) r.lens_selection = h->json();
  if (const auto m = v.find("method_choice")) {
    m->require_object("an object {method, shared_epochs, why}");
    read_fields(kMethodChoiceFields, *m, &r.method_choice.emplace());
  }
  return r;
}

}  // namespace rangecal
