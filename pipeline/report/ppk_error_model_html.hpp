#pragma once
// report.html's "PPK error model" section (docs/outputs.md): the model the network weighed the PPK
// fixes by (run.json stages.calibrate.counts.network.ppk_error_model; each value with its σ where it
// was estimated, else "fixed in the config"), the corrections' empirical autocorrelation per axis
// against the model's (correction_autocorrelation.hpp), and the number of independent looks at the
// PPK error with what would lower it.
#include <string>

#include "pipeline/report/report_data.hpp"

namespace rangecal {

/// The section's HTML; empty when the network did not run (no adjusted track).
std::string ppk_error_model_section(const ReportData& d);

}  // namespace rangecal
