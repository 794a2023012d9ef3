#pragma once
// `rangecal plan --target-path`'s output (docs/accuracy_analysis.md "A target's path"): per
// candidate the path's instants, how many two or more cameras see, the σ along the path (median,
// 95 %, the worst and where) and the medians of its parts; and the per-instant CSV.
#include <string>
#include <vector>

#include "pipeline/analysis/target_path_plan.hpp"

namespace rangecal {

struct TargetPathCandidate {
  std::string name;                  ///< the scenario's file stem
  std::vector<std::string> cameras;  ///< camera ids, by index
  bool calibration_known = true;     ///< false: the network's bound was singular, σ without it
  PlannedTargetPath plan;
};

/// The console table; `path_file` and the options head it.
std::string format_target_path_table(const std::vector<TargetPathCandidate>& candidates,
                                     const std::string& path_file, const std::vector<std::string>& free,
                                     const TargetPathOptions& options);

/// CSV, one row per candidate and instant: candidate,t_s,E,N,U,cameras,sigma_m,sigma_E,sigma_N,
/// sigma_U,sigma_labels_m,sigma_timing_m,sigma_calibration_m (m, s; cameras joined by '+').
std::string target_path_csv_text(const std::vector<TargetPathCandidate>& candidates);

}  // namespace rangecal
