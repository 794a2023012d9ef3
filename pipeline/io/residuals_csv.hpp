#pragma once
// `<cam>/residuals.csv`, written by the calibrate stage (docs/outputs.md): one row per observation
// of the camera's calibration problem — its lamp pairs in correspondences.csv order, then the
// control poles it calibrated with — with the residual of the calibrated camera and whether the
// calibration used it (0: rejected as an outlier). correspondences.csv stays as the detect stage
// wrote it (one writer per file), so a rerun of calibrate reads what detect wrote.
//
// Columns: kind,id,utc,E,N,U,u,v,du_px,dv_px,residual_px,used
//   kind        lamp | control
//   id          the control pole's id; empty for lamp rows
//   utc         the frame's UTC (lamp rows; ISO 8601, 9 digits); empty for control rows
//   E,N,U       the world point (m, site ENU), 0.1 mm
//   u,v         the observed pixel (px), 1e-4 px
//   du_px,dv_px projected − observed (px), 1e-4 px; the projection of the lamp where it stood at
//               the true exposure time (the calibration's clock offset); empty when it does not project
//   residual_px √(du² + dv²); empty when it does not project
//   used        1 or 0
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"

namespace rangecal {

struct ResidualRow {
  enum class Kind { lamp, control };
  Kind kind = Kind::lamp;
  std::string id;              ///< control pole id (control rows)
  std::optional<UtcTime> utc;  ///< frame UTC (lamp rows)
  Eigen::Vector3d enu = Eigen::Vector3d::Zero();
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  std::optional<Eigen::Vector2d> d_px;  ///< projected − observed; empty when it does not project
  bool used = true;
  long line = 0;  ///< line in the file when read
};

/// Deterministic text: same rows → same bytes.
std::string format_residuals_csv(const std::vector<ResidualRow>& rows);
/// Atomic write of format_residuals_csv.
void write_residuals_csv(const std::string& path, const std::vector<ResidualRow>& rows);
/// Reads and validates; errors name file, line and column.
std::vector<ResidualRow> read_residuals_csv(const std::string& path);
/// As read_residuals_csv, from text; `path` names it in messages.
std::vector<ResidualRow> parse_residuals_csv(const std::string& text, const std::string& path);

}  // namespace rangecal
