#include "pipeline/io/intersect_record.hpp"

#include "config/error.hpp"
#include "config/json_view.hpp"
#include "pipeline/io/record_fields.hpp"

namespace rangecal {
namespace {

const RecordField<IntersectMeansRecord> kMeansFields[] = {
    {"n", &IntersectMeansRecord::n},
    {"mean_abs_dE_m", &IntersectMeansRecord::mean_abs_dE_m},  // NaN is written as null
    {"mean_abs_dN_m", &IntersectMeansRecord::mean_abs_dN_m},
    {"mean_abs_dU_m", &IntersectMeansRecord::mean_abs_dU_m},
    {"mean_dR_m", &IntersectMeansRecord::mean_dR_m},
    {"max_dR_m", &IntersectMeansRecord::max_dR_m},
    {"rms_dR_m", &IntersectMeansRecord::rms_dR_m},
    {"mean_sigma_m", &IntersectMeansRecord::mean_sigma_m},
};

// The record's scalar keys, in the order they are read: cameras_used stands after the first part,
// check and control after the second.
const RecordField<IntersectRecord> kCovarianceFields[] = {
    {"joint_covariance", &IntersectRecord::joint_covariance},
};
const RecordField<IntersectRecord> kPoleFields[] = {
    {"pick_sigma_px", &IntersectRecord::pick_sigma_px},
    {"poles_picked", &IntersectRecord::poles_picked},
    {"poles_triangulated", &IntersectRecord::poles_triangulated},
    {"unsurveyed_poles", &IntersectRecord::unsurveyed_poles},
};
const RecordField<IntersectRecord> kWarningFields[] = {
    {"warnings", &IntersectRecord::warnings},
};

nlohmann::json means_json(const IntersectMeansRecord& m) {
  nlohmann::json j;
  write_fields(kMeansFields, m, &j);
  return j;
}

IntersectMeansRecord parse_means(const JsonView& v) {
  IntersectMeansRecord m;
  read_fields(kMeansFields, v, &m);
  return m;
}

}  // namespace

nlohmann::json intersect_record_json(const IntersectRecord& r) {
  nlohmann::json j = nlohmann::json::object();
  if (!r.skipped.empty()) {
    j["skipped"] = r.skipped;
    return j;
  }
  write_fields(kCovarianceFields, r, &j);
  j["cameras_used"] = r.cameras_used;
  write_fields(kPoleFields, r, &j);
  j["check_poles"] = r.check.n;
  j["control_poles"] = r.control.n;
  // The headline figures (docs/outputs.md summary: intersection mean and max dR) over check poles.
  j["mean_dR_m"] = r.check.mean_dR_m;
  j["max_dR_m"] = r.check.max_dR_m;
  j["mean_sigma_m"] = r.check.mean_sigma_m;
  j["check"] = means_json(r.check);
  j["control"] = means_json(r.control);
  write_fields(kWarningFields, r, &j);
  return j;
}

IntersectRecord parse_intersect_record(const nlohmann::json& j, const std::string& path,
                                       const std::string& field) {
  const JsonView v(j, path, field, ErrorKind::input);
  v.require_object("an object {cameras_used, poles_picked, poles_triangulated, ...}");
  IntersectRecord r;
  r.skipped = string_field(v, "skipped");
  if (!r.skipped.empty()) return r;
  read_fields(kCovarianceFields, v, &r);
  if (const auto u = v.find("cameras_used")) {
    const std::size_t n = u->require_array("an array of camera ids");
    for (std::size_t i = 0; i < n; ++i) r.cameras_used.push_back(u->element(i).string("a camera id"));
  }
  read_fields(kPoleFields, v, &r);
  if (const auto c = object_field(v, "check", "an object {n, mean_dR_m, ...}")) r.check = parse_means(*c);
  if (const auto c = object_field(v, "control", "an object {n, mean_dR_m, ...}")) r.control = parse_means(*c);
  read_fields(kWarningFields, v, &r);
  return r;
}

}  // namespace rangecal
