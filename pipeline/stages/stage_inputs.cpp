#include "pipeline/stages/stage_inputs.hpp"

#include <filesystem>

#include "config/error.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/steps/intersection.hpp"
#include "vision/triangulation/calibration_covariance.hpp"

namespace rangecal {

void require_stage_output(const std::string& path, const char* stage) {
  if (!std::filesystem::exists(path))
    throw_input_error(
        path, 0, "",
        std::string("missing; run the ") + stage + " stage first (rangecal " + stage + " CONFIG)");
}

std::optional<CalibratedCamera> read_calibrated_camera(const MissionConfig& cfg, const std::string& id,
                                                       const std::string& sigma_without,
                                                       std::vector<std::string>* warnings) {
  const std::string path = camera_output(cfg, id, kCalibrationJson);
  if (!std::filesystem::exists(path)) {
    warnings->push_back(id + ": no " + path + " (run rangecal calibrate CONFIG first): camera skipped");
    return std::nullopt;
  }
  CalibratedCamera c;
  c.result = read_calibration_json(path);
  c.covariance = camera_covariance(c.result, &c.usable);
  if (!c.usable)
    warnings->push_back(id + ": calibration.json has no usable covariance: " + sigma_without +
                        " only for this camera");
  return c;
}

}  // namespace rangecal
