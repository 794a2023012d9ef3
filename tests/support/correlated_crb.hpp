#pragma once
// An independent yardstick for the network bundle under time-correlated PPK errors
// (docs/accuracy_analysis.md "Correlated PPK errors: the independent bound";
// docs/references.md "Correlated PPK errors"): the linearised Cramér–Rao bound of a camera network, written
// here with dense linear algebra and numeric derivatives of vision's project() — no code of
// optim/network (its Schur complement) nor of optim/bundle/projection_jacobian.
//
// Observation model, at the truth (every observation noise-free, so the bound is evaluated there):
//   y = [pixels; PPK fixes; pole surveys; station surveys] = h(θ) + e,   e ~ N(0, Σ_y),
//   θ = [each camera's free parameters; one 3-vector per lamp epoch; one per control pole],
//   Σ_y = blockdiag(σ_px²·I per view, Σ_PPK (all epochs jointly, dense), σ_pole²·I, σ_station²·I),
//   F = Aᵀ Σ_y⁻¹ A   (A = ∂h/∂θ),   CRB = F⁻¹.
// The PPK fix of epoch k observes its point directly (rows of A = identity), so Σ_PPK⁻¹ lands on the
// epochs' block of F. Σ_PPK per ENU axis (E and N horizontal, U vertical), epochs i, j:
//   C_ij = σ_w²·δ_ij + σ_g²·exp(−|t_i − t_j|/τ)          (white + first-order Gauss–Markov)
// and no correlation between axes.
//
// The estimator of a network that weights the fixes by another covariance Σ_a (a white-noise
// network: Σ_a = diag(σ_w² + σ_g²)) has, under the true Σ_PPK, the sandwich covariance
//   Cov = F_a⁻¹ Aᵀ W Σ_y W A F_a⁻¹,  W = Σ_a,y⁻¹
//       = F_a⁻¹ + H·(Σ_PPK − Σ_a)·Hᵀ   on the cameras,  H = [F_a⁻¹]_cameras,epochs · Σ_a⁻¹,
// because only the PPK block of Σ_y differs from what the estimator assumes.
//
// Calibration-only intersection σ: a hidden point X seen by cameras c (noise-free pixels) and
// triangulated by least squares with the estimated cameras moves by δX = −J_X⁺·J_θ·δθ, so
//   Σ_X = J_X⁺ J_θ Σ_θ J_θᵀ J_X⁺ᵀ,   J_X⁺ = (J_XᵀJ_X)⁻¹J_Xᵀ  (equal pixel σ in every camera),
// and the figure is √(mean over the points of trace Σ_X) (m).
//
// Size limit: F is dense over every parameter (n = camera parameters + 3·(epochs + poles)) and
// Σ_PPK is held dense (3N × 3N); F is factored by Cholesky (Jacobi-scaled), Σ_PPK axis by axis (the
// axes are uncorrelated): O(n³) time, O(n²) memory. Up to kMaxCrbEpochs = 2,000 epochs (n ≈ 6,000:
// ~290 MB a matrix; one bound at 1,995 epochs took 14 s of CPU and 1.4 GB); more are refused.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "config/deterministic_random.hpp"
#include "optim/network/network_adjustment.hpp"
#include "vision/camera/camera_model.hpp"
#include "vision/camera/camera_parameters.hpp"

namespace rangecal::test {

inline constexpr std::size_t kMaxCrbEpochs = 2000;

/// One camera of the bound: its true values and free parameters (f, sx, u0, v0, the distortion
/// terms, wx wy wz and CE CN CU; the clock offset and T are not supported), and optionally its
/// station surveyed: a prior of σ per axis on its centre.
struct CrbCamera {
  Camera truth;
  std::vector<CameraParameter> free;
  double station_sigma_m = 0;  ///< > 0: the centre surveyed to this σ per ENU axis
};

/// One image observation: camera `camera` sees point `point` — lamp epoch `point` when it is below
/// the number of epochs, else control pole `point − epochs`.
struct CrbView {
  std::size_t camera = 0;
  std::size_t point = 0;
  double pixel_sigma_px = 0.1;
};

struct CrbNetwork {
  std::vector<CrbCamera> cameras;
  std::vector<Eigen::Vector3d> epochs;  ///< true lamp positions, ENU m, in time order
  std::vector<double> epoch_time_s;     ///< per epoch
  std::vector<Eigen::Vector3d> poles;   ///< true control pole tops, ENU m
  double pole_sigma_m = 0.003;          ///< survey σ per axis
  std::vector<CrbView> views;
};

/// PPK position error per ENU axis: white σ_w plus a first-order Gauss–Markov process σ_g, τ;
/// horizontal (E, N) and vertical (U) separately. τ = 0: the GM part is white too.
struct GaussMarkovPpk {
  double white_h_m = 0, white_v_m = 0;
  double gm_h_m = 0, gm_v_m = 0;
  double tau_h_s = 0, tau_v_s = 0;

  /// What a white-noise network assumes: no correlation, σ² = σ_w² + σ_g² per axis.
  GaussMarkovPpk as_white() const;
  /// Total σ per axis (E, N, U).
  Eigen::Vector3d total_sigma() const;
};

/// The measured mission's PPK errors (docs/simulator.md "A realistic preset"): white 0.3 / 0.5 cm,
/// GM 0.8 / 1.4 cm (horizontal / vertical), time constant `tau_s` on both.
GaussMarkovPpk measured_ppk_model(double tau_s = 30);

/// Σ_PPK over all epochs (3N × 3N, epoch-major: E, N, U of epoch 0, then epoch 1, …) and its inverse.
struct PpkJointCovariance {
  Eigen::MatrixXd cov;
  Eigen::MatrixXd information;  ///< Σ_PPK⁻¹ (Cholesky)
};

/// Σ_PPK at epoch times `t` (s) under `model` (see the file comment). Throws std::invalid_argument for
/// more than kMaxCrbEpochs epochs or a Σ_PPK that is not positive definite.
PpkJointCovariance ppk_joint_covariance(const std::vector<double>& t, const GaussMarkovPpk& model);

/// One draw of the PPK errors at epoch times `t` (ENU m per epoch): white noise plus the exact
/// discretisation of the GM process, g_k = φ_k·g_{k−1} + σ_g·√(1 − φ_k²)·n_k, φ_k = exp(−Δt_k/τ),
/// g_0 = σ_g·n_0 (stationary for any spacing; Brown & Hwang 2012).
std::vector<Eigen::Vector3d> draw_correlated_ppk_errors(const std::vector<double>& t,
                                                        const GaussMarkovPpk& model,
                                                        DeterministicRandom* rng);

/// A covariance of every camera's free parameters, cameras in order from offset[c] (each in its
/// `free` order; rotations are w of R = exp([w]×)·R_true, as vision/camera/camera_parameters.hpp).
struct CameraJointCovariance {
  Eigen::MatrixXd joint;
  std::vector<int> offset;
  /// σ of camera c's free parameters.
  Eigen::VectorXd sigma(std::size_t c) const;
};

/// The Cramér–Rao bound of the cameras' free parameters of `n` with the PPK errors `ppk` (the epochs'
/// Σ_PPK; ppk_joint_covariance of n.epoch_time_s). Throws std::invalid_argument for an unsupported free
/// parameter, a view out of range, a point behind its camera or a singular F.
CameraJointCovariance cramer_rao_bound(const CrbNetwork& n, const PpkJointCovariance& ppk);

/// The actual covariance of the estimator that weights the fixes by `assumed` when their errors have
/// covariance `truth` (the sandwich above). With assumed = truth it is the bound itself.
CameraJointCovariance sandwich_covariance(const CrbNetwork& n, const PpkJointCovariance& assumed,
                                          const PpkJointCovariance& truth);

/// Up to `count` points uniform in the box of the network's lamp epochs (fixed `seed`), each inside
/// the image of ≥ 2 cameras: the flight volume (fewer when 100·count draws do not find enough).
std::vector<Eigen::Vector3d> flight_volume(const CrbNetwork& n, int count, std::uint64_t seed);

/// Calibration-only intersection σ (m) over `points`: √(mean trace Σ_X) (see above) with the
/// cameras' covariance `cov`.
double intersection_sigma_m(const CrbNetwork& n, const CameraJointCovariance& cov,
                            const std::vector<Eigen::Vector3d>& points);

/// The geometry of the setting measured on a real mission (docs/accuracy_analysis.md "Correlated
/// PPK errors"): two 100 mm cameras (1280 × 800, 20 µm, distortion k1) 45–80 m from vertical ascents
/// at (E, N) = (−5, 0.75), (0, 4.75), (5, 0.75), (0, −3.25), (0, 8.75), each climbing 0.8 → 9.8 m
/// at a constant speed, one after another with a transit between them; one epoch every 1/rate_hz
/// on the climbs, kept when some camera sees it; free f, k1, pose.
struct AscentNetworkOptions {
  int ascents = 5;              ///< the first this many of the five
  double rate_hz = 5;           ///< fixed epochs per second on a climb
  double climb_s = 23.7;        ///< duration of one climb
  double transit_s = 5;         ///< between climbs (no fixed epochs)
  int control_poles = 0;        ///< 0–2: pole tops at (−2, −1, 2.2) and (2, −1, 7.5)
  double pole_sigma_m = 0.003;  ///< their survey σ
  double station_sigma_m = 0;   ///< > 0: both stations surveyed to this σ
  double pixel_sigma_px = 0.1;  ///< lamp centroid σ
  double pick_sigma_px = 0.2;   ///< pole pick σ
};
CrbNetwork ascent_network(const AscentNetworkOptions& options = {});

/// Camera 0 of `n` alone, with only the epochs it sees (renumbered, in time order): the per-camera
/// bundle's and the compare methods' mission.
CrbNetwork one_camera(const CrbNetwork& n);

/// `n` as network_adjust's input: cameras starting at `start` (or the truth when empty) with their
/// free sets and station priors (centred on `station_error` + truth when given), a-priori
/// covariance (not scaled); one point per epoch at truth + `ppk_error[k]` (zero when empty) under the
/// per-epoch prior diag(`weights`.total_sigma()²), one per control pole at truth + `pole_error[j]`
/// under its survey σ; the views with pixels from the truth + `pixel_noise[i]`.
struct NetworkInput {
  std::vector<NetworkCamera> cameras;
  std::vector<NetworkPoint> points;
  std::vector<NetworkObservation> observations;
};
struct NetworkNoise {
  std::vector<Eigen::Vector3d> ppk_error;      ///< per epoch
  std::vector<Eigen::Vector3d> pole_error;     ///< per pole
  std::vector<Eigen::Vector3d> station_error;  ///< per camera
  std::vector<Eigen::Vector2d> pixel_noise;    ///< per view
};
NetworkInput network_input(const CrbNetwork& n, const GaussMarkovPpk& weights, const NetworkNoise& noise = {},
                           const std::vector<Camera>& start = {});

/// The network's error model for fixes whose .pos covariance is the model's total (network_input):
/// white scale = white / total per axis, the GM part as it is.
PpkErrorModel network_model(const GaussMarkovPpk& m);

/// The network as a Monte Carlo of its σ runs it: plain least squares (no robust loss, no outlier
/// re-solve, no PPK prior ever dropped), so a mission's spread is its noise's alone.
NetworkOptions plain_least_squares_network();

/// One noisy draw of `n` under `model`: PPK errors, pole and station survey errors, pixel noise.
NetworkNoise draw_network_noise(const CrbNetwork& n, const GaussMarkovPpk& model, DeterministicRandom* rng);

/// Values of camera `c`'s free parameters of `cam` (rotations: the rotation vector of
/// cam.R·truth.Rᵀ), to compare an estimate with the truth in CameraJointCovariance's coordinates.
Eigen::VectorXd free_values(const CrbNetwork& n, std::size_t c, const Camera& cam);

}  // namespace rangecal::test
