#include "pipeline/stages/mission_runner.hpp"

#include <chrono>
#include <iterator>
#include <stdexcept>

#include "config/atomic_file.hpp"
#include "config/error.hpp"
#include "pipeline/io/stage_outputs.hpp"
#include "pipeline/stages/align_stage.hpp"
#include "pipeline/stages/calibrate_stage.hpp"
#include "pipeline/stages/detect_stage.hpp"
#include "pipeline/stages/gnss_stage.hpp"
#include "pipeline/stages/intersect_stage.hpp"
#include "pipeline/stages/report_stage.hpp"
#include "pipeline/stages/trajectory_stage.hpp"

namespace rangecal {

namespace {

using StageFunction = StageLog (*)(const MissionConfig&);

/// The function that runs each row of mission_stage_table() (pipeline/io/stage_outputs.hpp), by
/// its name: the table, below the stages, holds the order and the outputs; only this layer may
/// name the functions.
struct StageRunner {
  const char* name;
  StageFunction run;
};
constexpr StageRunner kStageRunners[] = {
    {"gnss", run_gnss_stage},           {"align", run_align_stage},
    {"detect", run_detect_stage},       {"calibrate", run_calibrate_stage},
    {"intersect", run_intersect_stage}, {"trajectory", run_trajectory_stage},
    {"report", run_report_stage},
};

StageFunction stage_function(const std::string& name) {
  for (const StageRunner& r : kStageRunners)
    if (name == r.name) return r.run;
  throw std::logic_error("no function runs the stage '" + name + "'");
}

}  // namespace

const std::vector<NamedStage>& mission_stages() {
  static const std::vector<NamedStage> stages = [] {
    std::vector<NamedStage> v;
    for (const MissionStage& s : mission_stage_table()) v.push_back({s.name, stage_function(s.name)});
    if (v.size() != std::size(kStageRunners))
      throw std::logic_error("a stage function is bound to no stage of the table");
    return v;
  }();
  return stages;
}

StageLog run_stage(const std::string& name, const MissionConfig& cfg) {
  for (const NamedStage& s : mission_stages()) {
    if (s.name != name) continue;
    remove_dead_temp_files(cfg.output_dir);
    // This stage's previous outputs and the later stages' would describe older inputs: remove them
    // before anything can fail, so that no old file is ever taken for a product of this run.
    const std::vector<std::string> removed = remove_outputs_from_stage(cfg, name);
    const auto t0 = std::chrono::steady_clock::now();
    const auto elapsed = [&] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    StageLog log;
    try {
      log = s.run(cfg);
    } catch (const Error& e) {
      StageLog failed = failed_stage_log(name, e);
      failed.wall_time_s = elapsed();
      failed.removed_outputs = removed;
      update_run_log(cfg, failed);
      throw;
    }
    log.stage = name;
    log.wall_time_s = elapsed();
    log.removed_outputs = removed;
    update_run_log(cfg, log);
    return log;
  }
  throw Error(ErrorKind::usage, "", 0, "stage", "unknown stage '" + name + "'");
}

std::vector<StageLog> run_mission(const MissionConfig& cfg,
                                  const std::function<void(const StageLog&)>& on_stage_done) {
  std::vector<StageLog> logs;
  for (const NamedStage& s : mission_stages()) {
    StageLog log = run_stage(s.name, cfg);
    if (on_stage_done) on_stage_done(log);
    logs.push_back(std::move(log));
  }
  return logs;
}

}  // namespace rangecal
