#pragma once
// The intersect stage's record: run.json `stages.intersect.counts` (docs/outputs.md,
// docs/intersection.md). One writer and one reader, so the stage, the report and the console
// summary share the keys:
//   skipped            why the stage did nothing (no poles); then the only key
//   joint_covariance   whether sigma_m took the network's cross blocks
//   cameras_used [ids], pick_sigma_px, poles_picked, poles_triangulated, check_poles,
//   control_poles, unsurveyed_poles,
//   mean_dR_m, max_dR_m, mean_sigma_m   the headline figures, over check poles
//   check, control     {n, mean_abs_dE_m, mean_abs_dN_m, mean_abs_dU_m, mean_dR_m, max_dR_m,
//                       rms_dR_m, mean_sigma_m}
//   warnings           how many the stage gave
// Metres are as the stage rounds them (1 µm); a figure not computed (no pole to average) is NaN,
// written as null.
#include <cstddef>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace rangecal {

/// Means over one role of poles (pipeline/steps/intersection.hpp IntersectionMeans).
struct IntersectMeansRecord {
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  int n = 0;
  double mean_abs_dE_m = kNone, mean_abs_dN_m = kNone, mean_abs_dU_m = kNone;
  double mean_dR_m = kNone, max_dR_m = kNone, rms_dR_m = kNone, mean_sigma_m = kNone;
};

struct IntersectRecord {
  std::string skipped;  ///< non-empty: why the stage was skipped; nothing below is set
  bool joint_covariance = false;
  std::vector<std::string> cameras_used;  ///< calibrated cameras with pole picks, in config order
  double pick_sigma_px = 0;
  std::size_t poles_picked = 0, poles_triangulated = 0;
  int unsurveyed_poles = 0;
  /// run.json's check_poles and control_poles are their `n`; its mean_dR_m, max_dR_m and
  /// mean_sigma_m are check's.
  IntersectMeansRecord check, control;
  std::size_t warnings = 0;
};

/// The record as run.json holds it.
nlohmann::json intersect_record_json(const IntersectRecord& r);

/// Parses `j` as intersect_record_json wrote it. `path` and `field` (e.g. "stages.intersect.counts")
/// name it in messages: a value of the wrong type throws rangecal::Error (input) naming
/// `field.<key>`. A missing key keeps its default.
IntersectRecord parse_intersect_record(const nlohmann::json& j, const std::string& path,
                                       const std::string& field);

}  // namespace rangecal
