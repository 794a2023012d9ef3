#pragma once
// Whether a network's σ hold, over many simulated missions (docs/accuracy_analysis.md "Correlated PPK
// errors"): each mission's calibration-only intersection error over the flight volume against the
// intersection σ the network predicts from its joint covariance (cross-camera blocks included), the
// correlated Cramér–Rao bound's, and the z-scores of f and the camera centres
// (tests/support/correlated_crb.hpp).
#include <Eigen/Core>
#include <vector>

#include "support/correlated_crb.hpp"

namespace rangecal::test {

/// The figures of a Monte Carlo over missions of a CrbNetwork.
struct HonestyFigures {
  double actual_m = 0;     ///< rms over missions of the calibration-only intersection error
  double predicted_m = 0;  ///< rms over missions of the intersection σ the network predicts
  double bound_m = 0;      ///< the correlated Cramér–Rao bound's intersection σ
  double z_rms = 0;        ///< rms z-score of f and the camera centres
  double z_worst = 0;      ///< the largest |z|
  int missions = 0;
  int z_count = 0;
};

/// Adds one mission's network result `r` on `n` (`bound` gives the parameters' order, `volume` the
/// intersection points) to `f`'s sums.
void add_mission(const CrbNetwork& n, const NetworkResult& r, const CameraJointCovariance& bound,
                 const std::vector<Eigen::Vector3d>& volume, HonestyFigures* f);

/// The sums of `f` into its rms figures, with the bound's intersection σ.
void finish(const CrbNetwork& n, const CameraJointCovariance& bound,
            const std::vector<Eigen::Vector3d>& volume, HonestyFigures* f);

/// One line of figures, named `what`.
void print(const char* what, const HonestyFigures& f);

}  // namespace rangecal::test
