#include "support/simulated_mission.hpp"

#include "support/paths.hpp"

namespace rangecal::test {

SimulatedRun simulate_and_run_in_scratch(const Scenario& scenario, const std::string& name) {
  SimulatedRun r;
  r.dir = scratch_dir(name);
  r.run = simulate_and_run(scenario, (r.dir / "mission").string());
  return r;
}

void copy_mission_inputs(const std::filesystem::path& src, const std::filesystem::path& dst) {
  namespace fs = std::filesystem;
  fs::remove_all(dst);
  fs::create_directories(dst);
  for (const auto& e : fs::directory_iterator(src))
    if (e.path().filename() != "out")
      fs::copy(e.path(), dst / e.path().filename(), fs::copy_options::recursive);
}

}  // namespace rangecal::test
