#pragma once
// The charts of report.html beyond the image plots of svg_plot.hpp: the site map (plan and side
// view), residuals against a variable with the noise model's ±2σ band and the network's lamp-track
// corrections against time with their ±1σ and their autocorrelation against the PPK error model's,
// colour maps over the image
// (projection uncertainty, calibration difference) and over a horizontal slice of the flight volume
// (predicted intersection σ), displacement vectors over the image (distortion), the correlation
// matrix, the check poles' error bars and the data funnel. Pure functions of typed data returning
// SVG text (pipeline/report/svg_chart.hpp conventions: one rect.area, data inside it in g.data,
// labelled axes "name (unit)", fixed number formats). The numbers they draw are computed elsewhere
// (projection_uncertainty, intersection_prediction, data_funnel, lamp_residuals) and tested there.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "pipeline/report/data_funnel.hpp"
#include "pipeline/report/intersection_prediction.hpp"
#include "pipeline/report/svg_plot.hpp"

namespace rangecal {

/// A camera on the site map: centre (ENU m) with its covariance (m², NaN: unknown), and the world
/// directions of the rays through the left and right edges of the image (the viewing wedge).
struct SiteCamera {
  std::string id;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Matrix3d center_cov_m2 = Eigen::Matrix3d::Zero();
  Eigen::Vector3d left_ray = Eigen::Vector3d::UnitX(), right_ray = Eigen::Vector3d::UnitX();
  double wedge_m = 0;  ///< length the wedge is drawn with (m, horizontal)
};

/// A surveyed pole; check poles intersected have their error (intersected − surveyed, m) and σ.
struct SitePole {
  std::string id;
  bool check = true;
  Eigen::Vector3d enu = Eigen::Vector3d::Zero();
  bool has_error = false;
  Eigen::Vector3d d_enu = Eigen::Vector3d::Zero();
  double sigma_m = 0;  ///< predicted RMS of ΔR (intersection.csv)
};

struct SiteMap {
  std::vector<SiteCamera> cameras;
  std::vector<Eigen::Vector3d> track;     ///< lamp-track epochs (ENU m) in time order
  std::vector<double> track_t_s;          ///< their time since the first (s)
  std::vector<Eigen::Vector3d> outliers;  ///< lamp positions of pairs a calibration rejected
  std::vector<SitePole> poles;
};

/// Plan view (E right, N up, equal scales): wedges, centres with 1σ ellipses (magnified when small,
/// the key says by how much), the track coloured by time, outliers (×), control poles (triangles),
/// check poles (squares) with their horizontal error vectors and σ circles, both magnified.
std::string svg_site_plan(const SiteMap& m, const std::string& id);
/// Side view: horizontal distance from the cameras' mean centre against height U.
std::string svg_site_side(const SiteMap& m, const std::string& id);

/// Residuals y (px) against x with the band ±2σ (σ per point; left open across a gap over 5× the
/// median step in x), rejected points hollow red.
std::string svg_residual_scatter(const std::vector<double>& x, const std::vector<double>& y,
                                 const std::vector<double>& sigma, const std::vector<bool>& used,
                                 const std::string& x_label, const std::string& y_label,
                                 const std::string& id, const std::string& title);

/// One axis of the network's lamp-track corrections (cm) against time since the first epoch (s)
/// over the band ±1σ of the adjusted position (cm) about zero, flagged PPK epochs as red ×
/// (path.flagged) and the others as dots (circle.point), with a key. The residual plot's layout.
std::string svg_correction_series(const std::vector<double>& t_s, const std::vector<double>& d_cm,
                                  const std::vector<double>& sigma_cm, const std::vector<bool>& flagged,
                                  const std::string& y_label, const std::string& id,
                                  const std::string& title);

/// The PPK corrections' empirical autocorrelation (circle.acf at each bin's mean lag, s) against the
/// model's ρ(lag) (polyline.model through `model_lag_s`, `model_rho`), with the zero line and a key.
std::string svg_autocorrelation(const std::vector<double>& lag_s, const std::vector<double>& rho,
                                const std::vector<double>& model_lag_s, const std::vector<double>& model_rho,
                                const std::string& y_label, const std::string& id, const std::string& title);

/// A colour map over the image (values ny × nx at cell centres u_px × v_px) with contours and a
/// colour bar labelled `value_label`; `marks` (px) are drawn as small × (e.g. cells that exceed).
std::string svg_image_map(const PlotFrame& frame, const std::vector<double>& u_px,
                          const std::vector<double>& v_px, const Eigen::MatrixXd& values,
                          const std::string& value_label, const std::string& id, const std::string& title,
                          const std::vector<Eigen::Vector2d>& marks = {});

/// Displacement vectors (px) at pixels `at`, magnified so the largest spans a twelfth of the width,
/// clipped to the frame, with a key of a round length `what` (e.g. "distortion").
std::string svg_image_vectors(const PlotFrame& frame, const std::vector<Eigen::Vector2d>& at,
                              const std::vector<Eigen::Vector2d>& vec, const std::string& what,
                              const std::string& id, const std::string& title);

/// The correlation matrix of `names` as a colour grid (rect.corr with data-rho "%.4f", ρ written in
/// each cell).
std::string svg_correlation_grid(const std::vector<std::string>& names, const Eigen::MatrixXd& rho,
                                 const std::string& id);

/// Per check pole ΔE, ΔN, ΔU (cm) as bars over grey ±1σ boxes (cm, per axis).
std::string svg_pole_bars(const std::vector<std::string>& ids, const std::vector<Eigen::Vector3d>& d_cm,
                          const std::vector<Eigen::Vector3d>& sigma_cm, const std::string& id);

/// The predicted calibration-only intersection σ (cm) over the slice, poles (E, N) marked.
std::string svg_slice_map(const IntersectionSigmaSlice& s, const std::vector<Eigen::Vector2d>& poles_en,
                          const std::string& id);

/// One stacked bar per funnel row: kept and each drop reason as shares of what came in.
std::string svg_funnel(const std::vector<FunnelRow>& rows, const std::string& id);

}  // namespace rangecal
