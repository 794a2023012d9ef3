#pragma once
// report.html's "Trajectory" section (docs/outputs.md, docs/trajectory.md): trajectory.csv summarised
// (trajectory_summary.hpp) — the instants, their σ and its parts, the instants inflated or resting on
// an extrapolated lens model, each camera's share, the stretches with their cameras and the gaps —
// and three charts: plan and side views of the track with 1σ ellipses (magnified, the key says how
// much), and σ against time with its label, timing and calibration parts.
#include <string>

#include "pipeline/report/report_data.hpp"

namespace rangecal {

/// The section's HTML; empty when there is no trajectory.csv.
std::string trajectory_section(const ReportData& d);

}  // namespace rangecal
