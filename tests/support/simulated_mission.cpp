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

std::string small_two_camera_scenario_text() {
  return R"({
    "seed": 5,
    "start_utc": "2026-05-14T02:30:00Z",
    "site": {"origin": {"lat": 45.6, "lon": 122.8, "h": 150.0}},
    "gnss": {"rate_hz": 10, "noise_sd_m": [0.005, 0.005, 0.008]},
    "lever_arm": {"body_frd_m": [0.0, 0.0, 0.25]},
    "attitude": {"rate_hz": 50, "wobble_deg": 1.0, "yaw_deg": 30},
    "lamp": {"psf_sigma_px": 1.2, "peak": 20000},
    "sky": {"background": 1000, "gradient": [0.5, -0.5], "read_noise": 30},
    "cameras": [
      {"id": "c1", "center_enu_m": [0, -30, 3], "look_at_enu_m": [0, 0, 3], "f_mm": 25,
       "pixel_size_um": 20, "width_px": 200, "height_px": 150, "fps": 100, "export_step": 5},
      {"id": "c2", "center_enu_m": [22, -22, 3], "look_at_enu_m": [0, 0, 3], "f_mm": 25,
       "pixel_size_um": 20, "width_px": 200, "height_px": 150, "fps": 100, "export_step": 5}],
    "routes": [
      {"type": "vertical", "start_enu_m": [-1.2, 0, 1.6], "height_m": 2.8, "speed_mps": 2, "accel_mps2": 2, "hover_s": 0.3},
      {"type": "vertical", "start_enu_m": [0, 0.8, 1.6], "height_m": 2.8, "speed_mps": 2, "accel_mps2": 2, "hover_s": 0.3},
      {"type": "vertical", "start_enu_m": [1.2, 0, 1.6], "height_m": 2.8, "speed_mps": 2, "accel_mps2": 2, "hover_s": 0.3}],
    "poles": [{"id": "P1", "role": "control", "enu_m": [0.5, 0.4, 3.2]},
              {"id": "P2", "role": "check", "enu_m": [-0.6, -0.5, 2.1]}],
    "survey_noise_m": 0.003,
    "pick_noise_px": 0.2
  })";
}

}  // namespace rangecal::test
