#include "pipeline/io/residuals_csv.hpp"

#include <cmath>

#include "config/atomic_file.hpp"
#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"
#include "gnss/time/csv_utc.hpp"

namespace rangecal {

std::string format_residuals_csv(const std::vector<ResidualRow>& rows) {
  std::string out = "kind,id,utc,E,N,U,u,v,du_px,dv_px,residual_px,used\n";
  for (const ResidualRow& r : rows) {
    out += r.kind == ResidualRow::Kind::lamp ? "lamp," : "control,";
    out += r.id + ",";
    if (r.utc) out += format_iso8601_utc(*r.utc, 9);
    for (int k = 0; k < 3; ++k) out += "," + format_number("%.4f", r.enu[k]);
    out += "," + format_number("%.4f", r.uv.x()) + "," + format_number("%.4f", r.uv.y());
    if (r.d_px && r.d_px->allFinite())
      out += "," + format_number("%.4f", r.d_px->x()) + "," + format_number("%.4f", r.d_px->y()) + "," +
             format_number("%.4f", r.d_px->norm());
    else
      out += ",,,";
    out += r.used ? ",1\n" : ",0\n";
  }
  return out;
}

void write_residuals_csv(const std::string& path, const std::vector<ResidualRow>& rows) {
  write_file_atomic(path, format_residuals_csv(rows));
}

std::vector<ResidualRow> parse_residuals_csv(const std::string& text, const std::string& path) {
  const CsvTable t = parse_csv(text, path);
  const std::size_t c_kind = t.column("kind"), c_id = t.column("id"), c_utc = t.column("utc"),
                    c_e = t.column("E"), c_n = t.column("N"), c_u = t.column("U"), c_pu = t.column("u"),
                    c_pv = t.column("v"), c_du = t.column("du_px"), c_dv = t.column("dv_px"),
                    c_used = t.column("used");
  std::vector<ResidualRow> out;
  out.reserve(t.records.size());
  for (const auto& rec : t.records) {
    ResidualRow r;
    r.line = rec.line;
    const std::string& kind = t.text(rec, c_kind);
    if (kind == "lamp")
      r.kind = ResidualRow::Kind::lamp;
    else if (kind == "control")
      r.kind = ResidualRow::Kind::control;
    else
      throw_input_error(path, rec.line, "kind", "'" + kind + "' is not lamp or control");
    r.id = t.text(rec, c_id);
    if (r.kind == ResidualRow::Kind::control && r.id.empty())
      throw_input_error(path, rec.line, "id", "a control row needs the pole id");
    if (!t.text(rec, c_utc).empty()) {
      r.utc = csv_utc(t, rec, c_utc);
    } else if (r.kind == ResidualRow::Kind::lamp) {
      throw_input_error(path, rec.line, "utc", "a lamp row needs the frame's UTC");
    }
    r.enu = {t.number(rec, c_e), t.number(rec, c_n), t.number(rec, c_u)};
    r.uv = {t.number(rec, c_pu), t.number(rec, c_pv)};
    if (!t.text(rec, c_du).empty() || !t.text(rec, c_dv).empty())
      r.d_px = Eigen::Vector2d(t.number(rec, c_du), t.number(rec, c_dv));
    const std::string& used = t.text(rec, c_used);
    if (used != "0" && used != "1") throw_input_error(path, rec.line, "used", "'" + used + "' is not 0 or 1");
    r.used = used == "1";
    out.push_back(r);
  }
  return out;
}

std::vector<ResidualRow> read_residuals_csv(const std::string& path) {
  return parse_residuals_csv(read_file_text(path), path);
}

}  // namespace rangecal
