#include "pipeline/io/methods_csv.hpp"

#include <cmath>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"

namespace rangecal {
namespace {

// A number, or nullopt for a blank field (methods.csv's sigma_f_mm of a method without covariance).
std::optional<double> optional_number(const CsvTable& t, const CsvRecord& r, std::size_t col) {
  if (t.text(r, col).empty()) return std::nullopt;
  return t.number(r, col);
}

int count_field(const CsvTable& t, const CsvRecord& r, std::size_t col) {
  const std::int64_t n = t.integer(r, col);
  if (n < 0 || n > 1000000000) throw_input_error(t.path, r.line, t.header[col], "expected a count >= 0");
  return static_cast<int>(n);
}

}  // namespace

MethodRow method_row(const CalibrationResult& r) {
  MethodRow m;
  const CameraIntrinsics& in = r.camera.intr;
  m.method = r.method;
  m.u0_px = in.u0_px;
  m.v0_px = in.v0_px;
  m.f_mm = in.f_mm;
  m.sx = in.sx;
  m.k1_per_mm2 = in.dist.k1;
  m.R = r.camera.pose.R;
  m.T = r.camera.pose.T;
  if (std::isfinite(r.sigma(CameraParameter::f))) m.sigma_f_mm = r.sigma(CameraParameter::f);
  m.rms_px = r.reprojection.rms_px;
  m.n_used = r.reprojection.n_used;
  m.n_rejected = r.reprojection.n_rejected;
  return m;
}

std::string format_methods_csv(const std::vector<MethodRow>& rows) {
  std::string s =
      "method,u0_px,v0_px,f_mm,sx,k1_per_mm2,r11,r12,r13,r21,r22,r23,r31,r32,r33,Tx_m,Ty_m,Tz_m,"
      "sigma_f_mm,rms_px,n_used,n_rejected\n";
  for (const MethodRow& m : rows) {
    s += m.method;
    auto add = [&](const char* format, double v) { s += "," + format_number(format, v); };
    add("%.4f", m.u0_px);
    add("%.4f", m.v0_px);
    add("%.5f", m.f_mm);
    add("%.6f", m.sx);
    add("%.6e", m.k1_per_mm2);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) add("%.6f", m.R(i, j));
    for (int i = 0; i < 3; ++i) add("%.4f", m.T[i]);
    if (m.sigma_f_mm)
      add("%.5f", *m.sigma_f_mm);
    else
      s += ",";
    add("%.4f", m.rms_px);
    s += "," + std::to_string(m.n_used) + "," + std::to_string(m.n_rejected) + "\n";
  }
  return s;
}

std::vector<MethodRow> parse_methods_csv(const std::string& text, const std::string& path) {
  const CsvTable t = parse_csv(text, path);
  const std::size_t c_method = t.column("method"), c_u0 = t.column("u0_px"), c_v0 = t.column("v0_px"),
                    c_f = t.column("f_mm"), c_sx = t.column(parameter_name(CameraParameter::sx)),
                    c_k1 = t.column("k1_per_mm2"), c_sf = t.column("sigma_f_mm"), c_rms = t.column("rms_px"),
                    c_nu = t.column("n_used"), c_nr = t.column("n_rejected");
  std::size_t c_r[3][3], c_t[3];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) c_r[i][j] = t.column("r" + std::to_string(i + 1) + std::to_string(j + 1));
    c_t[i] = t.column(std::string("T") + "xyz"[i] + "_m");
  }
  std::vector<MethodRow> rows;
  for (const CsvRecord& r : t.records) {
    MethodRow m;
    m.method = t.text(r, c_method);
    if (m.method.empty()) throw_input_error(path, r.line, "method", "empty method name");
    m.u0_px = t.number(r, c_u0);
    m.v0_px = t.number(r, c_v0);
    m.f_mm = t.number(r, c_f);
    m.sx = t.number(r, c_sx);
    m.k1_per_mm2 = t.number(r, c_k1);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) m.R(i, j) = t.number(r, c_r[i][j]);
      m.T[i] = t.number(r, c_t[i]);
    }
    m.sigma_f_mm = optional_number(t, r, c_sf);
    m.rms_px = t.number(r, c_rms);
    m.n_used = count_field(t, r, c_nu);
    m.n_rejected = count_field(t, r, c_nr);
    rows.push_back(m);
  }
  return rows;
}

}  // namespace rangecal
