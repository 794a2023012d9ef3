#pragma once
// A small simulator scenario (docs/simulator.md) for the simulator's unit tests and the simulate
// command's test: one camera looking north at a 4 m vertical ascent 30 m away, 200×150 px frames at
// 100 fps, every 5th exported; site origin 45.6° N, 122.8° E, 150 m.
#include <nlohmann/json.hpp>

namespace rangecal::test {

/// The scenario's JSON (seed 11).
nlohmann::json tiny_scenario();

}  // namespace rangecal::test
