#pragma once
// How much a camera's image residuals repeat themselves in time (docs/optimisation.md "Image
// residuals correlated in time"). The image variance components count every centroid as an
// independent look; a label or centroid error that persists over seconds (a hand label's bias, a
// rolling shutter, a lens misfit that moves slowly across the frame as the lamp does) makes n
// residuals worth n / F independent ones, F the variance inflation of the series' mean:
//   F = 1 + 2 Σ_{k=1}^{K} (1 − k/(K+1)) ρ_k
// (Bartlett's window over the lag-k autocorrelations ρ_k; Newey & West 1987), or, when larger, the
// first-order autoregression's (1 + ρ_1)/(1 − ρ_1): the window cuts a persistent series short (an
// AR(1) of φ 0.9 per lag: 11.1 through 20 lags of its 19; on simulated missions the σ then held
// 30 % short), while an error that is partly white and partly persistent has a small ρ_1 and a long
// tail only the window sees. The network weighs such
// a camera by σ·√F: its parameters' covariance then carries the correlated part, and the camera no
// longer pulls the lamp track off the fixes by more than its independent looks allow.
// The series is each epoch's residuals with the point's own three directions projected out
// (r − J (JᵀJ)⁻¹ Jᵀ r, whitened, J = ∂(pixels)/∂X over the cameras that saw it): what no position of
// the lamp can explain. The adjusted position carries the fix's slow PPK error, which the model
// already has; left in, it would make white centroids look correlated.
#include <cstddef>
#include <vector>

#include "optim/network/network_observation.hpp"
#include "optim/network/network_result.hpp"

namespace rangecal {

/// Lags the window spans (K above): at the lamp track's usual 2–20 Hz, 1–10 s.
inline constexpr int kCorrelationLags = 20;
/// A camera needs this many used lamp residuals with a time for its F to be measured; fewer: F = 1.
inline constexpr std::size_t kCorrelationMinResiduals = 60;
/// F is taken as 1 unless it exceeds 1 by this many of the sd the window's estimate has for white
/// residuals, √(2K/(3n)) over n residuals (Priestley 1981 §6.2.3).
inline constexpr double kCorrelationFloorSds = 3;
/// Two residuals are k lags apart only when their times are within (k + 1/2) median steps: a gap in
/// the track (the camera's held-out blocks, a dropped stretch) does not join distant epochs.
inline constexpr double kLagGapTolerance = 0.5;

/// Per camera (network order), F of its used lamp residuals at epochs (points with a time) that
/// two or more cameras saw, the point's directions projected out as above, u and v averaged, in
/// time order; 1 where fewer than kCorrelationMinResiduals or F within kCorrelationFloorSds of 1.
std::vector<double> image_time_correlation(const NetworkResult& result,
                                           const std::vector<NetworkPoint>& points,
                                           const std::vector<NetworkObservation>& observations);

}  // namespace rangecal
