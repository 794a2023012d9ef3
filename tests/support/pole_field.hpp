#pragma once
// The intersect stage's test scene: three seed-002-like cameras (1280×800, 20 µm, 135 mm) ~64 m
// from a field of six check and two control poles, and exact picks of every pole in every camera
// (the intersection's unit tests and its command-line tests).
#include <vector>

#include "pipeline/steps/intersection.hpp"

namespace rangecal::test {

/// The point the cameras look at (ENU m).
inline const Eigen::Vector3d kPoleFieldAim(0, 0, 4);

/// Three cameras ~64 m from the pole field (seed 002 had two; a third checks N > 2 views).
std::vector<Camera> pole_field_cameras();

/// Six check poles A1–A6 and two control poles C1, C2 (true pole tops, ENU m).
std::vector<SurveyedPole> pole_field_truth();

/// Exact picks of every pole in every camera (asserting with GoogleTest that they fall inside the image).
std::vector<IntersectCamera> pole_field_views(const std::vector<SurveyedPole>& poles = pole_field_truth());

}  // namespace rangecal::test
