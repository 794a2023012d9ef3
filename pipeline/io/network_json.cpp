#include "pipeline/io/network_json.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "config/atomic_file.hpp"
#include "config/error.hpp"

namespace rangecal {

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
  return j;
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
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < r.joint_covariance.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index k = 0; k < r.joint_covariance.cols(); ++k) row.push_back(r.joint_covariance(i, k));
    rows.push_back(row);
  }
  j["joint_covariance"] = rows;
  j["statistics"] = network_statistics_json(r, epoch_utc);
  return j;
}

void write_network_json(const std::string& path, const nlohmann::json& j) {
  write_file_atomic(path, j.dump(2) + "\n");
}

CrossCovariances read_network_cross_covariances(const std::string& path, const std::vector<std::string>& ids,
                                                const std::vector<std::vector<CameraParameter>>* parameters) {
  if (!std::filesystem::exists(path)) return {};
  std::ifstream in(path);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw_input_error(path, 0, "", std::string("not valid JSON: ") + e.what());
  }
  try {
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
    const auto& rows = j.at("joint_covariance");
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
        if (a == b) continue;
        const int ca = where[a], cb = where[b];
        Eigen::MatrixXd m(pick[a].size(), pick[b].size());
        for (std::size_t r = 0; r < pick[a].size(); ++r)
          for (std::size_t c = 0; c < pick[b].size(); ++c)
            m(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) =
                rows.at(offset[ca] + pick[a][r]).at(offset[cb] + pick[b][c]).get<double>();
        x[a][b] = m;
      }
    return x;
  } catch (const nlohmann::json::exception& e) {
    throw_input_error(path, 0, "", std::string("malformed network.json: ") + e.what());
  }
}

}  // namespace rangecal
