#pragma once
// The console summary of a stage that ran: one line per camera (or per stage) with the counts a
// range engineer checks — what came in, what was kept, what was dropped and why — then the
// warnings. Figures are rounded for reading; run.json keeps them exact.
#include <string>

#include "pipeline/io/run_log.hpp"

namespace rangecal {

/// The report stage's flight-volume line (its counts' `prediction`, docs/outputs.md): the
/// calibration-only intersection σ, and for a network run where it stands against the datum floor;
/// "" without a prediction.
std::string flight_volume_line(const nlohmann::json& report_counts);

/// A few lines of text ending in '\n'. With `verbose` the stage's run.json counts follow in full.
std::string stage_summary(const StageLog& log, bool verbose);

}  // namespace rangecal
