#include "pipeline/io/network_json.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "config/atomic_file.hpp"
#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/json_view.hpp"

namespace rangecal {
namespace {

/// network.json at `path` parsed by the project's one JSON reader (config/json_view.hpp: its line
/// and column, its nesting bound); rangecal::Error (input) when it is not JSON.
nlohmann::json parse_network_file(const std::string& path) {
  return parse_json_text(read_file_text(path), path, ErrorKind::input);
}

/// A matrix as JSON rows.
nlohmann::json matrix_rows(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index k = 0; k < m.cols(); ++k) row.push_back(m(i, k));
    rows.push_back(row);
  }
  return rows;
}

/// Every camera-pair block (a, b) of the joint covariance `rows` (a network.json matrix over its
/// `cameras`) for the cameras `ids`, each in `parameters`' order when given; empty when a camera is
/// missing, the matrix does not match the cameras, or a camera's parameter set differs (the file is
/// then not the calibration's). nlohmann::json exceptions propagate (the caller names the file).
CrossCovariances camera_blocks(const nlohmann::json& j, const nlohmann::json& rows,
                               const std::vector<std::string>& ids,
                               const std::vector<std::vector<CameraParameter>>* parameters) {
  std::vector<int> offset, size;
  std::vector<std::string> names;
  std::vector<std::vector<std::string>> params;
  int n = 0;
  for (const auto& c : j.at("cameras")) {
    names.push_back(c.at("id").get<std::string>());
    params.push_back(c.at("parameters").get<std::vector<std::string>>());
    offset.push_back(n);
    size.push_back(static_cast<int>(params.back().size()));
    n += size.back();
  }
  if (static_cast<int>(rows.size()) != n) return {};
  std::vector<int> where;
  for (const std::string& id : ids) {
    const auto it = std::find(names.begin(), names.end(), id);
    if (it == names.end()) return {};
    where.push_back(static_cast<int>(it - names.begin()));
  }
  // Row of each wanted parameter within its camera's network block (network order when no
  // parameters are given).
  std::vector<std::vector<int>> pick(ids.size());
  for (std::size_t a = 0; a < ids.size(); ++a) {
    const std::vector<std::string>& have = params[static_cast<std::size_t>(where[a])];
    if (!parameters) {
      for (int r = 0; r < size[where[a]]; ++r) pick[a].push_back(r);
      continue;
    }
    if (parameters->size() != ids.size() || (*parameters)[a].size() != have.size()) return {};
    for (CameraParameter p : (*parameters)[a]) {
      const auto it = std::find(have.begin(), have.end(), std::string(parameter_name(p)));
      if (it == have.end()) return {};
      pick[a].push_back(static_cast<int>(it - have.begin()));
    }
  }
  CrossCovariances x(ids.size(), std::vector<Eigen::MatrixXd>(ids.size()));
  for (std::size_t a = 0; a < ids.size(); ++a)
    for (std::size_t b = 0; b < ids.size(); ++b) {
      const int ca = where[a], cb = where[b];
      Eigen::MatrixXd m(pick[a].size(), pick[b].size());
      for (std::size_t r = 0; r < pick[a].size(); ++r)
        for (std::size_t c = 0; c < pick[b].size(); ++c)
          m(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) =
              rows.at(offset[ca] + pick[a][r]).at(offset[cb] + pick[b][c]).get<double>();
      x[a][b] = m;
    }
  return x;
}

}  // namespace

nlohmann::json ppk_error_estimate_json(const PpkErrorEstimate& e) {
  const auto hv = [](double h, double v) {
    const auto number = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); };
    return nlohmann::json{{"horizontal", number(h)}, {"vertical", number(v)}};
  };
  nlohmann::json j;
  j["method"] = "restricted maximum likelihood";
  j["white_kept"] = e.white;
  j["likelihood_ratio"] = e.likelihood_ratio;
  j["record_s"] = e.record_s;
  j["sd"] = {{"white_scale", hv(e.sd.white_scale_h, e.sd.white_scale_v)},
             {"gauss_markov_sd_m", hv(e.sd.gm_sd_h_m, e.sd.gm_sd_v_m)},
             {"tau_s", hv(e.sd.tau_h_s, e.sd.tau_v_s)}};
  j["gauss_markov_sd_held"] = {{"horizontal", e.gm_sd_held_h}, {"vertical", e.gm_sd_held_v}};
  j["evaluations"] = e.evaluations;
  j["guard_refused"] = e.guard_reasons;
  j["on_bound"] = e.on_bound;
  return j;
}

nlohmann::json image_sigma_json(const NetworkResult& r) {
  const PpkErrorEstimate& e = *r.ppk_estimate;
  nlohmann::json j = nlohmann::json::object();
  for (std::size_t c = 0; c < r.cameras.size() && c < e.image_scale.size(); ++c) {
    // The σ the network weighed by is the centroids' own scatter × √F when they repeat in time.
    const double factor = c < e.image_time_factor.size() ? e.image_time_factor[c] : 1.0;
    const double used = r.cameras[c].details.pixel_sigma_px;
    const double own = used / std::sqrt(factor);
    j[r.cameras[c].calibration.camera_id] = {{"stated_px", own / e.image_scale[c]},
                                             {"estimated_px", own},
                                             {"sd_px", own / e.image_scale[c] * e.image_scale_sd[c]},
                                             {"time_correlation_factor", factor},
                                             {"weighed_px", used}};
  }
  return j;
}

nlohmann::json network_statistics_json(const NetworkResult& r, const std::vector<std::string>& epoch_utc) {
  const NetworkStatistics& s = r.statistics;
  nlohmann::json j;
  j["variance_factor"] = s.variance_factor;
  j["chi2"] = s.chi2;
  j["dof"] = s.dof;
  j["epochs_seen_by_1"] = s.epochs_seen_by_1;
  j["epochs_seen_by_2"] = s.epochs_seen_by_2;
  j["epochs_seen_by_3_or_more"] = s.epochs_seen_by_3_or_more;
  j["float_epochs_used"] = s.float_epochs_used;
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t k : s.ppk_outliers) out.push_back(k < epoch_utc.size() ? epoch_utc[k] : std::to_string(k));
  j["ppk_outliers"] = out;
  j["image_outliers"] = s.image_outliers;
  nlohmann::json alone = nlohmann::json::array();
  for (std::size_t c : s.cameras_alone) alone.push_back(r.cameras[c].calibration.camera_id);
  j["cameras_alone"] = alone;
  j["rank_deficient"] = s.rank_deficient;
  j["ppk_error_model"] = ppk_error_model_json(r.ppk_error, r.gauss_markov_states);
  if (r.gauss_markov_states > 0)
    j["ppk_error_model"]["gauss_markov"]["independent_looks"] = {{"horizontal", s.ppk_looks_h},
                                                                 {"vertical", s.ppk_looks_v}};
  if (r.ppk_estimate) j["ppk_error_model"]["estimate"] = ppk_error_estimate_json(*r.ppk_estimate);
  if (r.ppk_estimate && !r.ppk_estimate->image_scale.empty()) j["image_sigma"] = image_sigma_json(r);
  return j;
}

namespace {

/// ppk_error_estimate_json read back into `r`: the σ (null → NaN: held), what was held or kept.
void read_ppk_error_estimate(const nlohmann::json& e, const std::string& path, const std::string& field,
                             PpkErrorModelRecord* r) {
  if (!e.is_object()) throw_input_error(path, 0, field, "expected an object (the model's estimate)");
  const auto flag = [&](const nlohmann::json& o, const char* k, const std::string& where) {
    if (!o.contains(k) || !o[k].is_boolean())
      throw_input_error(path, 0, where + "." + k, "expected true or false");
    return o[k].get<bool>();
  };
  const auto hv = [&](const nlohmann::json& o, const char* k, double* h, double* v) {
    const std::string where = field + ".sd." + k;
    if (!o.contains(k) || !o[k].is_object()) throw_input_error(path, 0, where, "expected an object");
    for (const auto& [axis, out] : {std::pair<const char*, double*>{"horizontal", h}, {"vertical", v}}) {
      const nlohmann::json& x = o[k].contains(axis) ? o[k][axis] : nlohmann::json();
      if (!x.is_null() && !x.is_number())
        throw_input_error(path, 0, where + "." + axis, "expected a number or null");
      *out = x.is_number() ? x.get<double>() : std::nan("");
    }
  };
  r->estimated = true;
  r->white_kept = flag(e, "white_kept", field);
  if (!e.contains("gauss_markov_sd_held") || !e["gauss_markov_sd_held"].is_object())
    throw_input_error(path, 0, field + ".gauss_markov_sd_held", "expected an object");
  r->gm_sd_held_h = flag(e["gauss_markov_sd_held"], "horizontal", field + ".gauss_markov_sd_held");
  r->gm_sd_held_v = flag(e["gauss_markov_sd_held"], "vertical", field + ".gauss_markov_sd_held");
  if (e.contains("record_s") && e["record_s"].is_number()) r->record_s = e["record_s"].get<double>();
  if (!e.contains("sd") || !e["sd"].is_object())
    throw_input_error(path, 0, field + ".sd", "expected an object");
  PpkErrorModel& s = r->sigma;
  hv(e["sd"], "white_scale", &s.white_scale_h, &s.white_scale_v);
  hv(e["sd"], "gauss_markov_sd_m", &s.gm_sd_h_m, &s.gm_sd_v_m);
  hv(e["sd"], "tau_s", &s.tau_h_s, &s.tau_v_s);
}

}  // namespace

PpkErrorModelRecord parse_ppk_error_model_json(const nlohmann::json& j, const std::string& path,
                                               const std::string& field) {
  if (!j.is_object()) throw_input_error(path, 0, field, "expected an object (the PPK error model)");
  PpkErrorModelRecord r;
  // The values by the model's one reader (gnss/track/ppk_error_model_json.hpp), what a run wrote
  // beside them here.
  r.model = read_ppk_error_model(JsonView(j, path, field, ErrorKind::input));
  // A value's optional σ: {horizontal, vertical} beside it.
  auto sigma = [&](const nlohmann::json& o, const std::string& key, const std::string& name, double* sh,
                   double* sv) {
    if (!o.contains(key) || !o[key].is_object() || !o[key].contains("sigma")) return;
    const nlohmann::json& x = o[key]["sigma"];
    const std::string where = name + "." + key + ".sigma";
    if (!x.is_object()) throw_input_error(path, 0, where, "expected an object");
    for (const auto& [axis, out] : {std::pair<const char*, double*>{"horizontal", sh}, {"vertical", sv}}) {
      if (!x.contains(axis) || !x[axis].is_number())
        throw_input_error(path, 0, where + "." + axis, "expected a number");
      *out = x[axis].get<double>();
    }
  };
  PpkErrorModel& s = r.sigma;
  sigma(j, "white_scale", field, &s.white_scale_h, &s.white_scale_v);
  if (j.contains("estimate")) read_ppk_error_estimate(j["estimate"], path, field + ".estimate", &r);
  if (!j.contains("gauss_markov")) throw_input_error(path, 0, field + ".gauss_markov", "missing");
  const nlohmann::json& gm = j["gauss_markov"];
  if (gm.is_null()) return r;
  const std::string gm_field = field + ".gauss_markov";
  sigma(gm, "sd_m", gm_field, &s.gm_sd_h_m, &s.gm_sd_v_m);
  sigma(gm, "tau_s", gm_field, &s.tau_h_s, &s.tau_v_s);
  if (!gm.contains("states") || !gm["states"].is_number_integer() || gm["states"].get<long>() < 0)
    throw_input_error(path, 0, gm_field + ".states", "expected a non-negative integer");
  r.states = gm["states"].get<long>();
  if (gm.contains("independent_looks")) {
    const nlohmann::json& looks = gm["independent_looks"];
    for (const auto& [axis, out] :
         {std::pair<const char*, double*>{"horizontal", &r.looks_h}, {"vertical", &r.looks_v}}) {
      if (!looks.is_object() || !looks.contains(axis) || !looks[axis].is_number())
        throw_input_error(path, 0, gm_field + ".independent_looks." + axis, "expected a number");
      *out = looks[axis].get<double>();
    }
  }
  return r;
}

NetworkStatisticsRecord parse_network_statistics_json(const nlohmann::json& j, const std::string& path,
                                                      const std::string& field) {
  if (!j.is_object()) throw_input_error(path, 0, field, "expected an object (the network statistics)");
  auto at = [&](const char* key) -> const nlohmann::json& {
    if (!j.contains(key)) throw_input_error(path, 0, field + "." + key, "missing");
    return j[key];
  };
  // nlohmann writes a NaN as null: χ²/dof without redundancy.
  auto number = [&](const char* key) {
    const nlohmann::json& v = at(key);
    if (v.is_null()) return std::nan("");
    if (!v.is_number()) throw_input_error(path, 0, field + "." + key, "expected a number");
    return v.get<double>();
  };
  auto count = [&](const char* key) {
    const nlohmann::json& v = at(key);
    if (!v.is_number_integer() || v.get<long>() < 0)
      throw_input_error(path, 0, field + "." + key, "expected a non-negative integer");
    return v.get<long>();
  };
  auto names = [&](const char* key) {
    const nlohmann::json& v = at(key);
    std::vector<std::string> out;
    if (!v.is_array()) throw_input_error(path, 0, field + "." + key, "expected an array of strings");
    for (const auto& x : v) {
      if (!x.is_string()) throw_input_error(path, 0, field + "." + key, "expected an array of strings");
      out.push_back(x.get<std::string>());
    }
    return out;
  };
  NetworkStatisticsRecord r;
  r.variance_factor = number("variance_factor");
  r.chi2 = number("chi2");
  const nlohmann::json& dof = at("dof");
  if (!dof.is_number_integer()) throw_input_error(path, 0, field + ".dof", "expected an integer");
  r.dof = dof.get<long>();
  r.epochs_seen_by_1 = count("epochs_seen_by_1");
  r.epochs_seen_by_2 = count("epochs_seen_by_2");
  r.epochs_seen_by_3_or_more = count("epochs_seen_by_3_or_more");
  r.float_epochs_used = count("float_epochs_used");
  r.ppk_outliers = names("ppk_outliers");
  r.image_outliers = count("image_outliers");
  r.cameras_alone = names("cameras_alone");
  const nlohmann::json& rank = at("rank_deficient");
  if (!rank.is_boolean()) throw_input_error(path, 0, field + ".rank_deficient", "expected true or false");
  r.rank_deficient = rank.get<bool>();
  if (j.contains("ppk_error_model"))
    r.ppk_error_model = parse_ppk_error_model_json(j["ppk_error_model"], path, field + ".ppk_error_model");
  return r;
}

nlohmann::json network_json(const NetworkResult& r, const std::vector<std::string>& epoch_utc) {
  nlohmann::json j;
  j["method"] = "network";
  nlohmann::json cams = nlohmann::json::array();
  for (const BundleResult& c : r.cameras)
    cams.push_back(
        {{"id", c.calibration.camera_id}, {"parameters", parameter_names(c.calibration.parameters)}});
  j["cameras"] = cams;
  j["joint_covariance"] = matrix_rows(r.joint_covariance);
  j["statistics"] = network_statistics_json(r, epoch_utc);
  if (r.datum_floor_covariance.size() > 0)
    j["datum_floor"] = {{"image_factor", r.datum_floor_image_factor},
                        {"joint_covariance", matrix_rows(r.datum_floor_covariance)}};
  const FloatEpochContribution& f = r.float_epochs;
  if (f.epochs > 0) {
    auto list = [](const Eigen::VectorXd& v) {
      if (v.size() == 0) return nlohmann::json(nullptr);
      return nlohmann::json(std::vector<double>(v.data(), v.data() + v.size()));
    };
    nlohmann::json fc = nlohmann::json::array();
    for (std::size_t c = 0; c < r.cameras.size() && c < f.sigma_with.size(); ++c)
      fc.push_back(
          {{"id", r.cameras[c].calibration.camera_id},
           {"parameters", parameter_names(r.cameras[c].calibration.parameters)},
           {"sigma_with", list(f.sigma_with[c])},
           {"sigma_without", list(c < f.sigma_without.size() ? f.sigma_without[c] : Eigen::VectorXd())}});
    j["float_epochs"] = {{"epochs", f.epochs}, {"cameras", fc}};
  }
  return j;
}

std::optional<PpkErrorModelRecord> read_network_ppk_error_model(const std::string& path) {
  if (!std::filesystem::exists(path)) return std::nullopt;
  const nlohmann::json j = parse_network_file(path);
  if (!j.is_object() || !j.contains("statistics") || !j["statistics"].is_object() ||
      !j["statistics"].contains("ppk_error_model"))
    return std::nullopt;
  return parse_ppk_error_model_json(j["statistics"]["ppk_error_model"], path, "statistics.ppk_error_model");
}

std::map<std::string, double> read_network_image_sigma(const std::string& path) {
  std::map<std::string, double> out;
  if (!std::filesystem::exists(path)) return out;
  const nlohmann::json j = parse_network_file(path);
  if (!j.is_object() || !j.contains("statistics") || !j["statistics"].is_object() ||
      !j["statistics"].contains("image_sigma"))
    return out;
  const nlohmann::json& s = j["statistics"]["image_sigma"];
  if (!s.is_object()) throw_input_error(path, 0, "statistics.image_sigma", "expected an object");
  for (const auto& [id, v] : s.items()) {
    const std::string field = "statistics.image_sigma." + id + ".estimated_px";
    if (!v.is_object() || !v.contains("estimated_px") || !v["estimated_px"].is_number() ||
        !(v["estimated_px"].get<double>() > 0))
      throw_input_error(path, 0, field, "expected a positive number (px)");
    out[id] = v["estimated_px"].get<double>();
  }
  return out;
}

std::optional<FloatEpochsRecord> read_network_float_epochs(const std::string& path) {
  if (!std::filesystem::exists(path)) return std::nullopt;
  const nlohmann::json j = parse_network_file(path);
  if (!j.is_object() || !j.contains("float_epochs")) return std::nullopt;
  const nlohmann::json& f = j["float_epochs"];
  auto bad = [&](const std::string& field, const std::string& why) {
    throw_input_error(path, 0, field, why);
  };
  if (!f.is_object()) bad("float_epochs", "expected an object");
  if (!f.contains("epochs") || !f["epochs"].is_number_integer() || f["epochs"].get<long>() < 0)
    bad("float_epochs.epochs", "expected a non-negative integer");
  if (!f.contains("cameras") || !f["cameras"].is_array()) bad("float_epochs.cameras", "expected an array");
  FloatEpochsRecord r;
  r.epochs = f["epochs"].get<long>();
  for (std::size_t c = 0; c < f["cameras"].size(); ++c) {
    const nlohmann::json& cj = f["cameras"][c];
    const std::string at = "float_epochs.cameras[" + std::to_string(c) + "]";
    if (!cj.is_object() || !cj.contains("id") || !cj["id"].is_string()) bad(at + ".id", "expected a string");
    FloatEpochsRecord::Camera cam;
    cam.id = cj["id"].get<std::string>();
    if (!cj.contains("parameters") || !cj["parameters"].is_array())
      bad(at + ".parameters", "expected an array");
    for (const auto& n : cj["parameters"]) {
      const std::optional<CameraParameter> p =
          n.is_string() ? parameter_from_name(n.get<std::string>()) : std::nullopt;
      if (!p) bad(at + ".parameters", "expected camera parameter names");
      cam.parameters.push_back(*p);
    }
    auto sigmas = [&](const char* key, bool may_be_null) {
      std::vector<double> v;
      if (!cj.contains(key)) bad(at + "." + key, "missing");
      const nlohmann::json& a = cj[key];
      if (a.is_null() && may_be_null) return v;
      if (!a.is_array() || a.size() != cam.parameters.size())
        bad(at + "." + key, "expected one σ per parameter (" + std::to_string(cam.parameters.size()) + ")");
      for (const auto& x : a) {
        if (!x.is_number() || !(x.get<double>() >= 0)) bad(at + "." + key, "expected σ ≥ 0");
        v.push_back(x.get<double>());
      }
      return v;
    };
    cam.sigma_with = sigmas("sigma_with", false);
    cam.sigma_without = sigmas("sigma_without", true);
    r.cameras.push_back(std::move(cam));
  }
  return r;
}

void write_network_json(const std::string& path, const nlohmann::json& j) {
  write_file_atomic(path, j.dump(2) + "\n");
}

CrossCovariances read_network_cross_covariances(const std::string& path, const std::vector<std::string>& ids,
                                                const std::vector<std::vector<CameraParameter>>* parameters) {
  if (!std::filesystem::exists(path)) return {};
  const nlohmann::json j = parse_network_file(path);
  try {
    CrossCovariances x = camera_blocks(j, j.at("joint_covariance"), ids, parameters);
    for (std::size_t a = 0; a < x.size(); ++a) x[a][a] = Eigen::MatrixXd();  // each calibration.json's own
    return x;
  } catch (const nlohmann::json::exception& e) {
    throw_input_error(path, 0, "", std::string("malformed network.json: ") + e.what());
  }
}

std::optional<NetworkDatumFloor> read_network_datum_floor(
    const std::string& path, const std::vector<std::string>& ids,
    const std::vector<std::vector<CameraParameter>>* parameters) {
  if (!std::filesystem::exists(path)) return std::nullopt;
  const nlohmann::json j = parse_network_file(path);
  if (!j.is_object() || !j.contains("datum_floor")) return std::nullopt;
  const nlohmann::json& f = j["datum_floor"];
  if (!f.is_object()) throw_input_error(path, 0, "datum_floor", "expected an object");
  if (!f.contains("image_factor") || !f["image_factor"].is_number() || !(f["image_factor"].get<double>() > 1))
    throw_input_error(path, 0, "datum_floor.image_factor", "expected a number above 1");
  if (!f.contains("joint_covariance") || !f["joint_covariance"].is_array())
    throw_input_error(path, 0, "datum_floor.joint_covariance", "expected an array of rows");
  NetworkDatumFloor d;
  d.image_factor = f["image_factor"].get<double>();
  try {
    d.blocks = camera_blocks(j, f["joint_covariance"], ids, parameters);
  } catch (const nlohmann::json::exception& e) {
    throw_input_error(path, 0, "datum_floor.joint_covariance", std::string("malformed: ") + e.what());
  }
  if (d.blocks.empty()) return std::nullopt;
  for (std::size_t a = 0; a < d.blocks.size(); ++a)
    if (!d.blocks[a][a].allFinite() || (d.blocks[a][a].diagonal().array() < 0).any())
      throw_input_error(path, 0, "datum_floor.joint_covariance",
                        "camera '" + ids[a] + "': expected finite variances ≥ 0 on the diagonal");
  return d;
}

}  // namespace rangecal
