#pragma once
// Each camera's label σ estimated from the views' disagreement (docs/trajectory.md "Label σ"): the
// target's labels come from whatever tracked it — a correlation tracker, a hand, a detector — whose
// σ need not be the lamp centroids' of the calibration, nor what its user stated. Where an instant is
// seen by more cameras than a point needs, the views' residuals carry that σ.
//
// The model (instants n, each with its point X_n; views i, each of one camera c(i)):
//   r_i = J_i·δX_n + B_i·u + e_i,   u ~ N(0, I),   cov(e_i) = θ_c(i)·L_i + F_i
// r_i the view's residual (px, 2), J_i = ∂pixel_i/∂X (2×3), L_i = σ_label,i²·I the label's covariance
// as given (a priori), F_i the rest of the view's own covariance (the clock's σ along the image
// velocity, a lens-model σ). u are the calibrations' errors, whitened: one draw for the whole
// trajectory, not one per instant — a camera's calibration error moves its residuals alike at every
// instant, and taken as independent per instant it would be read as label noise. B_i = ∂pixel_i/∂θ·S,
// Σ_θ = S·Sᵀ the calibrations' (joint) covariance. θ_c is camera c's variance scale: its label σ is
// √θ_c times the given one. The θ maximise the restricted likelihood (REML; X_n flat, u integrated
// out) by Fisher scoring (Koch, *Parameter Estimation and Hypothesis Testing in Linear Models*,
// 2nd ed. 1999, §3.6). With P₀ the per-instant projector W − W·J·(JᵀWJ)⁻¹·JᵀW (W = cov(e)⁻¹) and
// M = I + BᵀP₀B, the whole problem's projector is P = P₀ − P₀B·M⁻¹·BᵀP₀ (Woodbury), so that
//   P·r = P₀·(r − B·û), û = M⁻¹·BᵀP₀·r the calibration error the residuals show;
//   score_k = ½·rᵀP·Q_k·P·r − ½·tr(P·Q_k),   Fisher_kl = ½·tr(P·Q_k·P·Q_l),
// Q_k the label covariances of component k's views. Cov(θ̂) = Fisher⁻¹ for independent labels (a
// tracker's errors that repeat from frame to frame make the true spread larger).
//
// The labels are interpolated to the instants: at weight w between two frames whose labels' errors
// correlate by ρ the variance is σ²·((1 − w)² + w² + 2ρ·w(1 − w)) — two components per camera, θ_a at
// the frames and θ_b = ρ·θ_a between them, where the instants' weights spread enough to tell them
// apart; else one (ρ = 1, the σ whole).
//
// Identifiability: with two cameras an instant has one degree of freedom, shared between them by the
// geometry alone; cameras whose scale the data cannot separate (relative σ of their σ above
// `max_relative_sd`) share one scale — the a-posteriori variance factor of those cameras' labels —
// and if even that is not determined their labels keep the σ given. A scale that ends on its lower
// bound counts as not determined.
//
// Gross errors: an instant whose χ² = eᵀ·P₀·e (e = r − B·û) exceeds its 99.9 % quantile under the
// current scales is left out of the next iteration (a label off by much more than its σ would
// otherwise set it).
#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace rangecal {

/// One view of one instant, linearised at the triangulated point.
struct LabelVcView {
  std::size_t camera = 0;                                 ///< index into the cameras
  Eigen::Vector2d residual_px = Eigen::Vector2d::Zero();  ///< projected − label (px)
  Eigen::Matrix<double, 2, 3> d_pixel_d_point = Eigen::Matrix<double, 2, 3>::Zero();  ///< px/m
  double label_sigma_px = 0;  ///< the label's σ as given, per axis (px, > 0)
  /// Where the label lies between its two frames, 0 at the first and 1 at the second: its variance is
  /// σ²·((1 − w)² + w² + 2ρ·w(1 − w)), ρ the correlation of neighbouring labels' errors.
  double interpolation_weight = 0;
  /// The view's own covariance but the label's and the calibration's (px²).
  Eigen::Matrix2d fixed_cov_px2 = Eigen::Matrix2d::Zero();
  /// ∂pixel/∂u (px, 2×w): the view's pixel against the whitened calibration errors u, over u's
  /// entries common_offset … common_offset + w − 1 (w = 0: the camera's calibration taken as exact).
  Eigen::MatrixXd d_pixel_d_common = Eigen::MatrixXd(2, 0);
  Eigen::Index common_offset = 0;
};

/// One instant: its views (≥ 2 for one degree of freedom or more; others are ignored).
using LabelVcInstant = std::vector<LabelVcView>;

struct LabelVcOptions {
  /// A camera's own scale is kept only when the relative 1σ of its σ (sd(θ)/(2θ)) is at most this;
  /// otherwise it joins the common scale.
  double max_relative_sd = 0.2;
  int max_iterations = 50;
  double tolerance = 1e-6;  ///< relative change of every θ that ends the iteration
  /// The search keeps every variance scale above this (σ 0.1× the given); a scale that ends on it is
  /// not determined (the rest of the views' covariance already explains their residuals).
  double min_scale = 0.01;
};

/// How a camera's label σ was set.
enum class LabelScaleKind {
  own,       ///< its own scale, determined by the data
  common,    ///< one scale shared with the other cameras the data could not separate
  as_given,  ///< not determined: the σ given (no instant to judge it, or too few)
};

struct LabelVcResult {
  /// Per camera: a label's σ on its own frame = this × the given σ (1 when as_given).
  std::vector<double> sigma_scale;
  std::vector<double> sigma_scale_sd;  ///< 1σ of sigma_scale (independent labels); 0 when as_given
  /// Per camera: the correlation ρ of neighbouring labels' errors (1 when not estimated: a label
  /// between two frames keeps the σ whole), its 1σ, and whether it was estimated.
  std::vector<double> correlation;
  std::vector<double> correlation_sd;
  std::vector<bool> correlation_estimated;
  std::vector<double> redundancy;  ///< per camera: tr(P·Q) over its views, its share of the dof
  std::vector<LabelScaleKind> kind;
  std::size_t instants = 0;  ///< instants with a degree of freedom, used at the end
  std::size_t excluded = 0;  ///< left out as gross errors at the end
  int iterations = 0;
  bool converged = false;
};

/// Estimates each of `cameras` cameras' label scale from `instants` (model above); `common_dim` is
/// the dimension of u (0: every calibration exact).
LabelVcResult estimate_label_variance_components(const std::vector<LabelVcInstant>& instants,
                                                 std::size_t cameras, Eigen::Index common_dim = 0,
                                                 const LabelVcOptions& options = {});

}  // namespace rangecal
