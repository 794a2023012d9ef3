#include "pipeline/report/report_data.hpp"

#include <algorithm>
#include <filesystem>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/json_view.hpp"
#include "gnss/formats/lamp_track_csv.hpp"
#include "pipeline/io/calibrate_record.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/io/output_paths.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;

// run.json: version, config hash, warnings per stage, and the calibrate stage's record (failure
// reasons and warning codes per camera, network statistics, default-method choice).
void read_run_json(const std::string& path, ReportData* data, CalibrateRecord* calibrate) {
  const nlohmann::json doc = parse_json_text(read_file_text(path), path, ErrorKind::input);
  if (!doc.is_object()) throw_input_error(path, 0, "", "expected a JSON object (run.json)");
  if (doc.contains("program") && doc["program"].is_object() && doc["program"].contains("version") &&
      doc["program"]["version"].is_string())
    data->program_version = doc["program"]["version"].get<std::string>();
  if (doc.contains("config") && doc["config"].is_object() && doc["config"].contains("sha256") &&
      doc["config"]["sha256"].is_string())
    data->config_sha256 = doc["config"]["sha256"].get<std::string>();
  if (!doc.contains("stages")) return;
  const nlohmann::json& stages = doc["stages"];
  if (!stages.is_object()) throw_input_error(path, 0, "stages", "expected an object");
  data->run_stages = stages;
  data->run_stages.erase("report");  // the previous report run's own section
  for (const auto& [name, stage] : stages.items()) {
    if (name == "report") continue;  // the report's own warnings are of the previous report run
    if (!stage.is_object()) throw_input_error(path, 0, "stages." + name, "expected an object");
    StageWarnings sw;
    sw.stage = name;
    if (stage.contains("warnings")) {
      const nlohmann::json& w = stage["warnings"];
      if (!w.is_array()) throw_input_error(path, 0, "stages." + name + ".warnings", "expected an array");
      for (const auto& s : w) {
        if (!s.is_string())
          throw_input_error(path, 0, "stages." + name + ".warnings", "expected an array of strings");
        sw.warnings.push_back(s.get<std::string>());
      }
    }
    data->stage_warnings.push_back(sw);
    if (name != "calibrate" || !stage.contains("counts")) continue;
    *calibrate = parse_calibrate_record(stage["counts"], path, "stages.calibrate.counts");
    const CalibrateRecord& record = *calibrate;
    if (!record.network.is_null())
      data->network_statistics =
          parse_network_statistics_json(record.network, path, "stages.calibrate.counts.network");
    if (record.method_choice) {
      data->method_choice = record.method_choice->method;
      data->method_choice_why = record.method_choice->why;
    }
  }
}

}  // namespace

std::vector<const CalibrationResult*> calibrated_cameras(const ReportData& d) {
  std::vector<const CalibrationResult*> cams;
  for (const CameraReportData& c : d.cameras)
    if (c.calibration) cams.push_back(&*c.calibration);
  return cams;
}

const CrossCovariances* network_cross_or_null(const ReportData& d) {
  return d.network_cross.empty() ? nullptr : &d.network_cross;
}

ReportData read_report_data(const std::string& output_dir, const std::string& mission,
                            const std::vector<std::string>& camera_ids) {
  ReportData data;
  data.mission = mission;

  CalibrateRecord calibrate;
  const std::string run_json = mission_output(output_dir, kRunJson);
  if (fs::exists(run_json)) read_run_json(run_json, &data, &calibrate);

  const std::string track = mission_output(output_dir, kLampTrackCsv);
  if (fs::exists(track)) {
    const LampTrack t = read_lamp_track_csv(track);
    LampTrackSummary s;
    s.epochs = t.epochs.size();
    s.start = t.epochs.front().utc;  // the reader rejects a track without epochs
    s.end = t.epochs.back().utc;
    data.track = s;
    data.lamp_track = t;
  }
  // The network bundle's adjusted track (docs/outputs.md): its presence turns the network section on.
  const std::string adjusted = mission_output(output_dir, kLampTrackAdjustedCsv);
  if (fs::exists(adjusted)) data.network_track = read_lamp_track_adjusted_csv(adjusted);

  const std::optional<PpkErrorModelRecord> network_model =
      read_network_ppk_error_model(mission_output(output_dir, kNetworkJson));
  for (const std::string& id : camera_ids) {
    CameraReportData cam;
    cam.id = id;
    const std::string cal = camera_output(output_dir, id, kCalibrationJson);
    if (fs::exists(cal)) {
      cam.calibration = read_calibration_json(cal);
      cam.width_px = cam.calibration->camera.intr.width_px;
      cam.height_px = cam.calibration->camera.intr.height_px;
      const nlohmann::json& details = cam.calibration->details;
      if (cam.calibration->method == "network" && network_model)
        cam.ppk_model = network_model->model;
      else if (details.is_object() && details.contains("ppk_error_model"))
        cam.ppk_model =
            parse_ppk_error_model_json(details["ppk_error_model"], cal, "details.ppk_error_model").model;
    }
    const std::string corr = camera_output(output_dir, id, kCorrespondencesCsv);
    if (fs::exists(corr)) cam.pairs = read_correspondences_csv(corr);
    const std::string residuals = camera_output(output_dir, id, kResidualsCsv);
    if (fs::exists(residuals)) cam.residuals = read_residuals_csv(residuals);
    const std::string methods = camera_output(output_dir, id, kMethodsCsv);
    if (fs::exists(methods)) cam.methods = parse_methods_csv(read_file_text(methods), methods);
    if (const auto rec = calibrate.cameras.find(id); rec != calibrate.cameras.end()) {
      cam.calibration_failure = rec->second.failed;
      cam.warning_codes = rec->second.warnings;
    }
    data.cameras.push_back(std::move(cam));
  }
  // Network calibrations are correlated: the predictions take network.json's cross blocks, in the
  // order of the calibrated cameras (as the intersect stage does, docs/intersection.md).
  std::vector<std::string> ids;
  std::vector<std::vector<CameraParameter>> parameters;
  bool all_network = true;
  for (const CameraReportData& c : data.cameras) {
    if (!c.calibration) continue;
    ids.push_back(c.id);
    parameters.push_back(c.calibration->parameters);
    all_network = all_network && c.calibration->method == "network";
  }
  if (all_network && ids.size() >= 2) {
    data.network_cross =
        read_network_cross_covariances(mission_output(output_dir, kNetworkJson), ids, &parameters);
    // Without the cross blocks the prediction treats the cameras as independent; a floor with its
    // own cross blocks would then not compare like with like.
    if (!data.network_cross.empty())
      data.network_datum_floor =
          read_network_datum_floor(mission_output(output_dir, kNetworkJson), ids, &parameters);
  }
  if (data.network_track)
    data.network_float_epochs = read_network_float_epochs(mission_output(output_dir, kNetworkJson));

  const std::string inter = mission_output(output_dir, kIntersectionCsv);
  if (fs::exists(inter)) data.intersection = read_intersection_csv(inter);
  const std::string trajectory = mission_output(output_dir, kTrajectoryCsv);
  if (fs::exists(trajectory)) data.trajectory = read_trajectory_csv(trajectory);
  return data;
}

}  // namespace rangecal
