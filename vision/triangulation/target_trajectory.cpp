#include "vision/triangulation/target_trajectory.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "config/chi2_quantile.hpp"
#include "config/error.hpp"

namespace rangecal {

namespace {

constexpr std::size_t kMaxWarnings = 20;

double median_interval_s(const std::vector<TimedLabel>& labels) {
  std::vector<double> d;
  for (std::size_t i = 1; i < labels.size(); ++i) d.push_back(seconds_between(labels[i - 1].t, labels[i].t));
  if (d.empty()) return 0;
  std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

void check_camera(const TrajectoryCamera& c) {
  if (!(std::isfinite(c.label_sigma_px) && c.label_sigma_px > 0))
    throw_input_error("", 0, "label_sigma_px", "camera " + c.id + ": the labels' σ must be positive");
  if (!(std::isfinite(c.model_sigma_px) && c.model_sigma_px >= 0))
    throw_input_error("", 0, "model_sigma_px",
                      "camera " + c.id + ": the model's σ must be a finite number ≥ 0");
  for (const TimedLabel& l : c.labels)
    if (!(std::isfinite(l.sigma_px) && l.sigma_px >= 0))
      throw_input_error("", l.line, "sigma_px",
                        "camera " + c.id + ": a label's σ must be positive (or 0: the camera's)");
  for (std::size_t i = 1; i < c.labels.size(); ++i)
    if (!(c.labels[i - 1].t < c.labels[i].t))
      throw_input_error("", c.labels[i].line, "frame",
                        "camera " + c.id + ": the target's labels are not in strictly increasing time");
}

// A camera's view of the target at t, with its label σ (px, as given) apart from the rest of its
// pick σ (the model's and the extrapolated lens's, px): the first is what the labels' variance
// component scales.
struct ViewAt {
  TriangulationView view;
  double label_sigma_px = 0;
  double other_sigma_px = 0;
  double weight = 0;  // where t lies between the two labels: 0 at the first, 1 at the second
};

// The camera's two labels around t, at most max_gap apart, and where t lies between them (0 at the
// first, 1 at the second); none when t is outside the labels or across a wider gap. On a label: it
// and a neighbour (for the image velocity).
struct LabelPair {
  std::size_t a = 0, b = 0;
  double weight = 0;
};

std::optional<LabelPair> label_pair_at(const TrajectoryCamera& c, double max_gap_s, UtcTime t) {
  const auto it = std::lower_bound(c.labels.begin(), c.labels.end(), t,
                                   [](const TimedLabel& l, UtcTime x) { return l.t < x; });
  if (it == c.labels.end()) return std::nullopt;
  const auto i = static_cast<std::size_t>(it - c.labels.begin());
  LabelPair p;
  if (it->t == t) {
    if (i + 1 < c.labels.size()) {
      p.a = i;
      p.b = i + 1;
    } else if (i > 0) {
      p.a = i - 1;
      p.b = i;
    } else {
      return std::nullopt;
    }
  } else {
    if (i == 0) return std::nullopt;
    p.a = i - 1;
    p.b = i;
  }
  const double span = seconds_between(c.labels[p.a].t, c.labels[p.b].t);
  if (!(span > 0) || span > max_gap_s) return std::nullopt;
  p.weight = seconds_between(c.labels[p.a].t, t) / span;
  return p;
}

// The camera's view of the target at t from its label pair (label_pair_at). Its label σ
// is the labels' σ interpolated, times `label_scale` and √((1 − w)² + w² + 2ρ·w(1 − w)): neighbouring
// labels whose errors correlate by ρ (1: the σ whole).
std::optional<ViewAt> view_at(const TrajectoryCamera& c, double max_gap_s, double extrapolation_px_per_px,
                              UtcTime t, double label_scale = 1, double rho = 1) {
  const std::optional<LabelPair> pair = label_pair_at(c, max_gap_s, t);
  if (!pair) return std::nullopt;
  const std::size_t ia = pair->a, ib = pair->b;
  const TimedLabel& a = c.labels[ia];
  const TimedLabel& b = c.labels[ib];
  const double span = seconds_between(a.t, b.t);
  const double w = pair->weight;
  ViewAt out;
  TriangulationView& v = out.view;
  v.camera = c.camera;
  v.calibration = c.calibration;
  v.uv_px = (1 - w) * a.uv_px + w * b.uv_px;
  // Interpolated like the timing σ: neighbouring labels' errors taken as one (a tracker's error
  // moves slowly from frame to frame), which never understates it.
  const auto sigma = [&](const TimedLabel& l) { return l.sigma_px > 0 ? l.sigma_px : c.label_sigma_px; };
  out.label_sigma_px = (1 - w) * sigma(a) + w * sigma(b);
  out.other_sigma_px = c.model_sigma_px;
  // Where the label lies outside what the calibration saw, the lens model is extrapolated: its error
  // there, which the calibration's covariance does not carry, taken to grow with the distance.
  const double outside_px = c.coverage.distance_outside_px(v.uv_px);
  if (std::isfinite(outside_px))
    out.other_sigma_px = std::hypot(out.other_sigma_px, extrapolation_px_per_px * outside_px);
  out.weight = w;
  const double shape = std::sqrt((1 - w) * (1 - w) + w * w + 2 * rho * w * (1 - w));
  v.pick_sigma_px = std::hypot(label_scale * shape * out.label_sigma_px, out.other_sigma_px);
  v.image_velocity_px_s = (b.uv_px - a.uv_px) / span;
  v.timing_sigma_s = (1 - w) * a.timing_sigma_s + w * b.timing_sigma_s;
  return out;
}

// Central differences over neighbours exactly one grid step away on each side (or one-sided at a
// stretch's ends); σ from the label and timing parts of both positions.
void add_velocities(Trajectory& out) {
  std::vector<TrajectoryPoint>& p = out.points;
  if (p.size() < 2) return;
  const double grid = median_step_s(p);
  for (std::size_t k = 0; k < p.size(); ++k) {
    // Neighbours farther than 1.5 grid steps lie across a gap: not differenced.
    const TrajectoryPoint* prev =
        k > 0 && seconds_between(p[k - 1].t, p[k].t) <= 1.5 * grid ? &p[k - 1] : nullptr;
    const TrajectoryPoint* next =
        k + 1 < p.size() && seconds_between(p[k].t, p[k + 1].t) <= 1.5 * grid ? &p[k + 1] : nullptr;
    const TrajectoryPoint* a = prev ? prev : &p[k];
    const TrajectoryPoint* b = next ? next : &p[k];
    if (a == b) continue;
    const double dt = seconds_between(a->t, b->t);
    p[k].velocity = (b->fix.point - a->fix.point) / dt;
    const Eigen::Matrix3d ca = a->fix.cov_pick_m2 + a->fix.cov_timing_m2;
    const Eigen::Matrix3d cb = b->fix.cov_pick_m2 + b->fix.cov_timing_m2;
    p[k].velocity_sd = ((ca + cb).diagonal() / (dt * dt)).cwiseSqrt();
  }
}

// The calibrations' errors whitened, u ~ N(0, I) (label_variance_components.hpp): per camera the rows
// S_c of Σ_θ = S·Sᵀ over its parameters and the first of u's entries they reach. Cameras without
// cross blocks each get their own entries (Σ_θ block-diagonal); with cross blocks every camera
// reaches all of them.
struct WhitenedCalibration {
  std::vector<Eigen::MatrixXd> rows;  // per camera: p_c × w_c
  std::vector<Eigen::Index> offset;   // per camera
  Eigen::Index dim = 0;
};

// S with Σ = S·Sᵀ from Σ's eigen-decomposition, directions of no variance dropped.
Eigen::MatrixXd square_root(const Eigen::MatrixXd& sigma) {
  if (sigma.size() == 0) return Eigen::MatrixXd(sigma.rows(), 0);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (sigma + sigma.transpose()));
  const double top = es.eigenvalues().size() > 0 ? es.eigenvalues().maxCoeff() : 0;
  std::vector<Eigen::Index> keep;
  for (Eigen::Index i = 0; i < es.eigenvalues().size(); ++i)
    if (es.eigenvalues()(i) > 1e-12 * top && es.eigenvalues()(i) > 0) keep.push_back(i);
  Eigen::MatrixXd S(sigma.rows(), static_cast<Eigen::Index>(keep.size()));
  for (std::size_t k = 0; k < keep.size(); ++k)
    S.col(static_cast<Eigen::Index>(k)) =
        es.eigenvectors().col(keep[k]) * std::sqrt(es.eigenvalues()(keep[k]));
  return S;
}

WhitenedCalibration whiten_calibrations(const std::vector<TrajectoryCamera>& cameras,
                                        const CrossCovariances* cross) {
  WhitenedCalibration w;
  const std::size_t n = cameras.size();
  w.rows.resize(n);
  w.offset.assign(n, 0);
  bool joint = false;
  if (cross)
    for (std::size_t i = 0; i < cross->size() && i < n; ++i)
      for (std::size_t j = 0; j < (*cross)[i].size() && j < n; ++j)
        joint = joint || (i != j && (*cross)[i][j].size() > 0);
  if (!joint) {
    for (std::size_t c = 0; c < n; ++c) {
      w.rows[c] = square_root(cameras[c].calibration.covariance);
      w.offset[c] = w.dim;
      w.dim += w.rows[c].cols();
    }
    return w;
  }
  std::vector<Eigen::Index> at(n, 0);
  Eigen::Index p = 0;
  for (std::size_t c = 0; c < n; ++c) {
    at[c] = p;
    p += cameras[c].calibration.covariance.rows();
  }
  Eigen::MatrixXd sigma = Eigen::MatrixXd::Zero(p, p);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Index pi = cameras[i].calibration.covariance.rows();
    sigma.block(at[i], at[i], pi, pi) = cameras[i].calibration.covariance;
    for (std::size_t j = 0; j < n; ++j) {
      const Eigen::Index pj = cameras[j].calibration.covariance.rows();
      if (i == j || i >= cross->size() || j >= (*cross)[i].size()) continue;
      const Eigen::MatrixXd& b = (*cross)[i][j];
      if (b.rows() == pi && b.cols() == pj) sigma.block(at[i], at[j], pi, pj) = b;
    }
  }
  const Eigen::MatrixXd S = square_root(sigma);
  for (std::size_t c = 0; c < n; ++c)
    w.rows[c] = S.middleRows(at[c], cameras[c].calibration.covariance.rows());
  w.dim = S.cols();
  return w;
}

// Each camera's label σ from the views' disagreement (label_variance_components.hpp) over at most
// `max_instants` instants seen by two cameras or more, evenly spread over the track: each is
// triangulated under the σ given and linearised at its point; the calibrations' errors enter as one
// draw common to every instant.
LabelVcResult estimate_label_sigma(const std::vector<TrajectoryCamera>& cameras,
                                   const std::vector<UtcTime>& instants, const std::vector<double>& max_gap_s,
                                   const CrossCovariances* cross, const TrajectoryOptions& options) {
  const WhitenedCalibration whitened = whiten_calibrations(cameras, cross);
  std::vector<std::size_t> judged;  // instants with two views or more
  for (std::size_t k = 0; k < instants.size(); ++k) {
    int n = 0;
    for (std::size_t c = 0; c < cameras.size() && n < 2; ++c)
      n += label_pair_at(cameras[c], max_gap_s[c], instants[k]) ? 1 : 0;
    if (n >= 2) judged.push_back(k);
  }
  const std::size_t take = std::min(judged.size(), options.label_sigma_max_instants);
  std::vector<LabelVcInstant> sample;
  sample.reserve(take);
  for (std::size_t s = 0; s < take; ++s) {
    const UtcTime t = instants[judged[s * judged.size() / take]];
    std::vector<ViewAt> at;
    std::vector<TriangulationView> views;
    std::vector<std::size_t> used;
    for (std::size_t c = 0; c < cameras.size(); ++c)
      if (auto v = view_at(cameras[c], max_gap_s[c], options.extrapolation_sigma_px_per_px, t)) {
        views.push_back(v->view);
        at.push_back(std::move(*v));
        used.push_back(c);
      }
    LabelVcInstant inst;
    try {
      const TriangulationResult fix = triangulate_point(views, "the target at " + format_iso8601_utc(t, 3));
      for (std::size_t i = 0; i < views.size(); ++i) {
        LabelVcView lv;
        lv.camera = used[i];
        lv.residual_px = fix.residuals_px[i];
        pixel_jacobian_wrt_parameters(views[i].camera, {}, fix.point, &lv.d_pixel_d_point);
        lv.label_sigma_px = at[i].label_sigma_px;
        lv.interpolation_weight = at[i].weight;
        const TriangulationView& v = views[i];
        lv.fixed_cov_px2 =
            at[i].other_sigma_px * at[i].other_sigma_px * Eigen::Matrix2d::Identity() +
            v.timing_sigma_s * v.timing_sigma_s * v.image_velocity_px_s * v.image_velocity_px_s.transpose();
        const TrajectoryCamera& cam = cameras[used[i]];
        if (whitened.rows[used[i]].cols() > 0) {
          lv.d_pixel_d_common =
              pixel_jacobian_wrt_parameters(v.camera, cam.calibration.parameters, fix.point) *
              whitened.rows[used[i]];
          lv.common_offset = whitened.offset[used[i]];
        }
        inst.push_back(lv);
      }
    } catch (const Error& e) {
      if (e.kind() == ErrorKind::input) throw;
      continue;  // the main pass reports it
    }
    sample.push_back(std::move(inst));
  }
  return estimate_label_variance_components(sample, cameras.size(), whitened.dim, options.label_sigma);
}

}  // namespace

double median_step_s(const std::vector<TrajectoryPoint>& points) {
  std::vector<double> steps;
  for (std::size_t k = 1; k < points.size(); ++k)
    steps.push_back(seconds_between(points[k - 1].t, points[k].t));
  if (steps.empty()) return 0;
  std::nth_element(steps.begin(), steps.begin() + static_cast<long>(steps.size() / 2), steps.end());
  return steps[steps.size() / 2];
}

double fastest_label_rate_hz(const std::vector<TrajectoryCamera>& cameras) {
  double best = 0;
  for (const TrajectoryCamera& c : cameras) {
    const double d = median_interval_s(c.labels);
    if (d > 0) best = std::max(best, 1 / d);
  }
  return best;
}

std::vector<UtcTime> trajectory_instants(const std::vector<TrajectoryCamera>& cameras, double rate_hz) {
  // Two or more cameras: from the second-earliest first label to the second-latest last label.
  std::vector<std::int64_t> starts, ends;
  for (const TrajectoryCamera& c : cameras)
    if (c.labels.size() >= 2) {
      starts.push_back(c.labels.front().t.ns);
      ends.push_back(c.labels.back().t.ns);
    }
  std::vector<UtcTime> out;
  if (starts.size() < 2 || !(rate_hz > 0)) return out;
  std::sort(starts.begin(), starts.end());
  std::sort(ends.begin(), ends.end());
  const std::int64_t first = starts[1], last = ends[ends.size() - 2];
  constexpr std::int64_t kSecond = 1000000000;
  const std::int64_t second =
      first >= 0 ? first / kSecond * kSecond : (first - kSecond + 1) / kSecond * kSecond;
  const double step_ns = 1e9 / rate_hz;
  const auto k0 = static_cast<std::int64_t>(std::ceil(static_cast<double>(first - second) / step_ns - 1e-9));
  for (std::int64_t k = k0;; ++k) {
    const std::int64_t t = second + std::llround(static_cast<double>(k) * step_ns);
    if (t > last) break;
    out.push_back(UtcTime{t});
  }
  return out;
}

Trajectory estimate_trajectory(const std::vector<TrajectoryCamera>& cameras,
                               const std::vector<UtcTime>& instants, const CrossCovariances* cross,
                               const TrajectoryOptions& options) {
  if (!(std::isfinite(options.extrapolation_sigma_px_per_px) && options.extrapolation_sigma_px_per_px >= 0))
    throw_input_error("", 0, "extrapolation_sigma_px_per_px", "must be a finite number ≥ 0");
  std::vector<double> max_gap_s(cameras.size());
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    check_camera(cameras[c]);
    max_gap_s[c] = options.max_gap_frames * median_interval_s(cameras[c].labels);
  }
  Trajectory out;
  out.instants = instants.size();
  std::vector<double> scale(cameras.size(), 1.0), rho(cameras.size(), 1.0);
  if (options.estimate_label_sigma) {
    out.label_sigma = estimate_label_sigma(cameras, instants, max_gap_s, cross, options);
    out.label_sigma_estimated = true;
    scale = out.label_sigma.sigma_scale;
    rho = out.label_sigma.correlation;
  }
  for (const UtcTime t : instants) {
    std::vector<TriangulationView> views;
    std::vector<std::size_t> used;
    for (std::size_t c = 0; c < cameras.size(); ++c)
      if (auto v =
              view_at(cameras[c], max_gap_s[c], options.extrapolation_sigma_px_per_px, t, scale[c], rho[c])) {
        views.push_back(std::move(v->view));
        used.push_back(c);
      }
    if (views.size() < 2) {
      out.single_camera += views.size() == 1 ? 1 : 0;
      continue;
    }
    CrossCovariances sub;
    if (cross && !cross->empty()) {
      sub.assign(used.size(), std::vector<Eigen::MatrixXd>(used.size()));
      for (std::size_t i = 0; i < used.size(); ++i)
        for (std::size_t j = 0; j < used.size(); ++j)
          if (used[i] < cross->size() && used[j] < (*cross)[used[i]].size())
            sub[i][j] = (*cross)[used[i]][used[j]];
    }
    TrajectoryPoint p;
    p.t = t;
    try {
      p.fix =
          triangulate_point(views, "the target at " + format_iso8601_utc(t, 3), sub.empty() ? nullptr : &sub);
    } catch (const Error& e) {
      if (e.kind() == ErrorKind::input) throw;
      if (out.warnings.size() < kMaxWarnings) out.warnings.push_back(e.what());
      continue;
    }
    // The views' χ² under everything that moves a residual: the labels' and timing σ and the
    // calibrations' covariance projected to the pixels, cross blocks included — the weights the
    // point was solved with.
    p.chi2 = p.fix.weighted_chi2;
    p.dof = 2 * static_cast<int>(views.size()) - 3;
    if (p.chi2 > chi2_quantile_wilson_hilferty(p.dof, kNormalQuantile99)) {
      const double f = p.chi2 / p.dof;
      p.inflated = true;
      p.fix.cov_pick_m2 *= f;
      p.fix.cov_timing_m2 *= f;
      p.fix.cov_calibration_m2 *= f;
      p.fix.cov_m2 *= f;
      p.fix.sigma_m *= std::sqrt(f);
    }
    for (std::size_t i = 0; i < used.size(); ++i) {
      p.cameras.push_back(cameras[used[i]].id);
      if (!cameras[used[i]].coverage.covers(views[i].uv_px)) p.extrapolated.push_back(cameras[used[i]].id);
    }
    out.points.push_back(std::move(p));
  }
  add_velocities(out);
  return out;
}

}  // namespace rangecal
