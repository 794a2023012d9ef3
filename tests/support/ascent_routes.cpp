#include "support/ascent_routes.hpp"

#include "support/paths.hpp"

namespace rangecal::test {

std::string seed002_scenario_text() {
  return read_text(source_dir() / "config/examples/seed002_scenario.json");
}

namespace {

// A vertical ascent from (e, n, 0.8) m ENU.
nlohmann::json ascent(double e, double n) {
  return {{"type", "vertical"}, {"start_enu_m", {e, n, 0.8}}, {"height_m", 9.0},
          {"speed_mps", 2.5},   {"accel_mps2", 1.5},          {"hover_s", 0.5}};
}

}  // namespace

nlohmann::json three_ascents() {
  return nlohmann::json::array({ascent(-5, 0.75), ascent(0, 4.75), ascent(5, 0.75)});
}

nlohmann::json five_ascents() {
  return nlohmann::json::array(
      {ascent(-5, 0.75), ascent(0, 4.75), ascent(5, 0.75), ascent(0, -3.25), ascent(0, 8.75)});
}

}  // namespace rangecal::test
