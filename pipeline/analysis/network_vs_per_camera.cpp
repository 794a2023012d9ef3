#include "pipeline/analysis/network_vs_per_camera.hpp"

#include <cmath>
#include <limits>
#include <random>
#include <set>

#include "config/error.hpp"
#include "optim/network/network_input_checks.hpp"
#include "vision/triangulation/triangulation.hpp"

namespace rangecal {

int shared_epochs(const PlannedNetwork& n) {
  std::vector<std::set<std::size_t>> seen_by(n.points.size());
  for (const NetworkObservation& o : n.observations) seen_by[o.point].insert(o.camera);
  int shared = 0;
  for (std::size_t k = 0; k < n.points.size(); ++k)
    if (!n.points[k].control_pole && seen_by[k].size() >= 2) ++shared;
  return shared;
}

Eigen::MatrixXd per_camera_joint_covariance(const PlannedNetwork& n, const std::vector<std::string>& free,
                                            const PlanOptions& o) {
  const std::vector<CameraParameter> params = expand_free_parameters(free);
  const Eigen::Index p = static_cast<Eigen::Index>(params.size());
  const std::size_t nc = n.truth.size();
  // Diagonal blocks: each camera's own bound on its observations as the per-camera bundle reads
  // them (fix moved to the frame, Σ the fix's), exactly the data `rangecal plan`'s per-camera
  // tables use.
  std::vector<Eigen::MatrixXd> crb(nc);
  for (std::size_t c = 0; c < nc; ++c) {
    const CameraBound b =
        cramer_rao_bound(n.truth[c], camera_bundle_observations(c, n.points, n.observations), free, o);
    if (b.singular) return {};
    crb[c] = b.covariance;
  }
  // A_ck = J_ckᵀ C_ck⁻¹ J_X,ck of every observation: how camera c's normal equations pick up the
  // error of the point it sees (header).
  std::vector<std::vector<std::pair<std::size_t, Eigen::MatrixXd>>> by_point(n.points.size());
  for (const NetworkObservation& ob : n.observations) {
    BundleObservation b;
    b.world = n.points[ob.point].prior_enu + ob.offset_m;
    b.world_cov = n.points[ob.point].prior_cov;
    b.pixel_sigma_px = ob.pixel_sigma_px;
    b.velocity = ob.velocity;
    const ObservationTerms t = observation_terms(n.truth[ob.camera], params, b, o.pixel_sigma_px);
    by_point[ob.point].emplace_back(ob.camera, t.J.transpose() * t.C.inverse() * t.Jx);
  }
  // G_ab = Σ_k A_ak Σ_k A_bkᵀ over the points both cameras see, a ≠ b.
  std::vector<std::vector<Eigen::MatrixXd>> G(nc,
                                              std::vector<Eigen::MatrixXd>(nc, Eigen::MatrixXd::Zero(p, p)));
  for (std::size_t k = 0; k < n.points.size(); ++k)
    for (const auto& [a, Aa] : by_point[k])
      for (const auto& [b, Ab] : by_point[k])
        if (a != b) G[a][b] += Aa * n.points[k].prior_cov * Ab.transpose();
  Eigen::MatrixXd joint =
      Eigen::MatrixXd::Zero(p * static_cast<Eigen::Index>(nc), p * static_cast<Eigen::Index>(nc));
  for (std::size_t a = 0; a < nc; ++a)
    for (std::size_t b = 0; b < nc; ++b)
      joint.block(static_cast<Eigen::Index>(a) * p, static_cast<Eigen::Index>(b) * p, p, p) =
          a == b ? crb[a] : Eigen::MatrixXd(crb[a] * G[a][b] * crb[b]);
  return joint;
}

std::vector<Eigen::Vector3d> flight_volume_points(const PlannedNetwork& n, int count, std::uint64_t seed) {
  std::vector<Eigen::Vector3d> out;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const NetworkPoint& p : n.points)
    if (!p.control_pole) lo = lo.cwiseMin(p.prior_enu), hi = hi.cwiseMax(p.prior_enu);
  if (n.truth.size() < 2 || !(lo.x() <= hi.x())) return out;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U01(0, 1);
  for (long draw = 0; static_cast<int>(out.size()) < count && draw < 100L * count; ++draw) {
    const Eigen::Vector3d X = lo + (hi - lo).cwiseProduct(Eigen::Vector3d(U01(rng), U01(rng), U01(rng)));
    int seen = 0;
    for (const Camera& t : n.truth) {
      Eigen::Vector2d uv;
      if (project(t, X, &uv) && inside_image(t.intr, uv)) ++seen;
    }
    if (seen >= 2) out.push_back(X);
  }
  return out;
}

double predicted_intersection_rms(const std::vector<Camera>& truth,
                                  const std::vector<CameraParameter>& params, const Eigen::MatrixXd& joint,
                                  const std::vector<Eigen::Vector3d>& points, bool with_cross) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Eigen::Index p = static_cast<Eigen::Index>(params.size());
  if (joint.size() == 0 || joint.rows() != p * static_cast<Eigen::Index>(truth.size())) return nan;
  double sum = 0;
  int used = 0;
  for (const Eigen::Vector3d& X : points) {
    std::vector<TriangulationView> views;
    std::vector<Eigen::Index> camera_of;  // joint block of each view
    for (std::size_t c = 0; c < truth.size(); ++c) {
      TriangulationView v;
      if (!project(truth[c], X, &v.uv_px) || !inside_image(truth[c].intr, v.uv_px)) continue;
      v.camera = truth[c];
      // One common pick σ and the picks' weights alone (not the calibration's: the covariances
      // compared — per camera, network, datum floor — are then carried through one estimate): the
      // weights cancel, Σ_cal is the calibration's.
      v.pick_sigma_px = 1;
      const Eigen::Index at = static_cast<Eigen::Index>(c) * p;
      v.calibration = {params, joint.block(at, at, p, p)};
      views.push_back(v);
      camera_of.push_back(at);
    }
    if (views.size() < 2) continue;
    CrossCovariances cross(views.size(), std::vector<Eigen::MatrixXd>(views.size()));
    for (std::size_t i = 0; i < views.size(); ++i)
      for (std::size_t j = 0; j < views.size(); ++j)
        if (i != j) cross[i][j] = joint.block(camera_of[i], camera_of[j], p, p);
    try {
      sum += triangulation_covariance_at(views, X, with_cross ? &cross : nullptr, false)
                 .cov_calibration_m2.trace();
      ++used;
    } catch (const Error&) {
      // Nearly parallel rays: no prediction there, the point is left out.
    }
  }
  return used ? std::sqrt(sum / used) : nan;
}

}  // namespace rangecal
