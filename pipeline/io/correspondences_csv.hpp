#pragma once
// `<cam>/correspondences.csv` (docs/outputs.md): the (lamp ENU, lamp pixel) pairs the calibrate stage
// uses, written by align+detect — or by a user who already has point pairs.
//
// Columns: utc,E,N,U,u,v,residual_px,used[,sdE,sdN,sdU][,vE,vN,vU][,pixel_sigma_px]
//   utc      ISO 8601 UTC (Z, 9 digits) of the frame
//   E,N,U    lamp centre, local ENU metres about site.origin
//   u,v      lamp pixel (u right, v down, top-left pixel centre = (0,0))
//   residual_px  reprojection residual after calibration (blank before it)
//   used     1 if the calibration used the pair, 0 if it rejected it as an outlier (blank before it)
//   sdE,sdN,sdU  optional (our extension of docs/outputs.md): the world point's 1σ in metres, from the PPK
//                sd interpolated to the frame; when absent the calibrate stage uses its default.
//   vE,vN,vU     optional (our extension): the lamp velocity at the frame, m/s, for the bundle's
//                clock-offset parameter; when absent the clock offset cannot be estimated.
//   pixel_sigma_px  optional (our extension): the pixel's own 1σ per axis (px, an imported track's
//                `sigma_px`); blank: the camera's a-priori σ, which the network scales by its image
//                variance component. A stated σ is taken as stated, as a pole pick's.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"

namespace rangecal {

struct Correspondence {
  UtcTime utc;
  Eigen::Vector3d enu = Eigen::Vector3d::Zero();
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  std::optional<double> residual_px;  ///< filled by the calibrate stage
  std::optional<bool> used;           ///< filled by the calibrate stage
  std::optional<Eigen::Vector3d> sd_enu;
  std::optional<Eigen::Vector3d> vel_enu;  ///< m/s
  std::optional<double> pixel_sigma_px;    ///< the pixel's own σ (px); none: the camera's
  long line = 0;  ///< line of the file it was read from (0 when made in memory), for messages
};

/// Deterministic text: same pairs → same bytes. Positions to 0.1 mm, pixels to 1e-4 px.
std::string format_correspondences_csv(const std::vector<Correspondence>& pairs);
/// Atomic write of format_correspondences_csv.
void write_correspondences_csv(const std::string& path, const std::vector<Correspondence>& pairs);
/// Reads and validates (time strictly increasing, numbers finite, used ∈ {0,1,blank}); errors name
/// file, line and column. An empty table (header only) is allowed here; callers decide if too few.
std::vector<Correspondence> read_correspondences_csv(const std::string& path);
/// As read_correspondences_csv from the file's text in memory (`path` is for messages).
std::vector<Correspondence> parse_correspondences_csv(const std::string& text, const std::string& path);

}  // namespace rangecal
