#pragma once
// `intersection.csv` (docs/outputs.md): `id,E,N,U,E_survey,N_survey,U_survey,dE,dN,dU,dR,sigma_m`, one row
// per `check` pole triangulated by the intersect stage (seed 002 Table 4 without its mean row,
// which a reader computes from the rows: intersection_means). Metres, fixed 4 decimals (0.1 mm,
// far below the ~1 cm a 1 px pick error makes at the range's 64 m), so reruns are byte-identical.
// Control poles are not written: they may have been calibration points and so do not measure
// accuracy; their figures go to run.json's counts. Written by pipeline/stages/intersect_stage.cpp, read
// by the report stage. Rows from an intersection result and their mean row:
// pipeline/steps/intersection.hpp.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace rangecal {

struct IntersectionRow {
  std::string id;
  Eigen::Vector3d enu = Eigen::Vector3d::Zero();         ///< triangulated E, N, U (m)
  Eigen::Vector3d survey_enu = Eigen::Vector3d::Zero();  ///< surveyed E, N, U (m)
  Eigen::Vector3d d_enu = Eigen::Vector3d::Zero();       ///< dE, dN, dU = triangulated − surveyed (m)
  double dR = 0;                                         ///< |d| (m)
  double sigma_m = 0;                                    ///< predicted RMS of dR (m)
  long line = 0;                                         ///< line in the file when read
};

/// CSV text: header, then one line per row, every number "%.4f" (no "-0.0000").
std::string format_intersection_csv(const std::vector<IntersectionRow>& rows);

/// Writes the CSV atomically (config/atomic_file.hpp).
void write_intersection_csv(const std::string& path, const std::vector<IntersectionRow>& rows);

/// Parses intersection.csv text; `path` names it in messages. Throws rangecal::Error (input)
/// naming file, line and column for a missing column, a non-numeric value, an empty or duplicate
/// id, or a negative dR / sigma_m.
std::vector<IntersectionRow> parse_intersection_csv(const std::string& text, const std::string& path);
/// Reads intersection.csv (a missing file is an input error naming it).
std::vector<IntersectionRow> read_intersection_csv(const std::string& path);

}  // namespace rangecal
