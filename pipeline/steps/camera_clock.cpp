#include "pipeline/steps/camera_clock.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "config/error.hpp"
#include "optim/bundle/bundle_adjustment.hpp"
#include "vision/calibration/dlt.hpp"
#include "vision/camera/camera_model.hpp"
#include "vision/triangulation/triangulation.hpp"

namespace rangecal {

UtcTime CameraClock::time_of(UtcTime nominal) const {
  const double since_start_s = 1e-9 * static_cast<double>(nominal.ns - nominal_start.ns);
  return UtcTime{nominal.ns + std::llround((offset_s + rate * since_start_s) * 1e9)};
}

UtcTime CameraClock::label_time(UtcTime nominal, double v_px) const {
  const double row = v_px / std::max(1, image_height_px - 1) - 0.5;
  return UtcTime{time_of(nominal).ns + std::llround(readout_s * row * 1e9)};
}

double clock_time_sd_s(double offset_sd_s, double rate_sd, double mid_offset_sd_s, double span_s,
                       double since_start_s, double wander_sd_s) {
  const double var_a = offset_sd_s * offset_sd_s, var_b = rate_sd * rate_sd;
  const double cov_ab =
      span_s > 0 ? (mid_offset_sd_s * mid_offset_sd_s - var_a - 0.25 * span_s * span_s * var_b) / span_s
                 : 0.0;
  const double s = since_start_s;
  const double var = var_a + 2 * s * cov_ab + s * s * var_b;
  return std::sqrt(std::max(0.0, var) + wander_sd_s * wander_sd_s);
}

double CameraClock::time_sd_s(UtcTime nominal) const {
  const double since_start_s = 1e-9 * static_cast<double>(nominal.ns - nominal_start.ns);
  return clock_time_sd_s(offset_sd_s, rate_sd, mid_offset_sd_s, span_s, since_start_s, wander_sd_s);
}

namespace {

constexpr double kInfinite = std::numeric_limits<double>::infinity();

// A clock to try: offset and rate on the labels' nominal times, and a rolling shutter's readout.
struct Clock {
  UtcTime start;
  double offset_s = 0, rate = 0;
  double readout_s = 0;
  int height_px = 2;
  CameraClock camera_clock() const {
    CameraClock c;
    c.nominal_start = start;
    c.offset_s = offset_s;
    c.rate = rate;
    c.readout_s = readout_s;
    c.image_height_px = height_px;
    return c;
  }
  UtcTime at(const ClockObservation& label) const {
    return camera_clock().label_time(label.nominal, label.uv.y());
  }
};

// The labels `which` with the lamp where this clock puts them; labels outside the track (or in a gap)
// are left out. `kept` receives the indices used.
std::vector<TrackSample> samples_at(const HermiteTrack& track, const std::vector<ClockObservation>& labels,
                                    const std::vector<std::size_t>& which, const Clock& clock,
                                    std::vector<std::size_t>* kept) {
  std::vector<TrackSample> out;
  kept->clear();
  for (std::size_t i : which) {
    const TrackSample s = track.sample(clock.at(labels[i]));
    if (s.status != TrackSampleStatus::ok) continue;
    out.push_back(s);
    kept->push_back(i);
  }
  return out;
}

// The residual of each point under P (∞ behind the camera).
std::vector<double> dlt_residuals(const ProjectionMatrix& P, const std::vector<PointCorrespondence>& pts) {
  std::vector<double> r(pts.size());
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const Eigen::Vector3d x = P * pts[k].world.homogeneous();
    r[k] = x.z() > 0 ? (x.hnormalized() - pts[k].pixel).norm() : kInfinite;
  }
  return r;
}

// A linear DLT refitted once without the points beyond 3× its median residual: robust enough for the
// few per cent of wrong labels a hand-labelled track has, and cheap enough to try thousands of clocks.
// Throws rangecal::Error on a degenerate set.
ProjectionMatrix trimmed_dlt(const std::vector<PointCorrespondence>& pts) {
  const ProjectionMatrix P = dlt_projection_matrix(pts);
  std::vector<double> r = dlt_residuals(P, pts);
  std::vector<double> sorted = r;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double cut = 3 * sorted[sorted.size() / 2];
  std::vector<PointCorrespondence> inliers;
  for (std::size_t k = 0; k < pts.size(); ++k)
    if (r[k] <= cut) inliers.push_back(pts[k]);
  return inliers.size() >= 12 ? dlt_projection_matrix(inliers) : P;
}

// Step 1's score of one clock: the trimmed DLT's rms residual truncated at options.truncate_px; ∞ when
// fewer than half of the labels lie in the track or the DLT is degenerate.
double dlt_score(const HermiteTrack& track, const std::vector<ClockObservation>& labels,
                 const std::vector<std::size_t>& which, const Clock& clock,
                 const ClockSearchOptions& options) {
  std::vector<std::size_t> kept;
  const std::vector<TrackSample> s = samples_at(track, labels, which, clock, &kept);
  if (2 * kept.size() < which.size() || kept.size() < 12) return kInfinite;
  std::vector<PointCorrespondence> pts(kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k) pts[k] = {s[k].enu, labels[kept[k]].uv};
  try {
    double sum = 0;
    for (double e : dlt_residuals(trimmed_dlt(pts), pts))
      sum += std::pow(std::min(e, options.truncate_px), 2);
    return std::sqrt(sum / static_cast<double>(pts.size()));
  } catch (const Error&) {
    return kInfinite;
  }
}

struct Scored {
  double offset_s = 0, score = kInfinite;
};

// Offsets from lo to hi every step, scored; the best first.
std::vector<Scored> scan(const HermiteTrack& track, const std::vector<ClockObservation>& labels,
                         const std::vector<std::size_t>& which, UtcTime start, double lo, double hi,
                         double step, const ClockSearchOptions& options) {
  std::vector<Scored> out;
  const long n = static_cast<long>(std::floor((hi - lo) / step + 1e-9)) + 1;
  for (long k = 0; k < n; ++k) {
    const double offset = lo + static_cast<double>(k) * step;
    out.push_back({offset, dlt_score(track, labels, which, Clock{start, offset, 0}, options)});
  }
  return out;
}

// The bundle's observations of the labels `which` at `clock`, with their indices.
std::vector<BundleObservation> observations_at(const HermiteTrack& track,
                                               const std::vector<ClockObservation>& labels,
                                               const std::vector<std::size_t>& which, const Clock& clock,
                                               double pixel_sigma_px, std::vector<std::size_t>* kept) {
  const std::vector<TrackSample> s = samples_at(track, labels, which, clock, kept);
  std::vector<BundleObservation> obs(s.size());
  for (std::size_t k = 0; k < s.size(); ++k) {
    obs[k].world = s[k].enu;
    obs[k].world_cov = s[k].sd_enu.cwiseProduct(s[k].sd_enu).asDiagonal();
    obs[k].velocity = s[k].vel_enu;
    obs[k].pixel = labels[(*kept)[k]].uv;
    obs[k].pixel_sigma_px = pixel_sigma_px;
  }
  return obs;
}

BundleOptions refine_options(const ClockSearchOptions& options, std::vector<std::string> free) {
  BundleOptions o;
  o.free = std::move(free);
  o.pixel_sigma_px = options.pixel_sigma_px;
  o.scale_covariance = true;
  o.loss_scale = 2;
  return o;
}

struct Line {
  double a = 0, b = 0;  ///< block offset ≈ a + b·mid
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  double scatter = 1;  ///< √(χ²/dof), at least 1
};

// The weighted straight line through the blocks' offsets (step 4), its covariance scaled by the
// scatter when above 1.
Line fit_line(const std::vector<ClockBlock>& blocks) {
  Eigen::Matrix2d N = Eigen::Matrix2d::Zero();
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  for (const ClockBlock& b : blocks) {
    const Eigen::Vector2d g(1, b.mid_s);
    const double w = 1 / (b.sd_s * b.sd_s);
    N += w * g * g.transpose();
    rhs += w * g * b.deviation_s;
  }
  Line line;
  if (blocks.size() == 1) {  // one block: the offset only
    line.a = blocks[0].deviation_s;
    line.cov(0, 0) = blocks[0].sd_s * blocks[0].sd_s;
    return line;
  }
  const Eigen::Vector2d x = N.ldlt().solve(rhs);
  line.a = x(0);
  line.b = x(1);
  line.cov = N.inverse();
  if (blocks.size() > 2) {
    double chi2 = 0;
    for (const ClockBlock& b : blocks)
      chi2 += std::pow((b.deviation_s - line.a - line.b * b.mid_s) / b.sd_s, 2);
    line.scatter = std::max(1.0, std::sqrt(chi2 / static_cast<double>(blocks.size() - 2)));
    line.cov *= line.scatter * line.scatter;
  }
  return line;
}

// The rolling shutter's readout correction, the camera and the clock's offset and rate held: a label
// in row v was exposed ρ·readout after the frame's time (ρ = v/(H−1) − ½), so its residual moves by
// g·ρ·Δreadout, g = J_X·v_lamp its image velocity (px/s). One least-squares Δ over all labels and
// one per block; the blocks' scatter gives the σ (label errors are correlated from frame to frame).
struct ReadoutStep {
  double delta_s = 0, sd_s = 0;
};

ReadoutStep readout_step(const Camera& camera, const HermiteTrack& track,
                         const std::vector<ClockObservation>& labels, const std::vector<std::size_t>& which,
                         const Clock& clock, double clock_offset_s, double block_s) {
  std::map<long, std::pair<double, double>> by_block;  // Σ aᵀa, Σ aᵀr
  double aa = 0, ar = 0;
  for (std::size_t i : which) {
    const TrackSample s = track.sample(clock.at(labels[i]));
    if (s.status != TrackSampleStatus::ok) continue;
    // The point the camera was fitted to: the bundle's own offset δ moves it by −v·δ.
    const Eigen::Vector3d X = s.enu - s.vel_enu * clock_offset_s;
    Eigen::Vector2d uv;
    if (!project(camera, X, &uv)) continue;
    Eigen::Matrix<double, 2, 3> dX;
    try {
      pixel_jacobian_wrt_parameters(camera, {}, X, &dX);
    } catch (const Error&) {
      continue;
    }
    const double rho = labels[i].uv.y() / std::max(1, clock.height_px - 1) - 0.5;
    const Eigen::Vector2d a = dX * s.vel_enu * rho, r = uv - labels[i].uv;
    const long b =
        static_cast<long>(1e-9 * static_cast<double>(labels[i].nominal.ns - clock.start.ns) / block_s);
    by_block[b].first += a.squaredNorm();
    by_block[b].second += a.dot(r);
    aa += a.squaredNorm();
    ar += a.dot(r);
  }
  ReadoutStep step;
  if (!(aa > 0)) return step;
  step.delta_s = -ar / aa;
  std::vector<double> per_block;
  for (const auto& [b, sums] : by_block)
    if (sums.first > 0.01 * aa / static_cast<double>(by_block.size()))
      per_block.push_back(-sums.second / sums.first);
  if (per_block.size() >= 3) {
    double mean = 0, ss = 0;
    for (double x : per_block) mean += x / static_cast<double>(per_block.size());
    for (double x : per_block) ss += (x - mean) * (x - mean);
    step.sd_s =
        std::sqrt(ss / static_cast<double>(per_block.size() - 1) / static_cast<double>(per_block.size()));
  }
  return step;
}

}  // namespace

CameraClock estimate_camera_clock(const HermiteTrack& track, const std::vector<ClockObservation>& labels,
                                  const SensorGeometry& sensor, const ClockSearchOptions& options,
                                  const std::string& source) {
  if (labels.size() < 20)
    throw_input_error(
        source, 0, "",
        fmt::format("{} labelled frames: finding the camera's clock needs at least 20", labels.size()));
  if (track.size() < 2) throw_input_error(source, 0, "", "the lamp track has fewer than 2 epochs");
  const UtcTime start = labels.front().nominal;
  const double span = 1e-9 * static_cast<double>(labels.back().nominal.ns - start.ns);
  auto seconds_after_start = [start](UtcTime t) { return 1e-9 * static_cast<double>(t.ns - start.ns); };
  // Step 1: the whole overlap — the frames' first instant may go from half the record before the
  // track's start to the track's end less half the record.
  const double track_first = seconds_after_start(track.epoch_time(0));
  const double track_last = seconds_after_start(track.epoch_time(track.size() - 1));
  const double lo = options.search_s ? options.search_s->first : track_first - 0.5 * span;
  const double hi = options.search_s ? options.search_s->second : track_last - 0.5 * span;
  if (!(hi >= lo))
    throw_input_error(
        source, 0, "",
        fmt::format("the labels span {:.1f} s and the lamp track {:.1f} s: no clock offset puts half "
                    "of the labels inside the track",
                    span, track_last - track_first));
  std::vector<std::size_t> all(labels.size()), sample;
  for (std::size_t i = 0; i < labels.size(); ++i) all[i] = i;
  const std::size_t n_sample = std::min(options.subsample, labels.size());
  for (std::size_t k = 0; k < n_sample; ++k) sample.push_back(k * labels.size() / n_sample);
  // The coarse step: a wrong offset by half a step must misplace the labels by less than the score's
  // truncation, so the right basin stands out — on a telephoto camera 0.2 s of lamp motion is
  // hundreds of pixels. The labels show their own image speed (px/s between consecutive labels).
  std::vector<double> speed;
  for (std::size_t i = 1; i < labels.size(); ++i) {
    const double dt = 1e-9 * static_cast<double>(labels[i].nominal.ns - labels[i - 1].nominal.ns);
    if (dt > 0 && dt < 1) speed.push_back((labels[i].uv - labels[i - 1].uv).norm() / dt);
  }
  double step = options.coarse_step_s;
  if (!speed.empty()) {
    const std::size_t p90 = speed.size() * 9 / 10;
    std::nth_element(speed.begin(), speed.begin() + static_cast<long>(p90), speed.end());
    if (speed[p90] > 0) step = std::clamp(0.5 * options.truncate_px / speed[p90], options.fine_step_s, step);
  }
  const std::vector<Scored> coarse = scan(track, labels, sample, start, lo, hi, step, options);
  const Scored best = *std::min_element(coarse.begin(), coarse.end(),
                                        [](const Scored& a, const Scored& b) { return a.score < b.score; });
  if (!std::isfinite(best.score))
    throw_input_error(
        source, 0, "",
        fmt::format("no clock offset between {:.1f} and {:.1f} s puts half of the labels inside the "
                    "lamp track with a camera that explains them",
                    lo, hi));
  CameraClock clock;
  clock.nominal_start = start;
  clock.search_best_score_px = best.score;
  for (const Scored& s : coarse)
    if (std::abs(s.offset_s - best.offset_s) > 2 &&
        (clock.search_other_score_px == 0 || s.score < clock.search_other_score_px)) {
      clock.search_other_score_px = s.score;
      clock.search_other_offset_s = s.offset_s;
    }
  if (clock.search_other_score_px > 0 && clock.search_other_score_px < options.ambiguity_ratio * best.score)
    throw_input_error(
        source, 0, "",
        fmt::format("the camera's clock offset is ambiguous: {:+.2f} s scores {:.2f} px and {:+.2f} s "
                    "{:.2f} px (truncated rms of a DLT); give track.clock_search_s [lo, hi] around the "
                    "right one",
                    best.offset_s, best.score, clock.search_other_offset_s, clock.search_other_score_px));
  // Step 2: offset and rate, every fine_step_s of the mid-record offset within ±fine_half_width_s and
  // every rate_step of rate within ±max_rate (step 1 holds the rate at 0, which fixes the clock at the
  // record's middle best: there the two agree).
  Clock current{start, best.offset_s, 0, options.readout_s, sensor.height_px};
  double best_fine = kInfinite;
  const long n_rates = std::lround(options.max_rate / options.rate_step);
  const long n_offsets = std::lround(std::max(options.fine_half_width_s, step) / options.fine_step_s);
  for (long i = -n_rates; i <= n_rates; ++i)
    for (long k = -n_offsets; k <= n_offsets; ++k) {
      const double rate = static_cast<double>(i) * options.rate_step;
      const double mid_offset = best.offset_s + static_cast<double>(k) * options.fine_step_s;
      const Clock trial{start, mid_offset - rate * 0.5 * span, rate, options.readout_s, sensor.height_px};
      const double score = dlt_score(track, labels, sample, trial, options);
      if (score < best_fine) {
        best_fine = score;
        current = trial;
      }
    }
  // Step 3: camera + offset, then the blocks' line, until the line moves nothing.
  std::vector<std::size_t> kept;
  Line line;
  for (int iteration = 0; iteration < 12; ++iteration) try {
      const std::vector<BundleObservation> obs =
          observations_at(track, labels, all, current, options.pixel_sigma_px, &kept);
      std::vector<PointCorrespondence> pts(obs.size());
      for (std::size_t k = 0; k < obs.size(); ++k) pts[k] = {obs[k].world, obs[k].pixel};
      const Camera initial = camera_from_krc(decompose_projection_matrix(trimmed_dlt(pts)), sensor);
      const BundleResult whole = bundle_adjust(
          initial, obs, refine_options(options, {"f", "u0", "v0", "k1", "k2", "pose", "clock_offset"}));
      const Camera camera = whole.calibration.camera;
      clock.rms_px = whole.calibration.reprojection.rms_px;
      clock.points = obs.size();
      // One offset per block, the camera held.
      clock.blocks.clear();
      const int n_blocks = std::max(1, static_cast<int>(std::ceil(span / options.block_s - 1e-9)));
      for (int b = 0; b < n_blocks; ++b) {
        std::vector<std::size_t> in_block;
        std::vector<BundleObservation> block_obs;
        for (std::size_t k = 0; k < obs.size(); ++k) {
          const double t = seconds_after_start(labels[kept[k]].nominal);
          if (t >= b * options.block_s && (t < (b + 1) * options.block_s || b + 1 == n_blocks) &&
              !whole.outlier[k]) {
            in_block.push_back(kept[k]);
            block_obs.push_back(obs[k]);
          }
        }
        if (block_obs.size() < options.min_block_points) continue;
        BundleOptions bo = refine_options(options, {"clock_offset"});
        bo.initial_clock_offset_s = whole.calibration.clock_offset_s;
        try {
          const BundleResult r = bundle_adjust(camera, block_obs, bo);
          if (r.rank_deficient || r.details.sigma_scaled.size() != 1) continue;
          double mid = 0;
          for (std::size_t i : in_block) mid += seconds_after_start(labels[i].nominal);
          // The bundle's δ is stamp − true time: the block's clock is `current` less δ.
          clock.blocks.push_back({mid / static_cast<double>(in_block.size()), -r.calibration.clock_offset_s,
                                  r.details.sigma_scaled(0), block_obs.size()});
        } catch (const Error&) {
          continue;  // a block the bundle cannot solve (too few distinct points) gives no offset
        }
      }
      if (clock.blocks.empty())
        throw_input_error(
            source, 0, "",
            fmt::format("no {:.0f}-s block of labels has {} points inside the lamp track to fix the "
                        "camera's clock",
                        options.block_s, options.min_block_points));
      line = fit_line(clock.blocks);
      current.offset_s += line.a;
      current.rate += line.b;
      for (ClockBlock& b : clock.blocks)
        b.deviation_s -= line.a + line.b * b.mid_s;  // now the residual about the line
      double readout_change = 0;
      if (options.estimate_readout) {
        std::vector<std::size_t> inliers;
        for (std::size_t k = 0; k < kept.size(); ++k)
          if (!whole.outlier[k]) inliers.push_back(kept[k]);
        const ReadoutStep step = readout_step(camera, track, labels, inliers, current,
                                              whole.calibration.clock_offset_s, options.block_s);
        current.readout_s += step.delta_s;
        clock.readout_sd_s = step.sd_s;
        readout_change = std::abs(step.delta_s) * 0.5;  // the most it moves a label (row at an edge)
      }
      if (std::abs(line.a) + std::abs(line.b) * span + readout_change < 5e-5) break;
    } catch (const Error& e) {
      if (e.kind() == ErrorKind::input) throw;
      throw_input_error(source, 0, "", std::string("the camera's clock could not be refined: ") + e.what());
    }
  clock.offset_s = current.offset_s;
  clock.rate = current.rate;
  clock.readout_s = current.readout_s;
  clock.image_height_px = sensor.height_px;
  // The lamp track's own error along the lamp's path is a time shift the labels cannot tell from the
  // clock's: a PPK error correlated over the record (Gauss–Markov, τ of minutes) moves the offset by
  // its size over the speed, and drifts it over the record. Its share: the median over the labels of
  // the fix's sd along the velocity over the speed; at most that drift across the record for the rate.
  std::vector<double> along;
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const TrackSample s = track.sample(current.at(labels[kept[k]]));
    const double speed = s.vel_enu.norm();
    if (s.status == TrackSampleStatus::ok && speed > 0.1)
      along.push_back(s.sd_enu.cwiseProduct(s.vel_enu).norm() / speed / speed);  // axes independent
  }
  if (!along.empty()) {
    std::nth_element(along.begin(), along.begin() + static_cast<long>(along.size() / 2), along.end());
    clock.track_sd_s = along[along.size() / 2];
  }
  const double track_var = clock.track_sd_s * clock.track_sd_s;
  line.cov(0, 0) += track_var;
  line.cov(1, 1) += 2 * track_var / std::max(span * span, 1.0);
  clock.offset_sd_s = std::sqrt(line.cov(0, 0));
  clock.rate_sd = std::sqrt(line.cov(1, 1));
  const Eigen::Vector2d g_mid(1, 0.5 * span);
  clock.mid_offset_sd_s = std::sqrt(g_mid.dot(line.cov * g_mid));
  clock.span_s = span;
  double dev2 = 0, sd2 = 0;
  std::size_t determined = 0;
  for (const ClockBlock& b : clock.blocks)
    if (b.sd_s <= options.vfr_block_sd_s) {
      clock.worst_block_deviation_s = std::max(clock.worst_block_deviation_s, std::abs(b.deviation_s));
      if (std::abs(b.deviation_s) > options.vfr_threshold_s) clock.variable_frame_rate = true;
      dev2 += b.deviation_s * b.deviation_s;
      sd2 += b.sd_s * b.sd_s;
      ++determined;
    }
  // The wander: the blocks' scatter about the line beyond their own σ (the line takes two degrees of
  // freedom). A frame outside the blocks the line was fitted to carries it: a variable frame rate's
  // stretches keep their own offsets, which no line through other stretches predicts.
  if (determined > 2) {
    const double excess = dev2 / static_cast<double>(determined - 2) - sd2 / static_cast<double>(determined);
    clock.wander_sd_s = std::sqrt(std::max(0.0, excess));
  }
  return clock;
}

}  // namespace rangecal
