#include "pipeline/steps/network_problem.hpp"

#include <cmath>
#include <cstdlib>
#include <map>
#include <set>

namespace rangecal {

NetworkCamera network_camera(const CalibrationProblem& p, const Camera& start, double start_clock_offset_s) {
  NetworkCamera nc;
  nc.initial = start;
  nc.options.free = p.free;
  nc.options.pixel_sigma_px = p.pixel_sigma_px;
  nc.options.initial_clock_offset_s = start_clock_offset_s;
  nc.options.priors = bundle_options(p).priors;
  return nc;
}

NetworkProblem make_network_problem(const std::vector<NetworkCameraInput>& cams, const LampTrack& track,
                                    double max_frame_offset_s) {
  NetworkProblem n;
  const std::int64_t max_ns = static_cast<std::int64_t>(std::llround(max_frame_offset_s * 1e9));
  std::map<std::size_t, std::size_t> point_of_epoch;
  std::map<std::string, std::size_t> point_of_pole;
  for (std::size_t c = 0; c < cams.size(); ++c) {
    const CalibrationProblem& p = *cams[c].problem;
    const std::vector<Correspondence>& pairs = *cams[c].pairs;
    n.cameras.push_back(network_camera(p, cams[c].start, cams[c].start_clock_offset_s));
    for (std::size_t i = 0; i < p.observations.size(); ++i) {
      const BundleObservation& o = p.observations[i];
      NetworkObservation ob;
      ob.camera = c;
      ob.pixel = o.pixel;
      ob.pixel_sigma_px = o.pixel_sigma_px;
      ob.velocity = o.velocity;
      ob.source = p.camera_id + " " + o.source;
      const bool lamp = i < pairs.size();
      long epoch = -1;
      if (lamp && !track.epochs.empty()) {
        const std::size_t e =
            nearest_in_time(track.epochs, pairs[i].utc, [](const LampEpoch& le) { return le.utc; });
        if (e < track.epochs.size() && std::llabs(track.epochs[e].utc.ns - pairs[i].utc.ns) <= max_ns)
          epoch = static_cast<long>(e);
      }
      if (epoch >= 0) {
        const LampEpoch& le = track.epochs[static_cast<std::size_t>(epoch)];
        auto it = point_of_epoch.find(static_cast<std::size_t>(epoch));
        if (it == point_of_epoch.end()) {
          NetworkPoint pt;
          pt.prior_enu = le.enu;
          pt.prior_cov = le.cov_enu.allFinite() && le.cov_enu.trace() > 0
                             ? le.cov_enu
                             : Eigen::Matrix3d(le.sd_enu.cwiseProduct(le.sd_enu).asDiagonal());
          pt.quality = le.quality;
          // Seconds from the track's first epoch: the epoch's place in a correlated PPK error model's
          // Gauss–Markov chain (gnss/track/ppk_error_model.hpp).
          pt.time_s = 1e-9 * static_cast<double>(le.utc.ns - track.epochs.front().utc.ns);
          pt.source = "epoch " + format_iso8601_utc(le.utc);
          it = point_of_epoch.emplace(static_cast<std::size_t>(epoch), n.points.size()).first;
          n.points.push_back(pt);
          n.epoch_of_point.push_back(epoch);
        }
        ob.point = it->second;
        ob.offset_m = o.world - le.enu;
      } else if (!lamp) {
        const std::string id = p.control_pole_ids[i - pairs.size()];
        auto it = point_of_pole.find(id);
        if (it == point_of_pole.end()) {
          NetworkPoint pt;
          pt.prior_enu = o.world;
          pt.prior_cov = o.world_cov;
          pt.control_pole = true;
          pt.quality = 0;
          pt.source = "control pole '" + id + "'";
          it = point_of_pole.emplace(id, n.points.size()).first;
          n.points.push_back(pt);
          n.epoch_of_point.push_back(-1);
        }
        ob.point = it->second;
      } else {  // a lone pair: its own point, its own prior
        NetworkPoint pt;
        pt.prior_enu = o.world;
        pt.prior_cov = o.world_cov;
        pt.source = ob.source;
        ob.point = n.points.size();
        n.points.push_back(pt);
        n.epoch_of_point.push_back(-1);
      }
      n.observations.push_back(ob);
    }
  }
  return n;
}

std::size_t shared_epoch_count(const NetworkProblem& n) {
  std::vector<std::set<std::size_t>> cameras_of(n.points.size());
  for (const NetworkObservation& o : n.observations)
    if (o.point < n.points.size() && n.epoch_of_point[o.point] >= 0) cameras_of[o.point].insert(o.camera);
  std::size_t shared = 0;
  for (const auto& c : cameras_of) shared += c.size() >= 2 ? 1 : 0;
  return shared;
}

}  // namespace rangecal
