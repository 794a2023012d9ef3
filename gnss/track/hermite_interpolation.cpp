#include "gnss/track/hermite_interpolation.hpp"

#include <algorithm>
#include <cmath>

#include "config/error.hpp"

namespace rangecal {

const char* to_string(TrackSampleStatus s) {
  switch (s) {
    case TrackSampleStatus::ok:
      return "ok";
    case TrackSampleStatus::before_track:
      return "before_track";
    case TrackSampleStatus::after_track:
      return "after_track";
    case TrackSampleStatus::in_gap:
      return "in_gap";
  }
  return "unknown";
}

namespace {

bool all_finite(const Eigen::Vector3d& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

std::string epoch_label(std::size_t i, UtcTime t) {
  return "epoch " + std::to_string(i + 1) + " (" + format_iso8601_utc(t) + ")";
}

}  // namespace

HermiteTrack::HermiteTrack(const LampTrack& track, double max_gap_s, const std::string& source) {
  if (!(std::isfinite(max_gap_s) && max_gap_s > 0)) {
    throw_config_error("", "gnss.max_gap_s",
                       "must be a positive number of seconds, got " + std::to_string(max_gap_s));
  }
  const auto& ep = track.epochs;
  if (ep.empty()) throw_input_error(source, 0, "utc", "the lamp track has no epochs: nothing to interpolate");
  const std::size_t n = ep.size();
  t_ns_.resize(n);
  p_.resize(n);
  sd_.resize(n);
  m_.assign(n, Eigen::Vector3d::Zero());
  from_velocity_.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0 && !(ep[i].utc > ep[i - 1].utc)) {
      throw_input_error(source, 0, "utc",
                        epoch_label(i, ep[i].utc) + " is not after " + epoch_label(i - 1, ep[i - 1].utc) +
                            ": lamp-track epochs must be strictly increasing in time");
    }
    if (!all_finite(ep[i].enu))
      throw_input_error(source, 0, "E,N,U", epoch_label(i, ep[i].utc) + " has a non-finite position");
    if (!all_finite(ep[i].sd_enu))
      throw_input_error(source, 0, "sdE,sdN,sdU", epoch_label(i, ep[i].utc) + " has a non-finite sd");
    t_ns_[i] = ep[i].utc.ns;
    p_[i] = ep[i].enu;
    sd_[i] = ep[i].sd_enu;
  }
  max_gap_s_ = max_gap_s;
  max_gap_ns_ = static_cast<std::int64_t>(std::llround(max_gap_s * 1e9));

  // Interval k joins epochs k and k+1; usable when not a gap.
  auto usable = [&](std::size_t k) { return k + 1 < n && t_ns_[k + 1] - t_ns_[k] <= max_gap_ns_; };
  auto h = [&](std::size_t k) { return static_cast<double>(t_ns_[k + 1] - t_ns_[k]) * 1e-9; };
  auto slope = [&](std::size_t k) -> Eigen::Vector3d { return (p_[k + 1] - p_[k]) / h(k); };

  for (std::size_t i = 0; i < n; ++i) {
    if (all_finite(ep[i].vel_enu)) {
      m_[i] = ep[i].vel_enu;
      from_velocity_[i] = 1;
      continue;
    }
    const bool left = i > 0 && usable(i - 1);
    const bool right = usable(i);
    if (left && right) {
      // Derivative at the middle node of the parabola through i−1, i, i+1 (uneven spacing).
      const double h0 = h(i - 1), h1 = h(i);
      m_[i] = (h1 * slope(i - 1) + h0 * slope(i)) / (h0 + h1);
    } else if (right) {
      if (usable(i + 1)) {  // parabola through i, i+1, i+2, derivative at its first node
        const double h1 = h(i), h2 = h(i + 1);
        m_[i] = slope(i) - h1 * (slope(i + 1) - slope(i)) / (h1 + h2);
      } else {
        m_[i] = slope(i);
      }
    } else if (left) {
      if (i >= 2 && usable(i - 2)) {  // parabola through i−2, i−1, i, derivative at its last node
        const double hm = h(i - 2), h0 = h(i - 1);
        m_[i] = slope(i - 1) + h0 * (slope(i - 1) - slope(i - 2)) / (hm + h0);
      } else {
        m_[i] = slope(i - 1);
      }
    }
    // An isolated epoch (gaps on both sides) keeps a zero tangent: no interval uses it.
  }
}

TrackSample HermiteTrack::sample(UtcTime t) const {
  TrackSample out;
  const std::size_t n = t_ns_.size();
  if (t.ns < t_ns_.front()) {
    out.status = TrackSampleStatus::before_track;
    return out;
  }
  if (t.ns > t_ns_.back()) {
    out.status = TrackSampleStatus::after_track;
    out.segment = n - 1;
    return out;
  }
  // k: last epoch with t_k ≤ t.
  const std::size_t k =
      static_cast<std::size_t>(std::upper_bound(t_ns_.begin(), t_ns_.end(), t.ns) - t_ns_.begin()) - 1;
  out.segment = k;
  if (t_ns_[k] == t.ns) {
    out.enu = p_[k];
    out.sd_enu = sd_[k];
    out.vel_enu = m_[k];
    return out;
  }
  const std::int64_t h_ns = t_ns_[k + 1] - t_ns_[k];
  const double h = static_cast<double>(h_ns) * 1e-9;
  out.interval_s = h;
  if (h_ns > max_gap_ns_) {
    out.status = TrackSampleStatus::in_gap;
    return out;
  }
  const double s = static_cast<double>(t.ns - t_ns_[k]) / static_cast<double>(h_ns);
  const double s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  const double d00 = 6 * s2 - 6 * s, d10 = 3 * s2 - 4 * s + 1, d01 = -6 * s2 + 6 * s, d11 = 3 * s2 - 2 * s;
  out.enu = h00 * p_[k] + h10 * h * m_[k] + h01 * p_[k + 1] + h11 * h * m_[k + 1];
  out.vel_enu = (d00 * p_[k] + d01 * p_[k + 1]) / h + d10 * m_[k] + d11 * m_[k + 1];
  out.sd_enu = (1 - s) * sd_[k] + s * sd_[k + 1];
  return out;
}

}  // namespace rangecal
