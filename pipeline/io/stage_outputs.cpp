#include "pipeline/io/stage_outputs.hpp"

#include <algorithm>
#include <filesystem>

#include "config/error.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/mission/calibration_method_names.hpp"

namespace rangecal {
namespace {

std::vector<std::string> per_camera(const MissionConfig& cfg, const std::vector<std::string>& files) {
  std::vector<std::string> out;
  for (const CameraConfig& cam : cfg.cameras)
    for (const std::string& f : files) out.push_back(camera_output(cfg, cam.id, f));
  return out;
}

std::vector<std::string> gnss_outputs(const MissionConfig& cfg) {
  return {lamp_track_path(cfg)};
}

std::vector<std::string> align_outputs(const MissionConfig& cfg) {
  return per_camera(cfg, {kAlignedCsv});
}

std::vector<std::string> detect_outputs(const MissionConfig& cfg) {
  return per_camera(cfg, {kDetectionsCsv, kCorrespondencesCsv});
}

std::vector<std::string> calibrate_outputs(const MissionConfig& cfg) {
  std::vector<std::string> files = {kCalibrationJson, kCameraOpencvYml, kDltCoefficientsCsv,
                                    kArgusProfileTxt, kResidualsCsv,    kMethodsCsv};
  for (const std::string& m : calibration_method_names()) files.push_back(compare_calibration_json(m));
  std::vector<std::string> out = per_camera(cfg, files);
  // The network's files: a rerun by another method must not leave them to be read as its own
  // (the report's network section, the intersect stage's cross covariances).
  out.push_back(mission_output(cfg, kNetworkJson));
  out.push_back(mission_output(cfg, kLampTrackAdjustedCsv));
  return out;
}

std::vector<std::string> intersect_outputs(const MissionConfig& cfg) {
  return {mission_output(cfg, kIntersectionCsv)};
}

std::vector<std::string> trajectory_outputs(const MissionConfig& cfg) {
  return {mission_output(cfg, kTrajectoryCsv), mission_output(cfg, kTrajectoryJson)};
}

std::vector<std::string> report_outputs(const MissionConfig& cfg) {
  return {mission_output(cfg, kSummaryJson), mission_output(cfg, kReportHtml)};
}

const MissionStage& stage_row(const std::string& stage) {
  for (const MissionStage& s : mission_stage_table())
    if (s.name == stage) return s;
  throw Error(ErrorKind::usage, "", 0, "stage", "unknown stage '" + stage + "'");
}

}  // namespace

const std::vector<MissionStage>& mission_stage_table() {
  static const std::vector<MissionStage> table = {
      {"gnss", gnss_outputs},           {"align", align_outputs},         {"detect", detect_outputs},
      {"calibrate", calibrate_outputs}, {"intersect", intersect_outputs}, {"trajectory", trajectory_outputs},
      {"report", report_outputs},
  };
  return table;
}

const std::vector<std::string>& mission_stage_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const MissionStage& s : mission_stage_table()) v.push_back(s.name);
    return v;
  }();
  return names;
}

std::vector<std::string> stage_output_files(const MissionConfig& cfg, const std::string& stage) {
  return stage_row(stage).outputs(cfg);
}

std::vector<std::string> remove_outputs_from_stage(const MissionConfig& cfg, const std::string& stage) {
  const auto& table = mission_stage_table();
  auto it = std::find_if(table.begin(), table.end(), [&](const MissionStage& s) { return s.name == stage; });
  if (it == table.end()) throw Error(ErrorKind::usage, "", 0, "stage", "unknown stage '" + stage + "'");
  std::vector<std::string> removed;
  for (; it != table.end(); ++it) {
    for (const std::string& path : it->outputs(cfg)) {
      std::error_code ec;
      if (!std::filesystem::exists(path, ec)) continue;
      if (!std::filesystem::remove(path, ec) || ec)
        throw_input_error(path, 0, "",
                          "cannot remove the previous output before rerunning the " + it->name +
                              " stage: " + (ec ? ec.message() : std::string("unknown reason")));
      removed.push_back(path);
    }
  }
  return removed;
}

}  // namespace rangecal
