#pragma once
// The built-in demo scenario (docs/cli.md `rangecal demo`): the text of
// config/examples/demo_scenario.json, compiled in by CMake (generated/demo_scenario_text.cpp).

namespace rangecal {

/// The scenario JSON text (seed 002's experiment: two 1280×800 cameras, 135 mm, ~64 m, three
/// ascents at different depths, PPK noise ≈ 1 cm, control and check poles).
const char* demo_scenario_json();

}  // namespace rangecal
