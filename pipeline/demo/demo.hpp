#pragma once
// `rangecal demo` (docs/cli.md): simulate a scenario (by default the built-in one mirroring
// seed 002's experiment), run every stage on the written files as `rangecal run` would, and
// gather the results beside the simulated truth for the printed tables (pipeline/demo/demo_tables.hpp).
#include <functional>
#include <string>
#include <vector>

#include "pipeline/demo/demo_tables.hpp"
#include "pipeline/io/run_log.hpp"
#include "pipeline/mission/mission_config.hpp"
#include "pipeline/simulate/mission_simulator.hpp"

namespace rangecal {

struct DemoResults {
  /// The method of calibration.json: calibrate.method, or the stage's default choice (network
  /// when the cameras share epochs, docs/config.md).
  std::string method;
  std::vector<DemoCamera> cameras;
  /// Check-pole intersection with the cameras of each method that calibrated every camera with
  /// picks: the main method first, then `bundle` when the main is the network, then the `compare`
  /// methods in config order.
  std::vector<DemoIntersection> intersections;
};

/// Reads a finished run's outputs (calibration.json and calibration_<method>.json of every
/// camera, pole picks, survey) and compares them with the simulated truth `m`. Throws
/// rangecal::Error when an output is missing or malformed.
DemoResults collect_demo_results(const SimMission& m, const MissionConfig& cfg);

struct DemoRun {
  SimMission mission;
  MissionConfig config;
  std::vector<StageLog> logs;
  DemoResults results;
};

/// Simulates `scenario` into `out_dir` (mission files, truth.json, outputs under out_dir/out),
/// runs every stage and collects the results. `progress` (may be empty) gets one line per step.
DemoRun simulate_and_run(const Scenario& scenario, const std::string& out_dir,
                         const std::function<void(const std::string&)>& progress = {});

}  // namespace rangecal
