#include "pipeline/io/run_outcome.hpp"

#include <fstream>

#include "pipeline/io/output_paths.hpp"
#include "pipeline/io/stage_outputs.hpp"

namespace rangecal {

RunOutcome run_outcome(const nlohmann::json& run_json, const std::string& before_stage) {
  RunOutcome out;
  std::vector<std::string> degradations;
  if (!run_json.is_object() || !run_json.contains("stages") || !run_json["stages"].is_object()) return out;
  const nlohmann::json& stages = run_json["stages"];
  for (const std::string& name : mission_stage_names()) {
    if (name == before_stage) break;
    if (!stages.contains(name) || !stages[name].is_object()) continue;
    const nlohmann::json& s = stages[name];
    if (s.value("status", std::string()) == "failed") {
      const nlohmann::json& e = s.value("error", nlohmann::json::object());
      out.status = "failed";
      out.exit_code = e.is_object() && e.contains("exit_code") && e["exit_code"].is_number_integer()
                          ? e["exit_code"].get<int>()
                          : 1;
      const std::string message = e.is_object() && e.contains("message") && e["message"].is_string()
                                      ? e["message"].get<std::string>()
                                      : "";
      out.reasons.push_back(name + ": failed: " + message);
    }
    if (s.contains("shortfalls") && s["shortfalls"].is_array())
      for (const nlohmann::json& r : s["shortfalls"])
        if (r.is_string()) out.reasons.push_back(name + ": " + r.get<std::string>());
    if (s.contains("degradations") && s["degradations"].is_array())
      for (const nlohmann::json& r : s["degradations"])
        if (r.is_string()) degradations.push_back(name + ": " + r.get<std::string>());
  }
  if (out.status != "failed" && !out.reasons.empty()) {
    out.status = "partial";
    out.exit_code = 4;
  }
  if (out.status == "complete" && !degradations.empty()) out.status = "degraded";
  // A partial or failed run lists what it misses first, then what is degraded.
  out.reasons.insert(out.reasons.end(), degradations.begin(), degradations.end());
  return out;
}

nlohmann::json run_outcome_json(const RunOutcome& outcome) {
  return {{"status", outcome.status}, {"exit_code", outcome.exit_code}, {"reasons", outcome.reasons}};
}

RunOutcome read_run_outcome(const MissionConfig& cfg, const std::string& before_stage) {
  std::ifstream f(mission_output(cfg, kRunJson));
  if (!f) return {};
  return run_outcome(nlohmann::json::parse(f, nullptr, /*allow_exceptions=*/false), before_stage);
}

std::string outcome_reasons_text(const RunOutcome& outcome) {
  std::string s;
  for (const std::string& r : outcome.reasons) s += (s.empty() ? "" : "; ") + r;
  return s;
}

}  // namespace rangecal
