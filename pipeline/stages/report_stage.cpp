#include "pipeline/stages/report_stage.hpp"

#include <cmath>
#include <filesystem>

#include "config/atomic_file.hpp"
#include "config/json_format.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/io/run_outcome.hpp"
#include "pipeline/report/report_html.hpp"
#include "pipeline/steps/calibration_problem.hpp"
#include "pipeline/steps/intersection.hpp"

namespace rangecal {
namespace {

nlohmann::ordered_json num_or_null(double x) {
  return std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(nullptr);
}

}  // namespace

nlohmann::ordered_json prediction_json(const FlightVolumeSigma& volume) {
  using ojson = nlohmann::ordered_json;
  ojson pred;
  pred["slice_up_m"] = volume.slice ? num_or_null(volume.slice->up_m) : ojson(nullptr);
  pred["median_sigma_m"] = volume.stats.n > 0 ? num_or_null(volume.stats.median) : ojson(nullptr);
  pred["max_sigma_m"] = volume.stats.n > 0 ? num_or_null(volume.stats.max) : ojson(nullptr);
  const bool floor = volume.stats.n > 0 && std::isfinite(volume.over_datum_floor);
  pred["datum_floor_median_sigma_m"] = floor ? num_or_null(volume.datum_floor_stats.median) : ojson(nullptr);
  pred["over_datum_floor"] = floor ? num_or_null(volume.over_datum_floor) : ojson(nullptr);
  return pred;
}

std::string format_summary_json(const ReportData& data, const FlightVolumeSigma& volume,
                                const RunOutcome& outcome) {
  using ojson = nlohmann::ordered_json;
  ojson j;
  j["format"] = "rangecal.summary/1";
  j["mission"] = data.mission;
  ojson cams = ojson::object();
  for (const CameraReportData& c : data.cameras) {
    ojson e;
    e["calibrated"] = c.calibration.has_value();
    if (c.calibration) {
      e["method"] = c.calibration->method;
      e["rms_px"] = num_or_null(c.calibration->reprojection.rms_px);
      e["n_used"] = c.calibration->reprojection.n_used;
      e["n_rejected"] = c.calibration->reprojection.n_rejected;
    } else {
      e["method"] = nullptr;
      e["rms_px"] = nullptr;
      e["n_used"] = nullptr;
      e["n_rejected"] = nullptr;
      // docs/outputs.md leaves a failed camera's entry open; saying why saves a look into run.json.
      e["failure"] = c.calibration_failure.empty() ? ojson(nullptr) : ojson(c.calibration_failure);
    }
    cams[c.id] = e;
  }
  j["cameras"] = cams;
  ojson inter;
  const IntersectionMeans m =
      data.intersection ? intersection_means(*data.intersection) : IntersectionMeans{};
  inter["n_poles"] = m.n;
  inter["mean_dR_m"] = m.n > 0 ? num_or_null(m.mean_dR) : ojson(nullptr);
  inter["max_dR_m"] = m.n > 0 ? num_or_null(m.max_dR) : ojson(nullptr);
  j["intersection"] = inter;
  j["prediction"] = prediction_json(volume);
  j["outcome"] = ojson(run_outcome_json(outcome));
  return dump_json_compact_arrays(j);
}

StageLog run_report_stage(const MissionConfig& cfg) {
  StageLog log;
  log.stage = "report";
  std::vector<std::string> ids;
  for (const CameraConfig& c : cfg.cameras) ids.push_back(c.id);
  ReportData data = read_report_data(cfg.output_dir, cfg.mission, ids);
  // The survey places the poles on the site map; a mission without one has none to draw.
  if (!cfg.poles_file.empty() && std::filesystem::exists(cfg.poles_file))
    data.survey = read_pole_survey(cfg.poles_file, cfg.origin);
  data.pick_sigma_px = cfg.intersect.pick_sigma_px;
  data.bar_mean_dR_m = cfg.intersect.bar_mean_dR_m;
  data.pixel_sigma_px = kDefaultPixelSigmaPx;
  int calibrated = 0;
  for (std::size_t i = 0; i < data.cameras.size(); ++i) {
    CameraReportData& c = data.cameras[i];
    if (c.width_px <= 0) {  // not calibrated: the config's sensor size still frames the lamp track
      c.width_px = cfg.cameras[i].sensor.width_px;
      c.height_px = cfg.cameras[i].sensor.height_px;
    }
    if (c.calibration)
      ++calibrated;
    else
      log.warnings.push_back(c.id + ": no calibration.json; the report shows the camera as not calibrated");
  }
  if (!data.intersection) log.warnings.push_back("no intersection.csv; the report has no intersection table");
  const FlightVolumeSigma volume = flight_volume_sigma(data);
  write_file_atomic(mission_output(cfg, kReportHtml), render_report_html(data, volume));
  write_file_atomic(
      mission_output(cfg, kSummaryJson),
      format_summary_json(data, volume, run_outcome(nlohmann::json{{"stages", data.run_stages}})));
  log.counts["cameras"] = data.cameras.size();
  log.counts["calibrated"] = calibrated;
  log.counts["intersection_poles"] = data.intersection ? data.intersection->size() : 0;
  log.counts["prediction"] = nlohmann::json(prediction_json(volume));
  return log;
}

}  // namespace rangecal
