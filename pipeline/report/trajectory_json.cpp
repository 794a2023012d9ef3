#include "pipeline/report/trajectory_json.hpp"

#include <cmath>

#include "pipeline/io/output_paths.hpp"
#include "pipeline/report/trajectory_summary.hpp"

namespace rangecal {

nlohmann::json trajectory_json(const std::vector<TrajectoryRow>& rows, const TrajectoryJsonContext& context) {
  const TrajectorySummary s = summarise_trajectory(rows);
  // The stretches' bounds are instants of the CSV: seconds since the first, back to its UTC.
  const auto utc_at = [&](double since_s) {
    return format_iso8601_utc(UtcTime{rows.front().utc.ns + std::llround(since_s * 1e9)}, 3);
  };
  nlohmann::json j;
  j["format"] = "rangecal trajectory summary 1";
  j["instants_file"] = kTrajectoryCsv;
  j["frame"] = {{"origin",
                 {{"lat_deg", context.origin.lat_deg},
                  {"lon_deg", context.origin.lon_deg},
                  {"h_m", context.origin.h_m}}},
                {"axes", "ENU (east, north, up) at the origin, m; σ 1σ, m; times UTC"}};
  j["settings"] = {{"rate_hz", context.rate_hz},
                   {"extrapolation_sigma_px_per_px", context.extrapolation_sigma_px_per_px},
                   {"gap_steps", kTrajectoryGapSteps},
                   {"smoothing", context.smoothing},
                   {"label_sigma", context.label_sigma}};
  j["instants"] = {{"tried", context.instants_tried},
                   {"triangulated", s.instants},
                   {"single_camera", context.single_camera},
                   {"inflated", s.inflated},
                   {"extrapolated", s.extrapolated}};
  j["joint_covariance"] = context.joint_covariance;
  if (!rows.empty()) {
    j["first_utc"] = format_iso8601_utc(rows.front().utc, 3);
    j["last_utc"] = format_iso8601_utc(rows.back().utc, 3);
    j["span_s"] = s.span_s;
    j["step_s"] = s.step_s;
    j["sigma_m"] = {{"median", s.sigma_median_m},
                    {"p95", s.sigma_p95_m},
                    {"labels_median", s.labels_median_m},
                    {"timing_median", s.timing_median_m},
                    {"calibration_median", s.calibration_median_m}};
  }
  nlohmann::json cameras = nlohmann::json::array();
  for (const auto& [id, inputs] : context.cameras.items()) {
    nlohmann::json c = inputs;
    c["id"] = id;
    c["instants"] = 0;
    c["extrapolated"] = 0;
    for (const TrajectoryCameraUse& u : s.cameras)
      if (u.id == id) {
        c["instants"] = u.instants;
        c["extrapolated"] = u.extrapolated;
      }
    cameras.push_back(c);
  }
  j["cameras"] = cameras;
  nlohmann::json stretches = nlohmann::json::array();
  for (const TrajectoryStretch& st : s.stretches)
    stretches.push_back({{"first_utc", utc_at(st.start_s)},
                         {"last_utc", utc_at(st.end_s)},
                         {"duration_s", st.end_s - st.start_s},
                         {"cameras", st.cameras},
                         {"instants", st.instants}});
  j["stretches"] = stretches;
  return j;
}

}  // namespace rangecal
