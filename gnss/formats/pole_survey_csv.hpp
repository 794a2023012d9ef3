#pragma once
// The pole survey (docs/formats.md): `poles.csv` with header `id,role,lat,lon,h` (WGS84 degrees,
// ellipsoidal metres) or `id,role,E,N,U` (site ENU metres). Role `control` poles may serve as
// calibration points (seed 002's Tsai baseline used them); `check` poles only ever serve the
// intersection check, never calibration.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "gnss/geodesy/geodetic_origin.hpp"

namespace rangecal {

enum class PoleRole { control, check };
const char* to_string(PoleRole r);

struct SurveyedPole {
  std::string id;
  PoleRole role = PoleRole::check;
  Eigen::Vector3d enu = Eigen::Vector3d::Zero();  ///< pole top, site ENU (m)
  long line = 0;                                  ///< line in the survey file, for messages
};

/// Reads a pole survey; geodetic rows are converted to site ENU about `origin`. Throws
/// rangecal::Error (input) naming file, line and field: unknown header, bad number, latitude out
/// of range, unknown role, duplicate id, no poles.
std::vector<SurveyedPole> read_pole_survey(const std::string& path, const GeodeticOrigin& origin);
/// As read_pole_survey from the file's text in memory (`path` is for messages).
std::vector<SurveyedPole> parse_pole_survey(const std::string& text, const std::string& path,
                                            const GeodeticOrigin& origin);

/// A pole-top pixel picked in one camera's images (docs/formats.md `<cam>/poles_px.csv`: `id,u,v`).
struct PolePick {
  std::string id;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  long line = 0;
};

/// The size of the image picks are made in (px); 0 × 0 when not known where the picks are read.
struct ImageExtent {
  int width_px = 0;
  int height_px = 0;
};

/// Reads `id,u,v`; errors name file, line and field (bad number, duplicate id, a pick outside the
/// image — or beyond ±1e5 px when `extent` is unknown).
std::vector<PolePick> read_pole_picks(const std::string& path, ImageExtent extent);
/// As read_pole_picks from the file's text in memory (`path` is for messages).
std::vector<PolePick> parse_pole_picks(const std::string& text, const std::string& path, ImageExtent extent);

}  // namespace rangecal
