#pragma once
// The flight-planning tests' routes (pipeline/analysis/route_plan.hpp, `rangecal plan`): the demo
// scenario (config/examples/seed002_scenario.json) and vertical ascents of 9 m at 2.5 m/s from 0.8 m,
// so that the unit test and the CLI test plan the same candidates.
#include <nlohmann/json.hpp>
#include <string>

namespace rangecal::test {

/// config/examples/seed002_scenario.json as text.
std::string seed002_scenario_text();

/// Seed 002's layout: three vertical ascents ~64 m from both cameras, standing at different depths
/// (a V seen from the cameras; three ascents in one plane would leave f and depth inseparable).
nlohmann::json three_ascents();

/// The same plus two ascents at other depths, one nearer and one farther along the lines of sight.
nlohmann::json five_ascents();

}  // namespace rangecal::test
