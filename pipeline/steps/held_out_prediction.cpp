#include "pipeline/steps/held_out_prediction.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "config/error.hpp"
#include "optim/network/network_adjustment.hpp"
#include "vision/triangulation/triangulation.hpp"

namespace rangecal {

namespace {

/// A lamp centroid's own σ (px) in camera c: the σ the network weighed it by, without the factor
/// √F it added for residuals that repeat in time (optim/network/image_time_correlation.hpp) — one
/// held-out epoch's pixel scatters by the centroid's own σ.
double centroid_sigma_px(const NetworkResult& r, std::size_t c) {
  const BundleDetails& d = r.cameras[c].details;
  return d.pixel_sigma_px / std::sqrt(d.time_correlation_factor);
}

// The marginal covariance of a fix's error under `m` (m²): the white part S·Σ_pos·S and the
// Gauss–Markov part's stationary variance σ_g² per axis.
Eigen::Matrix3d fix_covariance(const NetworkPoint& p, const PpkErrorModel& m) {
  const Eigen::Matrix3d S = m.white_scale().asDiagonal();
  Eigen::Matrix3d C = S * p.prior_cov * S;
  if (m.correlated()) C += m.gm_sd().cwiseProduct(m.gm_sd()).asDiagonal().toDenseMatrix();
  return C;
}

// Camera c as it saw an observation: the point it saw is X + offset − v·δ_c, so a camera whose
// translation absorbs that shift sees it at X.
Camera camera_seeing_epoch(const Camera& cam, const NetworkObservation& o, double clock_offset_s) {
  Camera shifted = cam;
  shifted.pose.T += cam.pose.R * (o.offset_m - o.velocity * clock_offset_s);
  return shifted;
}

struct Split {
  std::vector<NetworkPoint> points;
  std::vector<NetworkObservation> observations;
};

// The calibration half of one split: the observations of points in blocks of parity `parity`, and
// every point without a time (poles, lone pairs); points renumbered.
Split calibration_half(const std::vector<NetworkPoint>& points,
                       const std::vector<NetworkObservation>& observations, const std::vector<long>& block,
                       int parity) {
  Split s;
  std::vector<long> index(points.size(), -1);
  for (const NetworkObservation& o : observations) {
    const long b = block[o.point];
    if (b >= 0 && b % 2 != parity) continue;
    if (index[o.point] < 0) {
      index[o.point] = static_cast<long>(s.points.size());
      s.points.push_back(points[o.point]);
    }
    NetworkObservation copy = o;
    copy.point = static_cast<std::size_t>(index[o.point]);
    s.observations.push_back(copy);
  }
  return s;
}

struct Residual {
  double d2 = 0, mahalanobis = 0, log_det = 0, trace = 0;
};

// The held-out epochs of the other parity, triangulated from the cameras `r` calibrated.
std::vector<Residual> predict(const NetworkResult& r, const std::vector<NetworkPoint>& points,
                              const std::vector<NetworkObservation>& observations,
                              const std::vector<long>& block, int parity,
                              const std::vector<bool>& not_scored) {
  std::map<std::size_t, std::vector<const NetworkObservation*>> seen;
  for (const NetworkObservation& o : observations)
    if (block[o.point] >= 0 && block[o.point] % 2 != parity &&
        !(o.point < not_scored.size() && not_scored[o.point]))
      seen[o.point].push_back(&o);
  // Cross-covariances of the cameras' calibrations, from the joint covariance.
  const std::size_t n_cam = r.cameras.size();
  std::vector<Residual> out;
  for (const auto& [k, obs] : seen) {
    std::vector<TriangulationView> views;
    std::vector<std::size_t> cams;
    for (const NetworkObservation* o : obs) {
      if (std::find(cams.begin(), cams.end(), o->camera) != cams.end()) continue;
      const BundleResult& b = r.cameras[o->camera];
      TriangulationView v;
      v.camera = camera_seeing_epoch(b.calibration.camera, *o, b.calibration.clock_offset_s);
      v.calibration = {b.calibration.parameters, b.calibration.covariance};
      v.uv_px = o->pixel;
      v.pick_sigma_px = o->pixel_sigma_px > 0 ? o->pixel_sigma_px : centroid_sigma_px(r, o->camera);
      views.push_back(v);
      cams.push_back(o->camera);
    }
    if (views.size() < 2) continue;
    CrossCovariances cross(views.size(), std::vector<Eigen::MatrixXd>(views.size()));
    if (r.joint_covariance.size() > 0 && r.joint_offset.size() >= n_cam)
      for (std::size_t i = 0; i < views.size(); ++i)
        for (std::size_t j = 0; j < views.size(); ++j)
          if (i != j)
            cross[i][j] = r.joint_covariance.block(r.joint_offset[cams[i]], r.joint_offset[cams[j]],
                                                   r.cameras[cams[i]].calibration.parameters.size(),
                                                   r.cameras[cams[j]].calibration.parameters.size());
    TriangulationResult t;
    try {
      t = triangulate_point(views, "held-out epoch", &cross);
    } catch (const Error&) {
      continue;  // rays nearly parallel or a point behind a camera: no prediction to score
    }
    const Eigen::Vector3d d = t.point - points[k].prior_enu;
    const Eigen::Matrix3d C = t.cov_m2 + fix_covariance(points[k], r.ppk_error);
    const Eigen::LLT<Eigen::Matrix3d> llt(C);
    if (llt.info() != Eigen::Success) continue;
    Residual e;
    e.d2 = d.squaredNorm();
    e.mahalanobis = d.dot(llt.solve(d));
    e.log_det = 2 * llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
    e.trace = C.trace();
    out.push_back(e);
  }
  return out;
}

// Each point's block of `block_s` of time from the first point with a time; −1 for a point without.
std::vector<long> time_blocks(const std::vector<NetworkPoint>& points, double block_s) {
  double t0 = std::numeric_limits<double>::infinity();
  for (const NetworkPoint& p : points)
    if (std::isfinite(p.time_s)) t0 = std::min(t0, p.time_s);
  std::vector<long> block(points.size(), -1);
  for (std::size_t k = 0; k < points.size(); ++k)
    if (std::isfinite(points[k].time_s))
      block[k] = static_cast<long>(std::floor((points[k].time_s - t0) / block_s));
  return block;
}

}  // namespace

std::vector<HeldOutScore> score_held_out_blocks(const std::vector<NetworkCamera>& cameras,
                                                const std::vector<NetworkPoint>& points,
                                                const std::vector<NetworkObservation>& observations,
                                                const std::vector<HeldOutCandidate>& candidates,
                                                const HeldOutOptions& options) {
  const std::vector<long> block =
      options.blocks.empty() ? time_blocks(points, options.block_s) : options.blocks;
  std::vector<HeldOutScore> scores;
  for (const HeldOutCandidate& c : candidates) {
    HeldOutScore s;
    s.candidate = c.name;
    std::vector<Residual> all;
    for (int parity = 0; parity < (options.both_splits ? 2 : 1) && s.why.empty(); ++parity) {
      const Split half = calibration_half(points, observations, block, parity);
      try {
        const NetworkResult r = network_adjust(c.cameras.empty() ? cameras : c.cameras, half.points,
                                               half.observations, c.options);
        const std::vector<Residual> e = predict(r, points, observations, block, parity, options.not_scored);
        if (e.size() < options.min_epochs)
          s.why = "split " + std::to_string(parity) + ": " + std::to_string(e.size()) +
                  " held-out epochs seen by two cameras (fewer than " + std::to_string(options.min_epochs) +
                  ")";
        all.insert(all.end(), e.begin(), e.end());
      } catch (const Error& err) {
        s.why = "split " + std::to_string(parity) + ": " + err.reason();
      }
    }
    if (s.why.empty()) {
      s.scored = true;
      s.epochs = all.size();
      std::vector<double> norms;
      double d2 = 0, m = 0, score = 0, trace = 0;
      for (const Residual& e : all) {
        d2 += e.d2;
        m += e.mahalanobis;
        score += e.mahalanobis + e.log_det;
        trace += e.trace;
        norms.push_back(std::sqrt(e.d2));
      }
      const double n = static_cast<double>(all.size());
      std::nth_element(norms.begin(), norms.begin() + norms.size() / 2, norms.end());
      s.rms_m = std::sqrt(d2 / n);
      s.median_m = norms[norms.size() / 2];
      s.sigma_rms_m = std::sqrt(trace / n);
      s.z_rms = std::sqrt(m / (3 * n));
      s.score = score / n;
    }
    scores.push_back(s);
  }
  return scores;
}

std::vector<long> outer_ring_blocks(const std::vector<NetworkCamera>& cameras,
                                    const std::vector<NetworkPoint>& points,
                                    const std::vector<NetworkObservation>& observations, std::size_t camera,
                                    double outer_share) {
  const CameraIntrinsics& in = cameras[camera].initial.intr;
  std::vector<double> radius(points.size(), -1);
  for (const NetworkObservation& o : observations)
    if (o.camera == camera && std::isfinite(points[o.point].time_s))
      radius[o.point] = (o.pixel - Eigen::Vector2d(in.u0_px, in.v0_px)).norm();
  std::vector<double> seen;
  for (double r : radius)
    if (r >= 0) seen.push_back(r);
  std::vector<long> block(points.size(), -1);
  if (seen.empty()) return block;
  const auto rank =
      static_cast<std::ptrdiff_t>(std::floor((1 - outer_share) * static_cast<double>(seen.size() - 1)));
  std::nth_element(seen.begin(), seen.begin() + rank, seen.end());
  const double rim = seen[static_cast<std::size_t>(rank)];
  for (std::size_t k = 0; k < points.size(); ++k)
    if (std::isfinite(points[k].time_s)) block[k] = radius[k] > rim ? 1 : 0;
  return block;
}

bool clearly_better(const HeldOutScore& b, const HeldOutScore& a) {
  if (!a.scored || !b.scored) return false;
  const double epochs = static_cast<double>(std::min(a.epochs, b.epochs));
  return epochs * (a.score - b.score) >= 2 * std::log(kHeldOutDensityRatio);
}

nlohmann::json held_out_scores_json(const std::vector<HeldOutScore>& scores) {
  nlohmann::json j = nlohmann::json::array();
  for (const HeldOutScore& s : scores) {
    nlohmann::json c = {{"candidate", s.candidate}, {"scored", s.scored}};
    if (!s.scored) {
      c["why"] = s.why;
    } else {
      c["epochs"] = s.epochs;
      c["rms_m"] = s.rms_m;
      c["median_m"] = s.median_m;
      c["sigma_rms_m"] = s.sigma_rms_m;
      c["z_rms"] = s.z_rms;
      c["score"] = s.score;
    }
    j.push_back(c);
  }
  return j;
}

}  // namespace rangecal
