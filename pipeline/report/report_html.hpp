#pragma once
// report.html (docs/outputs.md): one self-contained page (inline CSS and SVG, no scripts, no external
// resources) built from ReportData. Sections: mission and warnings; an overview; per camera the
// parameters with 1σ, the reprojection tables (seed 002 Tables 2–3), the lamp track on the image
// (Fig. 6), residual vectors and a residual histogram, and the methods table (Table 1); the
// intersection table (Table 4). Deterministic: the same data gives the same bytes (no times).
#include <string>

#include "pipeline/report/flight_volume_sigma.hpp"
#include "pipeline/report/report_data.hpp"

namespace rangecal {

/// `volume` is flight_volume_sigma(data): the verdict's prediction and the intersection slice map.
std::string render_report_html(const ReportData& data, const FlightVolumeSigma& volume);

}  // namespace rangecal
