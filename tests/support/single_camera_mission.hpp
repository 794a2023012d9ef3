#pragma once
// A one-camera mission folder for CLI tests of the stages after detect: correspondences written
// as the detect stage would, and a mission.json (1280×800, 20 µm pixels, 135 mm lens).
#include <filesystem>
#include <string>
#include <vector>

#include "vision/calibration/point_correspondence.hpp"

namespace rangecal::test {

/// Writes <dir>/out/cam1/correspondences.csv from `pts` (0.1 s apart from 2025-06-01T03:00:00Z,
/// lamp sd `sd_m` on each axis) and <dir>/mission.json whose "calibrate" section is
/// `calibrate_json` (a JSON object text) and "mission" is `mission`.
void write_single_camera_mission(const std::filesystem::path& dir,
                                 const std::vector<PointCorrespondence>& pts, double sd_m,
                                 const std::string& calibrate_json, const std::string& mission);

}  // namespace rangecal::test
