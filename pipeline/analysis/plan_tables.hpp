#pragma once
// `rangecal plan`'s output (docs/accuracy_analysis.md `plan`, "Output"): the analyses of
// route_plan.hpp as console tables and as one HTML page, the candidates side by side.
#include <string>
#include <vector>

#include "pipeline/analysis/route_plan.hpp"

namespace rangecal {

/// Side-by-side tables of the candidates (same cameras and poles expected; missing ones shown "-").
/// Per free set: per camera the points and each parameter's σ in every candidate ("!" for poorly
/// determined) — per-camera, network and their ratio when some candidate's cameras share an
/// epoch, else per-camera only with a note that the network is the per-camera calibration —; the
/// calibration-only intersection σ through the flight volume of both methods; the poles' 1σ.
std::string format_plan_table(const std::vector<RoutePlanAnalysis>& candidates);

/// The same tables as one self-contained HTML page (poorly determined cells highlighted).
std::string format_plan_html(const std::vector<RoutePlanAnalysis>& candidates);

}  // namespace rangecal
