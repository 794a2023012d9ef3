#include "pipeline/stages/mission_runner.hpp"

#include "pipeline/stages/calibrate_stage.hpp"
#include "pipeline/stages/camera_stages.hpp"
#include "pipeline/stages/gnss_stage.hpp"
#include "pipeline/stages/intersect_stage.hpp"
#include "pipeline/stages/report_stage.hpp"

namespace rangecal {

const std::vector<NamedStage>& mission_stages() {
  static const std::vector<NamedStage> stages = {
      {"gnss", run_gnss_stage},           {"align", run_align_stage},         {"detect", run_detect_stage},
      {"calibrate", run_calibrate_stage}, {"intersect", run_intersect_stage}, {"report", run_report_stage},
  };
  return stages;
}

std::vector<StageLog> run_mission(const MissionConfig& cfg,
                                  const std::function<void(const StageLog&)>& on_stage_done) {
  std::vector<StageLog> logs;
  for (const NamedStage& s : mission_stages()) {
    StageLog log = s.run(cfg);
    update_run_log(cfg, log);
    if (on_stage_done) on_stage_done(log);
    logs.push_back(std::move(log));
  }
  return logs;
}

}  // namespace rangecal
