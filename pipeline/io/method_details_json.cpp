#include "pipeline/io/method_details_json.hpp"

#include <cmath>
#include <vector>

#include "pipeline/io/network_json.hpp"

namespace rangecal {
namespace {

std::vector<double> values(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

const char* start_source_name(TsaiStartSource s) {
  switch (s) {
    case TsaiStartSource::linear:
      return "linear";
    case TsaiStartSource::nominal_focal_length:
      return "nominal_focal_length";
    case TsaiStartSource::depth_profile:
      return "depth_profile";
  }
  return "linear";
}

nlohmann::json start_json(const TsaiStart& s) {
  return {
      {"source", start_source_name(s.source)},
      {"f_mm", s.f_mm},
      {"Tz_m", s.Tz},
      {"f_linear_relative_sigma", std::isfinite(s.f_linear_rel_sigma) ? nlohmann::json(s.f_linear_rel_sigma)
                                                                      : nlohmann::json("singular")}};
}

}  // namespace

nlohmann::json tsai_details_json(const TsaiResult& t) {
  nlohmann::json d = {
      {"f_linear_mm", t.f_linear_mm},
      {"Tz_linear_m", t.Tz_linear},
      {"step2_start", start_json(t.start)},
      {"step1_linear_rms_mm", t.step1.linear_rms_mm},
      {"step1_ty_ratio", t.step1.ty_ratio},
      {"step1_eq12_origin", values(t.step1.eq12_origin)},
      {"step1_pose_origin", values(t.step1.pose_origin)},
      {"step2_iterations", t.iterations},
      {"step2_converged", t.converged},
      {"rms_sensor_mm", t.rms_sensor_mm},
      {"covariance", "not computed (Tsai's method gives no uncertainty; see the bundle method)"}};
  if (!t.fallback.empty()) d["step2_fallback"] = t.fallback;
  return d;
}

nlohmann::json tsai_sassa_details_json(const TsaiSassaResult& t, const TsaiSassaOptions& opt) {
  const nlohmann::json search = {{"theta", values(t.search.theta)},
                                 {"z", values(t.search.z)},
                                 {"z_norm", t.search.z_norm},
                                 {"z_max", t.search.z_max},
                                 {"objective", t.search.f},
                                 {"rms_px", t.search_rms_px},
                                 {"evaluations", t.search.search.evaluations},
                                 {"population", opt.search.population},
                                 {"iterations", opt.search.max_iterations},
                                 {"anneal", opt.search.anneal},
                                 {"T0", t.search.search.T0},
                                 {"seed", opt.search.seed}};
  nlohmann::json d = {{"parameters", parameter_names(t.parameters)},
                      {"theta0", values(t.theta0)},
                      {"theta0_start", start_json(t.start)},
                      {"half_range", values(t.half_range)},
                      {"step1",
                       {{parameter_name(CameraParameter::sx), t.step1.sx},
                        {parameter_name(CameraParameter::Tx), t.step1.Tx},
                        {parameter_name(CameraParameter::Ty), t.step1.Ty},
                        {"linear_rms_mm", t.step1.linear_rms_mm},
                        {"ty_ratio", t.step1.ty_ratio},
                        {"eq12_origin", values(t.step1.eq12_origin)},
                        {"pose_origin", values(t.step1.pose_origin)}}},
                      {"search", search}};
  if (t.polished)
    d["polish"] = {
        {"theta", values(t.theta_polished)}, {"objective", 2 * t.polish.F},
        {"iterations", t.polish.iterations}, {"residual_evaluations", t.polish.residual_evaluations},
        {"converged", t.polish.converged},   {"moved_z", (t.polish.x - t.search.z).norm()}};
  d["covariance"] = "not computed (the search gives no uncertainty; see the bundle method)";
  return d;
}

nlohmann::json dlt_lmqn_details_json(const DltLmqnResult& r) {
  return {{"dlt_ransac_inliers", r.dlt.inliers.size()},
          {"final_inliers", r.used.size()},
          {"dlt_outliers", r.dlt.outliers.size()},
          {"dlt_ransac_iterations", r.dlt.ransac_iterations},
          {"dlt_rms_px", r.dlt.rms_px},
          {"dlt_skew_px", r.dlt.skew_px},
          {"lmqn_iterations", r.lmqn.iterations},
          {"lmqn_lm_steps", r.lmqn.lm_steps},
          {"lmqn_qn_steps", r.lmqn.qn_steps},
          {"lmqn_stop", r.lmqn.stop_reason},
          {"lmqn_chi2", 2 * r.lmqn.F}};
}

nlohmann::json bundle_details_json(const BundleDetails& b) {
  nlohmann::json d;
  d["free"] = parameter_names(b.free);
  nlohmann::json solves = nlohmann::json::array();
  for (const BundleSolve& s : b.solves) {
    nlohmann::json j = {{"loss", to_string(s.loss)}, {"iterations", s.iterations}};
    if (s.rejected) j["rejected"] = *s.rejected;
    solves.push_back(j);
  }
  d["stages"] = solves;
  d["iterations"] = b.iterations;
  d["chi2"] = b.chi2;
  d["dof"] = b.dof;
  d["variance_factor"] = b.variance_factor;
  d["covariance_scaled_by_variance_factor"] = b.covariance_scaled;
  d["rank_deficient"] = b.rank_deficient;
  d["outlier_threshold_sigma"] = b.outlier_threshold_sigma;
  d["pixel_sigma_px"] = b.pixel_sigma_px;
  d["time_correlation_factor"] = b.time_correlation_factor;
  if (b.clock_offset_s) d["clock_offset_s"] = *b.clock_offset_s;
  if (b.sigma_unscaled.size() == static_cast<Eigen::Index>(b.free.size()) && !b.free.empty()) {
    nlohmann::json su, ss;
    for (std::size_t k = 0; k < b.free.size(); ++k) {
      su[parameter_name(b.free[k])] = b.sigma_unscaled[static_cast<Eigen::Index>(k)];
      ss[parameter_name(b.free[k])] = b.sigma_scaled[static_cast<Eigen::Index>(k)];
    }
    d["sigma_unscaled"] = su;
    d["sigma_scaled"] = ss;
  }
  d["outliers"] = b.outliers;
  // Only when the σ are a sandwich under another model than the weights (optim/bundle/
  // correlated_ppk_covariance.hpp): a white run's details stay as they were.
  if (b.ppk_error_model)
    d["ppk_error_model"] = ppk_error_model_json(*b.ppk_error_model, b.gauss_markov_states);
  return d;
}

}  // namespace rangecal
