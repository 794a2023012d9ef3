#pragma once
// `<cam>/methods.csv` (docs/outputs.md), written by the calibrate stage when `compare` is set: one row per
// method (the configured one first, then the compared ones in config order) in seed 002 Table 1's
// layout — u0, v0, f, sx, k1, R, T, σ f, reprojection rms, points used and rejected. Columns:
//   method,u0_px,v0_px,f_mm,sx,k1_per_mm2,r11,…,r33,Tx_m,Ty_m,Tz_m,sigma_f_mm,rms_px,n_used,n_rejected
// Fixed formats (u0 v0 %.4f, f %.5f, sx %.6f, k1 %.6e, R %.6f, T %.4f, σ f %.5f or blank, rms
// %.4f), so the same results give the same bytes.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "vision/camera/calibration_result.hpp"

namespace rangecal {

/// One row: one method's camera (seed 002 Table 1 layout).
struct MethodRow {
  std::string method;
  double u0_px = 0, v0_px = 0, f_mm = 0, sx = 1, k1_per_mm2 = 0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d T = Eigen::Vector3d::Zero();
  std::optional<double> sigma_f_mm;
  double rms_px = 0;
  int n_used = 0;
  int n_rejected = 0;
};

/// The row of a calibration result.
MethodRow method_row(const CalibrationResult& r);

/// methods.csv text.
std::string format_methods_csv(const std::vector<MethodRow>& rows);

/// Parses methods.csv text (`path` for messages); errors name file, line and column.
std::vector<MethodRow> parse_methods_csv(const std::string& text, const std::string& path);

}  // namespace rangecal
