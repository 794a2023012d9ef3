#include "pipeline/io/run_log.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "config/atomic_file.hpp"
#include "pipeline/io/output_paths.hpp"

namespace rangecal {

void update_run_log(const MissionConfig& cfg, const StageLog& log) {
  const std::string path = mission_output(cfg, kRunJson);
  nlohmann::json j = nlohmann::json::object();
  {
    std::ifstream f(path);
    if (f) {
      // A run.json we cannot parse (e.g. edited by hand) is replaced rather than trusted.
      j = nlohmann::json::parse(f, nullptr, /*allow_exceptions=*/false);
      if (!j.is_object()) j = nlohmann::json::object();
    }
  }
  j["program"] = {{"name", "rangecal"}, {"version", RANGECAL_VERSION}};
  j["config"] = {{"path", cfg.config_path}, {"sha256", cfg.config_sha256}};
  nlohmann::json stage;
  stage["wall_time_s"] = std::round(log.wall_time_s * 1000.0) / 1000.0;
  stage["counts"] = log.counts;
  stage["warnings"] = log.warnings;
  j["stages"][log.stage] = stage;
  // All warnings of all stages in one list, for a reader who only looks there.
  nlohmann::json all = nlohmann::json::array();
  for (const auto& [name, s] : j["stages"].items())
    for (const auto& w : s["warnings"]) all.push_back(name + ": " + w.get<std::string>());
  j["warnings"] = all;
  write_file_atomic(path, j.dump(2) + "\n");
}

}  // namespace rangecal
