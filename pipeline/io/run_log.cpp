#include "pipeline/io/run_log.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "config/atomic_file.hpp"
#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/json_view.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/io/run_outcome.hpp"
#include "pipeline/io/stage_outputs.hpp"

namespace rangecal {

StageLog failed_stage_log(const std::string& stage, const Error& e) {
  StageLog log;
  log.stage = stage;
  log.failed = true;
  log.error = {{"message", e.what()},
               {"exit_code", e.exit_code()},
               {"file", e.file()},
               {"line", e.line()},
               {"field", e.field()}};
  return log;
}

void update_run_log(const MissionConfig& cfg, const StageLog& log) {
  const std::string path = mission_output(cfg, kRunJson);
  nlohmann::json j = nlohmann::json::object();
  if (std::filesystem::exists(path)) {
    // A run.json we cannot parse (e.g. edited by hand) is replaced rather than trusted; the project's
    // reader also refuses nesting that nlohmann's dump below would recurse through until the stack
    // overflows (config/json_view.hpp kMaxJsonNesting).
    try {
      j = parse_json_text(read_file_text(path), path, ErrorKind::input);
    } catch (const Error&) {
      j = nlohmann::json::object();
    }
    if (!j.is_object()) j = nlohmann::json::object();
  }
  j["program"] = {{"name", "rangecal"}, {"version", RANGECAL_VERSION}};
  j["config"] = {{"path", cfg.config_path}, {"sha256", cfg.config_sha256}};
  nlohmann::json stage;
  stage["status"] = log.failed ? "failed" : "ok";
  if (log.failed) stage["error"] = log.error;
  stage["config_sha256"] = cfg.config_sha256;
  stage["wall_time_s"] = std::round(log.wall_time_s * 1000.0) / 1000.0;
  stage["counts"] = log.counts;
  stage["warnings"] = log.warnings;
  if (!log.shortfalls.empty()) stage["shortfalls"] = log.shortfalls;
  if (!log.degradations.empty()) stage["degradations"] = log.degradations;
  stage["removed_outputs"] = log.removed_outputs.size();
  if (!j["stages"].is_object()) j["stages"] = nlohmann::json::object();
  j["stages"][log.stage] = stage;
  // The later stages' outputs went with this stage's: their sections describe nothing any more.
  const auto& names = mission_stage_names();
  for (auto it = std::find(names.begin(), names.end(), log.stage); it != names.end(); ++it)
    if (*it != log.stage) j["stages"].erase(*it);
  std::string failed;
  for (const auto& [name, s] : j["stages"].items())
    if (s.is_object() && s.contains("status") && s["status"] == "failed") failed = name;
  j["status"] = failed.empty() ? "ok" : "failed";
  if (failed.empty())
    j.erase("failed_stage");
  else
    j["failed_stage"] = failed;
  // All warnings of all stages in one list, for a reader who only looks there.
  nlohmann::json all = nlohmann::json::array();
  for (const auto& [name, s] : j["stages"].items())
    if (s.is_object() && s.contains("warnings") && s["warnings"].is_array())
      for (const auto& w : s["warnings"])
        if (w.is_string()) all.push_back(name + ": " + w.get<std::string>());
  j["warnings"] = all;
  j["outcome"] = run_outcome_json(run_outcome(j));
  // Messages may quote bytes from bad input that are not UTF-8: replaced (U+FFFD), never a throw.
  write_file_atomic(path, j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

}  // namespace rangecal
