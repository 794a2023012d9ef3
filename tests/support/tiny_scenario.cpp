#include "support/tiny_scenario.hpp"

namespace rangecal::test {

nlohmann::json tiny_scenario() {
  return nlohmann::json::parse(R"({
    "seed": 11,
    "start_utc": "2026-05-14T02:30:00Z",
    "site": {"origin": {"lat": 45.6, "lon": 122.8, "h": 150.0}},
    "gnss": {"rate_hz": 10, "noise_sd_m": [0.01, 0.01, 0.015]},
    "lever_arm": {"body_frd_m": [0.0, 0.0, 0.25]},
    "attitude": {"rate_hz": 50, "wobble_deg": 1.5, "yaw_deg": 30},
    "lamp": {"psf_sigma_px": 1.2, "peak": 20000},
    "sky": {"background": 1000, "gradient": [0.5, -0.5], "read_noise": 30},
    "cameras": [{"id": "c1", "center_enu_m": [0, -30, 3], "look_at_enu_m": [0, 0, 3], "f_mm": 25,
                 "pixel_size_um": 20, "width_px": 200, "height_px": 150, "u0_px": 101.5, "v0_px": 73.25,
                 "sx": 1.01, "fps": 100, "export_step": 5, "clock_offset_s": 0.0021}],
    "routes": [{"type": "vertical", "start_enu_m": [0, 0, 1.5], "height_m": 3, "speed_mps": 2,
                "accel_mps2": 2, "hover_s": 0.5}],
    "poles": [{"id": "P1", "role": "control", "enu_m": [0.5, 1.0, 3.2]},
              {"id": "P2", "role": "check", "enu_m": [-0.8, -1.0, 2.1]},
              {"id": "FAR", "role": "check", "enu_m": [40, 0, 2]}],
    "survey_noise_m": 0.004,
    "pick_noise_px": 0.2
  })");
}

}  // namespace rangecal::test
