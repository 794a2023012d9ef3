#pragma once
// N-camera triangulation of one point (docs/intersection.md; seed 002 §4.2 Table 4) with its predicted
// covariance from the pick noise and the cameras' calibration covariances. Method and choices:
// docs/intersection.md.
//
//  1. Linear: the least-squares midpoint of the undistorted viewing rays (pixel_ray_world):
//       X0 = argmin Σ_i |(I − d_i d_iᵀ)(X − C_i)|²   (closed form, 3×3 solve).
//  2. Nonlinear: Gauss–Newton on the reprojection error (camera_model's project, distortion
//     inverted exactly), the views' pixels stacked and weighted by W = C⁻¹: first with C the
//     views' own terms, σ_px²·I + σ_t²·g·gᵀ per view — for a moving point the label's instant is
//     uncertain by σ_t, which moves it along its image velocity g (0 for a static point) — then,
//     when a view has a calibration covariance, once more from that solution with C gaining the
//     calibrations' K_i·Σ_ij·K_jᵀ (K_i = ∂pixel_i/∂θ_i there; Σ_ii a camera's own covariance, Σ_ij
//     the network's cross blocks): the generalised least-squares point. An error common to the
//     cameras (a network's datum) moves the point whatever the weights and so weighs no view down.
//  3. Covariance, first order at the solution (J the stacked ∂pixel/∂X, N = JᵀWJ, A = N⁻¹JᵀW):
//       pick noise:   Σ_pick   = Σ_i A_i σ_px² A_iᵀ;   timing: Σ_timing = Σ_i A_i σ_t² g gᵀ A_iᵀ
//       calibration:  ∂X/∂θ_i = −A_i K_i      (implicit-function theorem)
//                     Σ_cal  = Σ_i Σ_j (∂X/∂θ_i) Σ_ij (∂X/∂θ_j)ᵀ
//       Σ_X = Σ_pick + Σ_timing + Σ_cal (= N⁻¹: the weights are the errors' covariance);
//       sigma_m = √trace Σ_X, the predicted RMS of ΔR (Table 4).
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "vision/camera/camera_model.hpp"
#include "vision/camera/camera_parameters.hpp"

namespace rangecal {

/// The calibration uncertainty of one camera: covariance over any subset of the camera
/// parameters (vision/camera/camera_parameters.hpp), in their units (e.g. a CalibrationResult's
/// parameters / covariance). Empty = exactly known. The translation (Tx Ty Tz) and the centre
/// (CE CN CU) cannot be mixed in one covariance: with the centre (or neither) a rotation
/// perturbation turns the camera about its centre, with the translation about the world origin. A
/// clock_offset entry is allowed: a static point's pixel does not depend on it (zero column), so it
/// acts only through its correlations with the others, which the covariance already carries.
struct CameraCovariance {
  std::vector<CameraParameter> parameters;
  Eigen::MatrixXd covariance;  ///< n×n, n = parameters.size()
};

/// One camera's view of the point.
struct TriangulationView {
  Camera camera;
  CameraCovariance calibration;
  Eigen::Vector2d uv_px = Eigen::Vector2d::Zero();  ///< picked pixel (u right, v down)
  double pick_sigma_px = 0.2;                       ///< 1σ of the pick per axis (px, > 0)
  /// A moving point (a target's label at an instant): the label's image velocity (px/s) and the 1σ
  /// of its instant (s): the view's pixel covariance gains σ_t²·g·gᵀ along the image track. Zero for
  /// a static point.
  Eigen::Vector2d image_velocity_px_s = Eigen::Vector2d::Zero();
  double timing_sigma_s = 0;
};

struct TriangulationResult {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();         ///< ENU (m), nonlinear solution
  Eigen::Vector3d linear_point = Eigen::Vector3d::Zero();  ///< ENU (m), midpoint start
  std::vector<Eigen::Vector2d> residuals_px;               ///< projected − picked, per view (px)
  double rms_px = 0;                                       ///< √(mean over views of |residual|²) (px)
  /// rᵀ·W·r, the residuals under the weights the point was solved with (the views' whole stacked
  /// covariance, calibrations and their cross blocks included, when a view has a calibration
  /// covariance): the generalised least-squares objective, χ² with 2·views − 3 degrees of freedom.
  double weighted_chi2 = 0;
  double max_ray_angle_deg = 0;  ///< largest angle between two views' rays (intersection geometry)
  Eigen::Matrix3d cov_pick_m2 = Eigen::Matrix3d::Zero();         ///< from pick noise (m²)
  Eigen::Matrix3d cov_timing_m2 = Eigen::Matrix3d::Zero();       ///< from the views' timing σ (m²)
  Eigen::Matrix3d cov_calibration_m2 = Eigen::Matrix3d::Zero();  ///< from calibration covariances (m²)
  Eigen::Matrix3d cov_m2 = Eigen::Matrix3d::Zero();              ///< total (m²)
  double sigma_m = 0;  ///< √trace(cov_m2): predicted RMS of the 3-D error ΔR (m)
  int iterations = 0;  ///< Gauss–Newton iterations
};

/// Covariances between cameras' calibrations (a network calibration, optim/network): block (i, j),
/// i ≠ j, is cov(θ_i, θ_j) over view i's and view j's calibration parameters; an empty block (or no
/// table) means independent cameras. Σ_cal then gains Σ_{i≠j} (∂X/∂θ_i)·Σ_ij·(∂X/∂θ_j)ᵀ.
using CrossCovariances = std::vector<std::vector<Eigen::MatrixXd>>;

/// Triangulates one point seen by views.size() ≥ 2 cameras. `what` names the point in messages
/// (e.g. "pole A3"). Throws rangecal::Error (calibration) when fewer than two views are given,
/// the rays are (nearly) parallel (largest angle between them < 1e-4 rad), the point lies behind
/// a camera, the solution does not converge, or a covariance is malformed (size, T mixed with C,
/// non-finite, not positive semi-definite — a camera's own, or the joint one with its cross
/// blocks); (input) when a pick σ is not positive or a pixel is not finite.
TriangulationResult triangulate_point(const std::vector<TriangulationView>& views,
                                      const std::string& what = "point",
                                      const CrossCovariances* cross = nullptr);

/// The covariance triangulate_point states, evaluated at the world point X (ENU, m) instead of at
/// a solution: the views' weights (step 2, with their calibrations) and the parts of step 3 at X;
/// the views' pixels are not used (point = X, no residuals). For predictions — what a target
/// anywhere in the volume would be given. `weigh_calibration` false: the views weighted by their
/// pick and timing σ alone (step 2's first solve), so that covariances compared with each other
/// (a calibration's and its datum floor's) are carried through one estimate. Throws as
/// triangulate_point for fewer than two views, rays through X (nearly) parallel, X behind a camera,
/// a malformed covariance or a pick σ not positive.
TriangulationResult triangulation_covariance_at(const std::vector<TriangulationView>& views,
                                                const Eigen::Vector3d& X,
                                                const CrossCovariances* cross = nullptr,
                                                bool weigh_calibration = true);

/// ∂pixel/∂θ (2×n) of `camera` at world point X for `parameters` (perturbation model as above),
/// and ∂pixel/∂X (2×3) in `d_point` when non-null. Throws like triangulate_point for T mixed with C
/// or a point behind the camera. Exposed for tests and planning tools.
Eigen::MatrixXd pixel_jacobian_wrt_parameters(const Camera& camera,
                                              const std::vector<CameraParameter>& parameters,
                                              const Eigen::Vector3d& X,
                                              Eigen::Matrix<double, 2, 3>* d_point = nullptr);

}  // namespace rangecal
