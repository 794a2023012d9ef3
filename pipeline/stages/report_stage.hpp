#pragma once
// The report stage (docs/outputs.md): reads what the earlier stages wrote in the output folder
// (pipeline/report/report_data.hpp) and writes `<output_dir>/report.html` (pipeline/report/report_html.hpp)
// and
// `<output_dir>/summary.json`. Runs alone; a camera without calibration is reported, not an error.
#include <string>

#include "pipeline/config/mission_config.hpp"
#include "pipeline/io/run_log.hpp"
#include "pipeline/report/report_data.hpp"

namespace rangecal {

/// summary.json text (docs/outputs.md): per camera method, rms_px, n_used (null when not calibrated);
/// intersection mean and max dR in metres (null when intersection.csv is missing or has no dR).
/// Deterministic (fixed key order, numbers as read).
std::string format_summary_json(const ReportData& data);

StageLog run_report_stage(const MissionConfig& cfg);

}  // namespace rangecal
