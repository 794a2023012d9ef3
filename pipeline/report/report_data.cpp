#include "pipeline/report/report_data.hpp"

#include <algorithm>
#include <filesystem>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/json_view.hpp"
#include "gnss/formats/lamp_track_csv.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/io/calibration_json.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;

std::string join(const std::string& dir, const std::string& a, const std::string& b = "") {
  fs::path p = fs::path(dir) / a;
  if (!b.empty()) p /= b;
  return p.string();
}

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

// run.json: version, config hash, warnings per stage and the calibrate stage's failure reasons.
void read_run_json(const std::string& path, ReportData* data,
                   std::vector<std::pair<std::string, std::string>>* failures) {
  const nlohmann::json doc = parse_json_text(read_file_text(path), path, ErrorKind::input);
  if (!doc.is_object()) throw_input_error(path, 0, "", "expected a JSON object (run.json)");
  if (doc.contains("program") && doc["program"].is_object() && doc["program"].contains("version") &&
      doc["program"]["version"].is_string())
    data->program_version = doc["program"]["version"].get<std::string>();
  if (doc.contains("config") && doc["config"].is_object() && doc["config"].contains("sha256") &&
      doc["config"]["sha256"].is_string())
    data->config_sha256 = doc["config"]["sha256"].get<std::string>();
  if (!doc.contains("stages")) return;
  const nlohmann::json& stages = doc["stages"];
  if (!stages.is_object()) throw_input_error(path, 0, "stages", "expected an object");
  for (const auto& [name, stage] : stages.items()) {
    if (name == "report") continue;  // the report's own warnings are of the previous report run
    if (!stage.is_object()) throw_input_error(path, 0, "stages." + name, "expected an object");
    StageWarnings sw;
    sw.stage = name;
    if (stage.contains("warnings")) {
      const nlohmann::json& w = stage["warnings"];
      if (!w.is_array()) throw_input_error(path, 0, "stages." + name + ".warnings", "expected an array");
      for (const auto& s : w) {
        if (!s.is_string())
          throw_input_error(path, 0, "stages." + name + ".warnings", "expected an array of strings");
        sw.warnings.push_back(s.get<std::string>());
      }
    }
    data->stage_warnings.push_back(sw);
    if (name == "calibrate" && stage.contains("counts") && stage["counts"].is_object())
      for (const auto& [cam, c] : stage["counts"].items())
        if (c.is_object() && c.contains("failed") && c["failed"].is_string())
          failures->emplace_back(cam, c["failed"].get<std::string>());
  }
}

}  // namespace

std::vector<MethodRow> parse_methods_csv(const std::string& text, const std::string& path) {
  const CsvTable t = parse_csv(text, path);
  const std::size_t c_method = t.column("method"), c_u0 = t.column("u0_px"), c_v0 = t.column("v0_px"),
                    c_f = t.column("f_mm"), c_sx = t.column("sx"), c_k1 = t.column("k1_per_mm2"),
                    c_sf = t.column("sigma_f_mm"), c_rms = t.column("rms_px"), c_nu = t.column("n_used"),
                    c_nr = t.column("n_rejected");
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

ReportData read_report_data(const std::string& output_dir, const std::string& mission,
                            const std::vector<std::string>& camera_ids) {
  ReportData data;
  data.mission = mission;

  std::vector<std::pair<std::string, std::string>> failures;
  const std::string run_json = join(output_dir, "run.json");
  if (fs::exists(run_json)) read_run_json(run_json, &data, &failures);

  const std::string track = join(output_dir, "gnss", "lamp_track.csv");
  if (fs::exists(track)) {
    const LampTrack t = read_lamp_track_csv(track);
    LampTrackSummary s;
    s.epochs = t.epochs.size();
    s.start = t.epochs.front().utc;  // the reader rejects a track without epochs
    s.end = t.epochs.back().utc;
    data.track = s;
  }

  for (const std::string& id : camera_ids) {
    CameraReportData cam;
    cam.id = id;
    const std::string cal = join(output_dir, id, kCalibrationJson);
    if (fs::exists(cal)) {
      cam.calibration = read_calibration_json(cal);
      cam.width_px = cam.calibration->camera.intr.width_px;
      cam.height_px = cam.calibration->camera.intr.height_px;
    }
    const std::string corr = join(output_dir, id, kCorrespondencesCsv);
    if (fs::exists(corr)) cam.pairs = read_correspondences_csv(corr);
    const std::string methods = join(output_dir, id, kMethodsCsv);
    if (fs::exists(methods)) cam.methods = parse_methods_csv(read_file_text(methods), methods);
    for (const auto& [fid, why] : failures)
      if (fid == id) cam.calibration_failure = why;
    data.cameras.push_back(std::move(cam));
  }

  const std::string inter = join(output_dir, "intersection.csv");
  if (fs::exists(inter)) data.intersection = read_intersection_csv(inter);
  return data;
}

}  // namespace rangecal
