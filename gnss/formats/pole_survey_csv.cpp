#include "gnss/formats/pole_survey_csv.hpp"

#include <set>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "gnss/geodesy/local_enu.hpp"

namespace rangecal {

const char* to_string(PoleRole r) {
  return r == PoleRole::control ? "control" : "check";
}

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
    p.id = t.text(r, c_id);
    p.line = r.line;
    if (p.id.empty()) throw_input_error(path, r.line, "id", "empty pole id");
    if (!ids.insert(p.id).second) throw_input_error(path, r.line, "id", "duplicate pole id '" + p.id + "'");
    const std::string& role = t.text(r, c_role);
    if (role == "control")
      p.role = PoleRole::control;
    else if (role == "check")
      p.role = PoleRole::check;
    else
      throw_input_error(path, r.line, "role", "'" + role + "' is not 'control' or 'check'");
    const Eigen::Vector3d v(t.number(r, c1), t.number(r, c2), t.number(r, c3));
    if (geodetic) {
      if (std::abs(v.x()) > 90) throw_input_error(path, r.line, "lat", "latitude outside [-90, 90] degrees");
      if (std::abs(v.y()) > 180)
        throw_input_error(path, r.line, "lon", "longitude outside [-180, 180] degrees");
      p.enu = site.from_geodetic(v);
    } else {
      p.enu = v;
    }
    poles.push_back(p);
  }
  if (poles.empty()) throw_input_error(path, 0, "", "no poles in the survey file");
  return poles;
}

std::vector<PolePick> read_pole_picks(const std::string& path) {
  return parse_pole_picks(read_file_text(path), path);
}

std::vector<PolePick> parse_pole_picks(const std::string& text, const std::string& path) {
  const CsvTable t = parse_csv(text, path);
  const std::size_t c_id = t.column("id"), c_u = t.column("u"), c_v = t.column("v");
  std::vector<PolePick> picks;
  std::set<std::string> ids;
  for (const auto& r : t.records) {
    PolePick p;
    p.id = t.text(r, c_id);
    p.line = r.line;
    if (p.id.empty()) throw_input_error(path, r.line, "id", "empty pole id");
    if (!ids.insert(p.id).second) throw_input_error(path, r.line, "id", "pole '" + p.id + "' picked twice");
    p.uv = {t.number(r, c_u), t.number(r, c_v)};
    picks.push_back(p);
  }
  return picks;
}

}  // namespace rangecal
