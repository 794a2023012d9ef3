#pragma once
// The autopilot log's timing as the report states it (report.html "Data funnel"; docs/gnss.md
// "Receiver lag"): the GNSS receiver lag taken when the log was put on UTC, where it came from, and
// how much a timing error moves the lamp through the lever arm — from the gnss stage's counts in
// run.json (`stages.gnss.counts.attitude`, `.lever_arm`; read with pipeline/io/gnss_record.hpp).
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace rangecal {

struct AttitudeTiming {
  std::string format;      ///< the log's format ("dataflash", "ulog")
  double gnss_lag_ms = 0;  ///< the receiver lag taken (ms)
  std::string lag_source;  ///< "attitude.gnss_lag_ms" or "default for <format>"
  /// The lever arm's lamp motion per ms of timing error (mm/ms), largest and rms over the track;
  /// none when the lever arm is not a body-frame one.
  std::optional<double> motion_max_mm_per_ms, motion_rms_mm_per_ms;
};

/// The timing of run.json's `stages` object; none when the mission's attitude is not an autopilot
/// log (no receiver lag recorded). A count of the wrong type throws rangecal::Error naming its field.
std::optional<AttitudeTiming> attitude_timing(const nlohmann::json& stages);

/// One plain sentence for the report, e.g. "Attitude: dataflash log put on UTC with a GNSS receiver
/// lag of 120 ms (default for dataflash). Through the lever arm a timing error moves the lamp by up
/// to 0.171 mm per ms (rms 0.028): 10 ms of lag error, up to 1.7 mm."
std::string attitude_timing_sentence(const AttitudeTiming& timing);

}  // namespace rangecal
