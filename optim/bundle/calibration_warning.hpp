#pragma once
// A calibration's warning as a typed code beside its text (docs/optimisation.md "Warnings"): the
// kind and the parameters it is about are what readers act on (the report's verdict asks for the
// poorly determined and correlated ones); the text is what people read, in calibration.json and
// run.json, and is never searched.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vision/camera/camera_parameters.hpp"

namespace rangecal {

enum class CalibrationWarningKind {
  rank_deficient,        ///< the covariance: `parameters` cannot be determined (in the network: this camera's
                         ///< share)
  poorly_determined,     ///< one parameter's σ beyond its rule (optim/bundle/bundle_diagnostics.hpp)
  correlated,            ///< two parameters with |ρ| above the correlation warning
  large_clock_offset,    ///< beyond the first-order model's reach
  variance_factor,       ///< χ² beyond its 1 % quantile
  no_redundancy,         ///< dof = 0
  search_at_range_edge,  ///< the sparrow search ended at the edge of its range in `parameters`
  polish_not_converged,  ///< tsai_sassa's LM polish
  no_covariance,         ///< dlt_lmqn: the normal matrix is rank-deficient
  clock_offset_not_estimated,  ///< a method other than bundle/network with clock_offset free
  projection_fallback,         ///< tsai/tsai_sassa: the solved camera did not project every point; a
                               ///< fallback camera was kept
};

struct CalibrationWarning {
  CalibrationWarningKind kind = CalibrationWarningKind::poorly_determined;
  std::vector<CameraParameter> parameters;  ///< the camera's parameters it is about, if any
  std::string text;                         ///< the words, as calibration.json holds them
  std::string camera = {};                  ///< the camera calibrated (its id; set by the caller)
};

/// The kind's name in run.json (`stages.calibrate.counts.cameras.<id>.warnings[].kind`).
inline const char* warning_kind_name(CalibrationWarningKind k) {
  switch (k) {
    case CalibrationWarningKind::rank_deficient:
      return "rank_deficient";
    case CalibrationWarningKind::poorly_determined:
      return "poorly_determined";
    case CalibrationWarningKind::correlated:
      return "correlated";
    case CalibrationWarningKind::large_clock_offset:
      return "large_clock_offset";
    case CalibrationWarningKind::variance_factor:
      return "variance_factor";
    case CalibrationWarningKind::no_redundancy:
      return "no_redundancy";
    case CalibrationWarningKind::search_at_range_edge:
      return "search_at_range_edge";
    case CalibrationWarningKind::polish_not_converged:
      return "polish_not_converged";
    case CalibrationWarningKind::no_covariance:
      return "no_covariance";
    case CalibrationWarningKind::clock_offset_not_estimated:
      return "clock_offset_not_estimated";
    case CalibrationWarningKind::projection_fallback:
      return "projection_fallback";
  }
  return "";
}

/// The kind named `name`; nullopt for a name warning_kind_name never gives.
inline std::optional<CalibrationWarningKind> warning_kind_from_name(std::string_view name) {
  for (int k = 0; k <= static_cast<int>(CalibrationWarningKind::projection_fallback); ++k)
    if (name == warning_kind_name(static_cast<CalibrationWarningKind>(k)))
      return static_cast<CalibrationWarningKind>(k);
  return std::nullopt;
}

/// The rank-deficiency warnings of a covariance as codes of camera `camera`: each names those of
/// the camera's free parameters `free` that the text names (`named`, indices into `free`; in the
/// network's joint covariance `first` is the camera's first column and the names of other
/// cameras' columns are left out).
template <typename Index>
std::vector<CalibrationWarning> rank_deficiency_warnings(const std::vector<std::string>& texts,
                                                         const std::vector<Index>& named,
                                                         const std::vector<CameraParameter>& free,
                                                         const std::string& camera, Index first = 0) {
  std::vector<CameraParameter> parameters;
  for (Index k : named)
    if (k >= first && k - first < static_cast<Index>(free.size()))
      parameters.push_back(free[static_cast<std::size_t>(k - first)]);
  std::vector<CalibrationWarning> out;
  for (const std::string& t : texts)
    out.push_back({CalibrationWarningKind::rank_deficient, parameters, t, camera});
  return out;
}

/// The texts of `warnings`, in order (CalibrationResult::warnings).
inline std::vector<std::string> warning_texts(const std::vector<CalibrationWarning>& warnings) {
  std::vector<std::string> texts;
  texts.reserve(warnings.size());
  for (const CalibrationWarning& w : warnings) texts.push_back(w.text);
  return texts;
}

}  // namespace rangecal
