#pragma once
// Whole simulated missions for the end-to-end tests: a scenario simulated into a scratch folder and
// run through every stage (pipeline/demo/demo.hpp simulate_and_run), and copies of a mission's input
// files for variants (a lever arm ignored, time stamps shifted, frames blanked, …).
#include <filesystem>
#include <string>

#include "pipeline/demo/demo.hpp"
#include "pipeline/simulate/scenario.hpp"

namespace rangecal::test {

struct SimulatedRun {
  std::filesystem::path dir;  ///< scratch folder; the mission is in dir/"mission", outputs in its out/
  DemoRun run;
};

/// Simulates `scenario` into <scratch "name">/mission and runs every stage on the written files.
SimulatedRun simulate_and_run_in_scratch(const Scenario& scenario, const std::string& name);

/// A small two-camera scenario (JSON text) that simulates and runs in seconds: two 200×150
/// cameras 30 m from three 3 m vertical ascents, a control and a check pole.
std::string small_two_camera_scenario_text();

/// Copies a mission folder's inputs — everything but its out/ folder — to `dst`, emptied first.
void copy_mission_inputs(const std::filesystem::path& src, const std::filesystem::path& dst);

}  // namespace rangecal::test
