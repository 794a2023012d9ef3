#pragma once
// One calibration observation: a known world point and the pixel where the camera saw it.
// World units are the caller's (rangecal uses ENU metres; the Tsai/Zhang/Heikkilä reference data
// use mm or inches) — every initialiser returns T in the same units. Pixels follow docs/conventions.md:
// u right, v down, centre of the top-left pixel at (0, 0).
#include <Eigen/Core>

namespace rangecal {

struct PointCorrespondence {
  Eigen::Vector3d world = Eigen::Vector3d::Zero();  ///< world point (ENU m, or the data's unit)
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  ///< observed pixel (u, v)
};

}  // namespace rangecal
