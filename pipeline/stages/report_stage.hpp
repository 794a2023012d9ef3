#pragma once
// The report stage (docs/outputs.md): reads what the earlier stages wrote in the output folder
// (pipeline/report/report_data.hpp) and writes `<output_dir>/report.html`
// (pipeline/report/report_html.hpp) and `<output_dir>/summary.json`. Runs alone; a camera without
// calibration is reported, not an error.
#include <nlohmann/json.hpp>
#include <string>

#include "pipeline/io/run_log.hpp"
#include "pipeline/io/run_outcome.hpp"
#include "pipeline/mission/mission_config.hpp"
#include "pipeline/report/flight_volume_sigma.hpp"
#include "pipeline/report/report_data.hpp"

namespace rangecal {

/// summary.json's and run.json's `prediction` (docs/outputs.md): the flight volume's
/// calibration-only intersection σ (median, max; m) on the slice at `slice_up_m`, and for a network
/// run its datum floor's median and the ratio of the two; null where they do not apply.
nlohmann::ordered_json prediction_json(const FlightVolumeSigma& volume);

/// summary.json text (docs/outputs.md): per camera method, rms_px, n_used (null when not calibrated);
/// intersection mean and max dR in metres (null when intersection.csv is missing or has no dR); the
/// prediction (`volume` = flight_volume_sigma(data)); the run's `outcome` over the stages before
/// the report (pipeline/io/run_outcome.hpp). Deterministic (fixed key order, numbers as read).
std::string format_summary_json(const ReportData& data, const FlightVolumeSigma& volume,
                                const RunOutcome& outcome);

StageLog run_report_stage(const MissionConfig& cfg);

}  // namespace rangecal
