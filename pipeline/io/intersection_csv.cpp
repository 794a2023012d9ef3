#include "pipeline/io/intersection_csv.hpp"

#include <set>

#include "config/atomic_file.hpp"
#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"

namespace rangecal {

namespace {

constexpr const char* kHeader = "id,E,N,U,E_survey,N_survey,U_survey,dE,dN,dU,dR,sigma_m";

/// "%.4f", with a value that rounds to zero always printed as "0.0000" (never "-0.0000"), so the
/// text does not depend on the sign of a sub-0.05 mm rounding residue.
void append_number(std::string* s, double v) {
  const std::string text = fmt::format("{:.4f}", v);
  s->push_back(',');
  *s += text == "-0.0000" ? "0.0000" : text;
}

}  // namespace

std::string format_intersection_csv(const std::vector<IntersectionRow>& rows) {
  std::string s = std::string(kHeader) + "\n";
  for (const IntersectionRow& r : rows) {
    s += r.id;
    for (int k = 0; k < 3; ++k) append_number(&s, r.enu[k]);
    for (int k = 0; k < 3; ++k) append_number(&s, r.survey_enu[k]);
    for (int k = 0; k < 3; ++k) append_number(&s, r.d_enu[k]);
    append_number(&s, r.dR);
    append_number(&s, r.sigma_m);
    s += "\n";
  }
  return s;
}

void write_intersection_csv(const std::string& path, const std::vector<IntersectionRow>& rows) {
  write_file_atomic(path, format_intersection_csv(rows));
}

std::vector<IntersectionRow> parse_intersection_csv(const std::string& text, const std::string& path) {
  const CsvTable t = parse_csv(text, path);
  const std::size_t c_id = t.column("id");
  const char* names[11] = {"E",  "N",  "U",  "E_survey", "N_survey", "U_survey",
                           "dE", "dN", "dU", "dR",       "sigma_m"};
  std::size_t c[11];
  for (int k = 0; k < 11; ++k) c[k] = t.column(names[k]);
  std::vector<IntersectionRow> rows;
  std::set<std::string> ids;
  for (const CsvRecord& rec : t.records) {
    IntersectionRow r;
    r.line = rec.line;
    r.id = t.text(rec, c_id);
    if (r.id.empty()) throw_input_error(path, rec.line, "id", "empty pole id");
    if (!ids.insert(r.id).second) throw_input_error(path, rec.line, "id", "pole '" + r.id + "' listed twice");
    for (int k = 0; k < 3; ++k) {
      r.enu[k] = t.number(rec, c[k]);
      r.survey_enu[k] = t.number(rec, c[3 + k]);
      r.d_enu[k] = t.number(rec, c[6 + k]);
    }
    r.dR = t.number(rec, c[9]);
    r.sigma_m = t.number(rec, c[10]);
    if (r.dR < 0) throw_input_error(path, rec.line, "dR", "negative distance");
    if (r.sigma_m < 0) throw_input_error(path, rec.line, "sigma_m", "negative standard deviation");
    rows.push_back(r);
  }
  return rows;
}

std::vector<IntersectionRow> read_intersection_csv(const std::string& path) {
  return parse_intersection_csv(read_file_text(path), path);
}

}  // namespace rangecal
