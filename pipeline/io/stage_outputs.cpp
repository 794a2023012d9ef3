#include "pipeline/io/stage_outputs.hpp"

#include <algorithm>
#include <filesystem>

#include "config/error.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/steps/calibration_method_names.hpp"

namespace rangecal {
namespace {

std::vector<std::string> per_camera(const MissionConfig& cfg, const std::vector<std::string>& files) {
  std::vector<std::string> out;
  for (const CameraConfig& cam : cfg.cameras)
    for (const std::string& f : files) out.push_back(camera_output(cfg, cam.id, f));
  return out;
}

}  // namespace

const std::vector<std::string>& mission_stage_names() {
  static const std::vector<std::string> names = {"gnss",      "align",     "detect",
                                                 "calibrate", "intersect", "report"};
  return names;
}

std::vector<std::string> stage_output_files(const MissionConfig& cfg, const std::string& stage) {
  if (stage == "gnss") return {lamp_track_path(cfg)};
  if (stage == "align") return per_camera(cfg, {kAlignedCsv});
  if (stage == "detect") return per_camera(cfg, {kDetectionsCsv, kCorrespondencesCsv});
  if (stage == "calibrate") {
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
  if (stage == "intersect") return {mission_output(cfg, kIntersectionCsv)};
  if (stage == "report") return {mission_output(cfg, kSummaryJson), mission_output(cfg, kReportHtml)};
  throw Error(ErrorKind::usage, "", 0, "stage", "unknown stage '" + stage + "'");
}

std::vector<std::string> remove_outputs_from_stage(const MissionConfig& cfg, const std::string& stage) {
  const auto& names = mission_stage_names();
  auto it = std::find(names.begin(), names.end(), stage);
  if (it == names.end()) throw Error(ErrorKind::usage, "", 0, "stage", "unknown stage '" + stage + "'");
  std::vector<std::string> removed;
  for (; it != names.end(); ++it) {
    for (const std::string& path : stage_output_files(cfg, *it)) {
      std::error_code ec;
      if (!std::filesystem::exists(path, ec)) continue;
      if (!std::filesystem::remove(path, ec) || ec)
        throw_input_error(path, 0, "",
                          "cannot remove the previous output before rerunning the " + *it +
                              " stage: " + (ec ? ec.message() : std::string("unknown reason")));
      removed.push_back(path);
    }
  }
  return removed;
}

}  // namespace rangecal
