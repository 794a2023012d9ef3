#include "pipeline/io/intersect_record.hpp"

#include "config/error.hpp"
#include "config/json_view.hpp"
#include "pipeline/io/record_fields.hpp"

namespace rangecal {
namespace {

nlohmann::json means_json(const IntersectMeansRecord& m) {
  nlohmann::json j;
  j["n"] = m.n;
  j["mean_abs_dE_m"] = m.mean_abs_dE_m;  // NaN is written as null
  j["mean_abs_dN_m"] = m.mean_abs_dN_m;
  j["mean_abs_dU_m"] = m.mean_abs_dU_m;
  j["mean_dR_m"] = m.mean_dR_m;
  j["max_dR_m"] = m.max_dR_m;
  j["rms_dR_m"] = m.rms_dR_m;
  j["mean_sigma_m"] = m.mean_sigma_m;
  return j;
}

IntersectMeansRecord parse_means(const JsonView& v) {
  IntersectMeansRecord m;
  m.n = static_cast<int>(integer_field(v, "n"));
  m.mean_abs_dE_m = number_field(v, "mean_abs_dE_m", m.mean_abs_dE_m);
  m.mean_abs_dN_m = number_field(v, "mean_abs_dN_m", m.mean_abs_dN_m);
  m.mean_abs_dU_m = number_field(v, "mean_abs_dU_m", m.mean_abs_dU_m);
  m.mean_dR_m = number_field(v, "mean_dR_m", m.mean_dR_m);
  m.max_dR_m = number_field(v, "max_dR_m", m.max_dR_m);
  m.rms_dR_m = number_field(v, "rms_dR_m", m.rms_dR_m);
  m.mean_sigma_m = number_field(v, "mean_sigma_m", m.mean_sigma_m);
  return m;
}

}  // namespace

nlohmann::json intersect_record_json(const IntersectRecord& r) {
  nlohmann::json j = nlohmann::json::object();
  if (!r.skipped.empty()) {
    j["skipped"] = r.skipped;
    return j;
  }
  j["joint_covariance"] = r.joint_covariance;
  j["cameras_used"] = r.cameras_used;
  j["pick_sigma_px"] = r.pick_sigma_px;
  j["poles_picked"] = r.poles_picked;
  j["poles_triangulated"] = r.poles_triangulated;
  j["check_poles"] = r.check.n;
  j["control_poles"] = r.control.n;
  j["unsurveyed_poles"] = r.unsurveyed_poles;
  // The headline figures (docs/outputs.md summary: intersection mean and max dR) over check poles.
  j["mean_dR_m"] = r.check.mean_dR_m;
  j["max_dR_m"] = r.check.max_dR_m;
  j["mean_sigma_m"] = r.check.mean_sigma_m;
  j["check"] = means_json(r.check);
  j["control"] = means_json(r.control);
  j["warnings"] = r.warnings;
  return j;
}

IntersectRecord parse_intersect_record(const nlohmann::json& j, const std::string& path,
                                       const std::string& field) {
  const JsonView v(j, path, field, ErrorKind::input);
  v.require_object("an object {cameras_used, poles_picked, poles_triangulated, ...}");
  IntersectRecord r;
  r.skipped = string_field(v, "skipped");
  if (!r.skipped.empty()) return r;
  r.joint_covariance = bool_field(v, "joint_covariance");
  if (const auto u = v.find("cameras_used")) {
    const std::size_t n = u->require_array("an array of camera ids");
    for (std::size_t i = 0; i < n; ++i) r.cameras_used.push_back(u->element(i).string("a camera id"));
  }
  r.pick_sigma_px = number_field(v, "pick_sigma_px");
  r.poles_picked = count_field(v, "poles_picked");
  r.poles_triangulated = count_field(v, "poles_triangulated");
  r.unsurveyed_poles = static_cast<int>(integer_field(v, "unsurveyed_poles"));
  if (const auto c = object_field(v, "check", "an object {n, mean_dR_m, ...}")) r.check = parse_means(*c);
  if (const auto c = object_field(v, "control", "an object {n, mean_dR_m, ...}")) r.control = parse_means(*c);
  r.warnings = count_field(v, "warnings");
  return r;
}

}  // namespace rangecal
