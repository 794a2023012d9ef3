#include "gnss/formats/pole_survey_csv.hpp"

#include <set>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/physical_ranges.hpp"
#include "gnss/geodesy/local_enu.hpp"

namespace rangecal {

const char* to_string(PoleRole r) {
  return r == PoleRole::control ? "control" : "check";
}

namespace {

// The record's pole id: not empty, and not seen before in this file (`duplicate` says why not).
std::string unique_pole_id(const CsvTable& t, const CsvRecord& r, std::size_t col,
                           std::set<std::string>* seen, const std::string& duplicate) {
  const std::string& id = t.text(r, col);
  if (id.empty()) throw_input_error(t.path, r.line, "id", "empty pole id");
  if (!seen->insert(id).second) throw_input_error(t.path, r.line, "id", duplicate + " '" + id + "'");
  return id;
}

}  // namespace

std::vector<SurveyedPole> read_pole_survey(const std::string& path, const GeodeticOrigin& origin) {
  return parse_pole_survey(read_file_text(path), path, origin);
}

std::vector<SurveyedPole> parse_pole_survey(const std::string& text, const std::string& path,
                                            const GeodeticOrigin& origin) {
  const CsvTable t = parse_csv(text, path);
  const std::size_t c_id = t.column("id"), c_role = t.column("role");
  const bool geodetic = t.find_column("lat").has_value();
  if (!geodetic && !t.find_column("E"))
    throw_input_error(path, 1, "", "header must be id,role,lat,lon,h or id,role,E,N,U");
  const std::size_t c1 = t.column(geodetic ? "lat" : "E"), c2 = t.column(geodetic ? "lon" : "N"),
                    c3 = t.column(geodetic ? "h" : "U");
  const LocalEnu site(origin);
  std::vector<SurveyedPole> poles;
  std::set<std::string> ids;
  for (const auto& r : t.records) {
    SurveyedPole p;
    p.id = unique_pole_id(t, r, c_id, &ids, "duplicate pole id");
    p.line = r.line;
    const std::string& role = t.text(r, c_role);
    if (role == "control")
      p.role = PoleRole::control;
    else if (role == "check")
      p.role = PoleRole::check;
    else
      throw_input_error(path, r.line, "role", "'" + role + "' is not 'control' or 'check'");
    if (geodetic) {
      const Eigen::Vector3d v(
          t.number_in(r, c1, -90, 90, "latitude, degrees"),
          t.number_in(r, c2, -180, 180, "longitude, degrees"),
          t.number_in(r, c3, ranges::kMinHeightM, ranges::kMaxHeightM, "ellipsoidal height, m"));
      p.enu = site.from_geodetic(v);
      if (!ranges::within_site_box(p.enu.x(), p.enu.y(), p.enu.z()))
        throw_input_error(path, r.line, "lat",
                          "pole lies " +
                              std::to_string(static_cast<long long>(p.enu.head<2>().norm() / 1000)) +
                              " km from the site origin, outside the site box of +/-50 km (wrong origin in "
                              "the mission config, or a swapped lat/lon?)");
    } else {
      const auto enu = t.site_enu(r, c1, c2, c3);
      p.enu = {enu[0], enu[1], enu[2]};
    }
    poles.push_back(p);
  }
  if (poles.empty()) throw_input_error(path, 0, "", "no poles in the survey file");
  return poles;
}

std::vector<PolePick> read_pole_picks(const std::string& path, ImageExtent extent) {
  return parse_pole_picks(read_file_text(path), path, extent);
}

std::vector<PolePick> parse_pole_picks(const std::string& text, const std::string& path, ImageExtent extent) {
  const CsvTable t = parse_csv(text, path);
  const std::size_t c_id = t.column("id"), c_u = t.column("u"), c_v = t.column("v");
  std::vector<PolePick> picks;
  std::set<std::string> ids;
  for (const auto& r : t.records) {
    PolePick p;
    p.id = unique_pole_id(t, r, c_id, &ids, "pole picked twice");
    p.line = r.line;
    p.uv = {t.number(r, c_u), t.number(r, c_v)};
    if (extent.width_px > 0 && extent.height_px > 0) {
      // Pixel centres at integers: the image spans [-0.5, width - 0.5] × [-0.5, height - 0.5].
      const std::string image = "pixel in the " + std::to_string(extent.width_px) + "x" +
                                std::to_string(extent.height_px) + " image";
      t.number_in(r, c_u, -0.5, extent.width_px - 0.5, image);
      t.number_in(r, c_v, -0.5, extent.height_px - 0.5, image);
    } else {
      t.number_in(r, c_u, -ranges::kMaxPixelCoordinatePx, ranges::kMaxPixelCoordinatePx, "pixel");
      t.number_in(r, c_v, -ranges::kMaxPixelCoordinatePx, ranges::kMaxPixelCoordinatePx, "pixel");
    }
    picks.push_back(p);
  }
  // A camera's picks file is given because the camera sees poles: a file with no pick is a file
  // not filled in (or cut short), and reading on would only surface later as a calibration or an
  // intersection check without poles, far from its cause.
  if (picks.empty())
    throw_input_error(path, t.header_line, "id",
                      "no pole picks after the header: give one id,u,v row per pole top the camera "
                      "sees, or leave pole_observations out of this camera's config");
  return picks;
}

}  // namespace rangecal
