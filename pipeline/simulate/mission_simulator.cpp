#include "pipeline/simulate/mission_simulator.hpp"

#include <tbb/parallel_for.h>

#include <GeographicLib/LocalCartesian.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "config/atomic_file.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"
#include "gnss/formats/rtklib_pos_writer.hpp"
#include "gnss/track/lever_arm.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/io/progress_bar.hpp"
#include "pipeline/simulate/ppk_error.hpp"
#include "vision/frames/frame_renderer.hpp"

namespace rangecal {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kGravity = 9.80665;

// Independent random streams (config/deterministic_random.hpp mix_seed): each purpose (GNSS
// noise, survey noise, picks of camera i, frame n of camera i, …) gets its own seed, so adding frames
// or poles never changes the other draws.
enum Stream : std::uint64_t {
  kGnssNoise = 1,
  kGnssFloat = 2,
  kWobble = 3,
  kSurvey = 4,
  kPicks = 5,
  kHotPixels = 6,
  kFrames = 7,
  kGnssGaussMarkov = 8,
  kGnssFlightBias = 9,
};

// FNV-1a of a camera id: a frame's noise seed follows the camera's name, not its position.
std::uint64_t fnv1a(const std::string& text) {
  std::uint64_t h = 0xCBF29CE484222325ull;
  for (unsigned char ch : text) h = (h ^ ch) * 0x100000001B3ull;
  return h;
}

std::int64_t seconds_to_ns(double s) {
  return static_cast<std::int64_t>(std::llround(s * 1e9));
}

// Position and velocity along a move leg with a trapezoidal speed profile (or a triangular one
// when the leg is too short to reach the cruise speed).
void leg_motion(const FlightPathLeg& leg, double t, Eigen::Vector3d* p, Eigen::Vector3d* v) {
  if (leg.hover) {
    *p = leg.from;
    *v = Eigen::Vector3d::Zero();
    return;
  }
  const Eigen::Vector3d d = leg.to - leg.from;
  const double L = d.norm();
  const Eigen::Vector3d dir = d / L;
  const double a = leg.accel_mps2, vp = leg.peak_speed_mps, T = leg.t1_s - leg.t0_s;
  const double ta = vp / a;
  const double tau = std::clamp(t - leg.t0_s, 0.0, T);
  double s, sp;
  if (tau < ta) {
    s = 0.5 * a * tau * tau;
    sp = a * tau;
  } else if (tau > T - ta) {
    const double r = T - tau;
    s = L - 0.5 * a * r * r;
    sp = a * r;
  } else {
    s = 0.5 * a * ta * ta + vp * (tau - ta);
    sp = vp;
  }
  *p = leg.from + dir * s;
  *v = dir * sp;
}

FlightPathLeg make_move(double t0, const Eigen::Vector3d& from, const Eigen::Vector3d& to, double speed,
                        double accel, int route) {
  FlightPathLeg leg;
  leg.t0_s = t0;
  leg.from = from;
  leg.to = to;
  leg.route = route;
  leg.accel_mps2 = accel;
  const double L = (to - from).norm();
  leg.peak_speed_mps = L < speed * speed / accel ? std::sqrt(accel * L) : speed;  // triangular or trapezoid
  leg.t1_s = t0 + straight_leg_duration_s(L, speed, accel);
  return leg;
}

FlightPathLeg make_hover(double t0, const Eigen::Vector3d& at, double duration, int route) {
  FlightPathLeg leg;
  leg.t0_s = t0;
  leg.t1_s = t0 + duration;
  leg.from = leg.to = at;
  leg.route = route;
  leg.hover = true;
  return leg;
}

void antenna_motion(const FlightPath& path, double t, Eigen::Vector3d* p, Eigen::Vector3d* v) {
  const auto it = std::lower_bound(path.legs.begin(), path.legs.end(), t,
                                   [](const FlightPathLeg& l, double x) { return l.t1_s < x; });
  leg_motion(it == path.legs.end() ? path.legs.back() : *it, t, p, v);
}

// A hovering multirotor's attitude wobble: per axis two sinusoids with seeded frequencies
// (0.15–0.6 Hz) and phases; roll and pitch with amplitude `wobble_deg`, yaw half of it.
struct Wobble {
  double f[3][2], ph[3][2];
};

Wobble make_wobble(std::uint64_t seed) {
  RenderRandom rng(mix_seed(seed, kWobble));
  Wobble w;
  for (int a = 0; a < 3; ++a)
    for (int k = 0; k < 2; ++k) {
      w.f[a][k] = 0.15 + 0.45 * rng.uniform();
      w.ph[a][k] = 2.0 * M_PI * rng.uniform();
    }
  return w;
}

double wobble_value(const Wobble& w, int axis, double t) {
  return 0.7 * std::sin(2 * M_PI * w.f[axis][0] * t + w.ph[axis][0]) +
         0.3 * std::sin(2 * M_PI * w.f[axis][1] * t + w.ph[axis][1]);
}

SimState state_with(const Scenario& s, const FlightPath& path, const Wobble& w, double t) {
  t = std::clamp(t, 0.0, path.duration_s());
  SimState st;
  antenna_motion(path, t, &st.antenna_enu, &st.velocity_enu);
  const double A = s.attitude.wobble_deg;
  Attitude& att = st.attitude;
  att.roll_deg = A * wobble_value(w, 0, t);
  att.pitch_deg = A * wobble_value(w, 1, t);
  att.yaw_deg = wrap_deg_180(s.attitude.yaw_deg + 0.5 * A * wobble_value(w, 2, t));
  if (s.attitude.tilt_with_acceleration) {
    // A multirotor accelerates horizontally by tilting its thrust: pitch nose-down to speed up
    // forward, roll right to accelerate right. The acceleration is the mean over ±0.25 s (the
    // airframe's response time), which keeps the attitude continuous across the profile's kinks.
    Eigen::Vector3d p0, v0, p1, v1;
    antenna_motion(path, std::max(0.0, t - 0.25), &p0, &v0);
    antenna_motion(path, std::min(path.duration_s(), t + 0.25), &p1, &v1);
    const Eigen::Vector3d acc = (v1 - v0) / 0.5;  // ENU
    const double psi = att.yaw_deg * kDeg;
    const double a_fwd = acc.y() * std::cos(psi) + acc.x() * std::sin(psi);
    const double a_right = -acc.y() * std::sin(psi) + acc.x() * std::cos(psi);
    att.pitch_deg += -std::atan(a_fwd / kGravity) / kDeg;
    att.roll_deg += std::atan(a_right / kGravity) / kDeg;
  }
  st.lamp_enu = lamp_enu_full(st.antenna_enu, rotation_nb(att), s.lever_arm_frd_m);
  return st;
}

double dn_scale(int bit_depth) {
  return bit_depth == 8 ? 255.0 / 65535.0 : 1.0;
}

nlohmann::ordered_json vec_json(const Eigen::VectorXd& v) {
  nlohmann::ordered_json a = nlohmann::ordered_json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(v[i]);
  return a;
}

// The correlated PPK error (docs/simulator.md "PPK error model") added to the epochs' white noise, from
// its own streams, so the white-noise and float draws stay as they were. A flight is the run of epochs
// between two gaps: a new flight, with a new bias, starts at the first epoch after a gap. The .pos sd
// becomes the total √(white² + σ_GM²).
void add_correlated_ppk_error(const Scenario& s, std::vector<SimEpoch>* epochs) {
  const PpkCorrelatedError& c = s.gnss.correlated_error;
  if (!c.active()) return;
  std::vector<double> times;
  std::vector<int> flights;
  for (const SimEpoch& e : *epochs) {
    bool after_gap = false;
    for (const TimeInterval& g : s.gnss.gaps)
      after_gap = after_gap || (!times.empty() && g.start_s < e.t_s && g.end_s > times.back());
    flights.push_back(flights.empty() ? 0 : flights.back() + (after_gap ? 1 : 0));
    times.push_back(e.t_s);
  }
  const auto err = draw_ppk_correlated_error(c, times, flights, mix_seed(s.seed, kGnssGaussMarkov),
                                             mix_seed(s.seed, kGnssFlightBias));
  for (std::size_t i = 0; i < epochs->size(); ++i) {
    (*epochs)[i].antenna_measured += err[i];
    (*epochs)[i].sd_enu = reported_sd_m((*epochs)[i].sd_enu, c);
  }
}

// truth.json's echo of the correlated PPK error, only when the scenario has one (white-noise scenarios
// keep their bytes).
void add_correlated_ppk_error_json(const PpkCorrelatedError& c, nlohmann::ordered_json* noise) {
  if (c.has_gauss_markov())
    (*noise)["gnss_gauss_markov"] = {{"sd_enu_m", vec_json(c.gm_sd_m)}, {"tau_enu_s", vec_json(c.gm_tau_s)}};
  if (c.has_flight_bias()) (*noise)["gnss_flight_bias_sd_enu_m"] = vec_json(c.flight_bias_sd_m);
}

}  // namespace

FlightPath make_flight_path(const Scenario& s) {
  FlightPath path;
  double t = 0;
  for (std::size_t i = 0; i < s.routes.size(); ++i) {
    const ScenarioRoute& r = s.routes[i];
    const int ri = static_cast<int>(i);
    if (i > 0) {
      const Eigen::Vector3d from = s.routes[i - 1].end_enu_m;
      if ((r.start_enu_m - from).norm() > 1e-3) {
        path.legs.push_back(make_move(t, from, r.start_enu_m, s.transit_speed_mps, s.transit_accel_mps2, -1));
        t = path.legs.back().t1_s;
      }
    }
    if (r.hover_s > 0) {
      path.legs.push_back(make_hover(t, r.start_enu_m, r.hover_s, ri));
      t = path.legs.back().t1_s;
    }
    path.legs.push_back(make_move(t, r.start_enu_m, r.end_enu_m, r.speed_mps, r.accel_mps2, ri));
    t = path.legs.back().t1_s;
    if (r.hover_s > 0) {
      path.legs.push_back(make_hover(t, r.end_enu_m, r.hover_s, ri));
      t = path.legs.back().t1_s;
    }
  }
  return path;
}

SimState state_at(const Scenario& s, const FlightPath& path, double t_s) {
  return state_with(s, path, make_wobble(s.seed), t_s);
}

namespace {

/// GNSS epochs at k/rate, the antenna position + noise (float epochs noisier, Q=2).
std::vector<SimEpoch> simulate_gnss_epochs(const Scenario& s, const FlightPath& path, const Wobble& wob) {
  std::vector<SimEpoch> epochs;
  const double duration = path.duration_s();
  RenderRandom noise(mix_seed(s.seed, kGnssNoise)), flt(mix_seed(s.seed, kGnssFloat));
  const double period_ns = 1e9 / s.gnss.rate_hz;
  for (std::int64_t k = 0;; ++k) {
    const std::int64_t tn = static_cast<std::int64_t>(std::llround(k * period_ns));
    const double t = tn * 1e-9;
    if (t > duration + 1e-9) break;
    // Draw for every epoch, in or out of a gap, so the draws do not depend on the gaps.
    const double u_float = flt.uniform();
    const Eigen::Vector3d z(noise.normal(), noise.normal(), noise.normal());
    bool in_gap = false;
    for (const auto& g : s.gnss.gaps) in_gap = in_gap || g.contains(t);
    if (in_gap) continue;
    bool is_float = u_float < s.gnss.float_fraction;
    for (const auto& f : s.gnss.float_intervals) is_float = is_float || f.contains(t);
    const SimState st = state_with(s, path, wob, t);
    SimEpoch e;
    e.t_s = t;
    e.utc = UtcTime{s.start_utc.ns + tn};
    e.antenna_true = st.antenna_enu;
    e.lamp_true = st.lamp_enu;
    e.attitude = st.attitude;
    e.quality = is_float ? 2 : 1;
    e.sd_enu = s.gnss.noise_sd_m * (is_float ? s.gnss.float_noise_factor : 1.0);
    e.antenna_measured = st.antenna_enu + e.sd_enu.cwiseProduct(z);
    epochs.push_back(e);
  }
  return epochs;
}

/// Attitude log at its rate (times rounded to the microsecond, as written).
std::vector<SimAttitudeSample> simulate_attitude_log(const Scenario& s, const FlightPath& path,
                                                     const Wobble& wob) {
  std::vector<SimAttitudeSample> attitude;
  const double duration = path.duration_s();
  const double period_us = 1e6 / s.attitude.rate_hz;
  for (std::int64_t k = 0;; ++k) {
    const std::int64_t tus = static_cast<std::int64_t>(std::llround(k * period_us));
    const double t = tus * 1e-6;
    if (t > duration + 1e-9) break;
    attitude.push_back({UtcTime{s.start_utc.ns + tus * 1000}, state_with(s, path, wob, t).attitude});
  }
  return attitude;
}

/// Poles: survey noise.
std::vector<SimPole> simulate_pole_survey(const Scenario& s) {
  std::vector<SimPole> poles;
  RenderRandom rng(mix_seed(s.seed, kSurvey));
  for (const auto& p : s.poles) {
    SimPole sp;
    sp.truth = p;
    const Eigen::Vector3d z(rng.normal(), rng.normal(), rng.normal());
    sp.surveyed_enu = p.enu_m + s.survey_noise_m * z;
    poles.push_back(sp);
  }
  return poles;
}

/// Camera ci: exported frames with the true lamp pixel, hot pixels, pole picks.
SimCamera simulate_camera(const Scenario& s, const FlightPath& path, const Wobble& wob, std::size_t ci) {
  const double duration = path.duration_s();
  SimCamera sc;
  sc.spec = s.cameras[ci];
  const Camera& cam = sc.spec.camera;
  const std::int64_t start_ns = seconds_to_ns(sc.spec.start_s);
  const std::int64_t offset_ns = seconds_to_ns(sc.spec.clock_offset_s);
  for (std::int64_t n = 0;; n += sc.spec.export_step) {
    const std::int64_t tn = start_ns + static_cast<std::int64_t>(std::llround(n * 1e9 / sc.spec.fps));
    const double t = tn * 1e-9;
    if (t > duration + 1e-9) break;
    if (t < 0) continue;
    SimFrame f;
    f.frame = n;
    f.true_utc = UtcTime{s.start_utc.ns + tn};
    f.stamp_utc = UtcTime{f.true_utc.ns + offset_ns};
    char name[96];
    std::snprintf(name, sizeof name, "frames/%s_%07lld.png", sc.spec.id.c_str(), static_cast<long long>(n));
    f.file = name;
    f.lamp_enu = state_with(s, path, wob, t).lamp_enu;
    constexpr double h = 1e-3;
    f.lamp_velocity_enu =
        (state_with(s, path, wob, t + h).lamp_enu - state_with(s, path, wob, t - h).lamp_enu) / (2 * h);
    f.projects = project(cam, f.lamp_enu, &f.lamp_px);
    f.in_view = f.projects && inside_image(cam.intr, f.lamp_px);
    sc.frames.push_back(f);
  }
  sc.hot_pixels =
      random_hot_pixels(cam.intr.width_px, cam.intr.height_px, s.sky.hot_pixels, 0.5 * s.sky.hot_pixel_excess,
                        s.sky.hot_pixel_excess, mix_seed(s.seed, kHotPixels, ci));
  RenderRandom rng(mix_seed(s.seed, kPicks, ci));
  for (const auto& p : s.poles) {
    const Eigen::Vector2d z(rng.normal(), rng.normal());
    Eigen::Vector2d uv;
    if (!project(cam, p.enu_m, &uv) || !inside_image(cam.intr, uv)) continue;
    sc.picks.push_back({p.id, uv, uv + s.pick_noise_px * z});
  }
  return sc;
}

}  // namespace

SimMission simulate_mission(const Scenario& s) {
  SimMission m;
  m.scenario = s;
  m.path = make_flight_path(s);
  const Wobble wob = make_wobble(s.seed);
  m.epochs = simulate_gnss_epochs(s, m.path, wob);
  add_correlated_ppk_error(s, &m.epochs);
  m.attitude = simulate_attitude_log(s, m.path, wob);
  m.poles = simulate_pole_survey(s);
  for (std::size_t ci = 0; ci < s.cameras.size(); ++ci)
    m.cameras.push_back(simulate_camera(s, m.path, wob, ci));
  return m;
}

cv::Mat render_sim_frame(const SimMission& m, const SimCamera& cam, const SimFrame& f) {
  const Scenario& s = m.scenario;
  const CameraIntrinsics& in = cam.spec.camera.intr;
  const double k = dn_scale(cam.spec.bit_depth);
  FrameRenderSettings st;
  st.width = in.width_px;
  st.height = in.height_px;
  st.bits = cam.spec.bit_depth;
  st.sky_level = s.sky.background * k;
  st.sky_gradient_u = s.sky.gradient.x() * k;
  st.sky_gradient_v = s.sky.gradient.y() * k;
  st.read_noise = s.sky.read_noise * k;
  st.gain = 0;
  // The same hot pixels in every frame of the camera.
  for (const HotPixel& h : cam.hot_pixels) st.hot_pixels.push_back({h.u, h.v, h.excess * k});
  if (s.sky.distractor)
    st.static_lights.push_back({s.sky.distractor->u_px, s.sky.distractor->v_px, s.sky.distractor->sigma_px,
                                s.sky.distractor->peak * k});
  std::vector<PsfSpot> spots;
  // The PSF reaches ~6σ; a lamp farther outside the image leaves no trace.
  const double margin = 6 * s.lamp.psf_sigma_px + 2;
  if (f.projects && f.lamp_px.x() > -margin && f.lamp_px.y() > -margin &&
      f.lamp_px.x() < in.width_px + margin && f.lamp_px.y() < in.height_px + margin)
    spots.push_back({f.lamp_px.x(), f.lamp_px.y(), s.lamp.psf_sigma_px, s.lamp.peak * k});
  cv::Mat img = render_frame(
      st, spots, mix_seed(s.seed, kFrames, fnv1a(cam.spec.id), static_cast<std::uint64_t>(f.frame)));
  const double full = std::ldexp(1.0, cam.spec.bit_depth) - 1;
  const double sat = std::floor(s.lamp.saturation * k);
  if (sat < full) img = cv::min(img, sat);
  return img;
}

std::string format_truth_json(const SimMission& m) {
  using J = nlohmann::ordered_json;
  const Scenario& s = m.scenario;
  J j;
  j["format"] = "rangecal simulation truth v1";
  j["mission"] = s.mission;
  j["seed"] = s.seed;
  j["start_utc"] = format_iso8601_utc(s.start_utc, 9);
  j["site"] = {{"origin", {{"lat", s.origin.lat_deg}, {"lon", s.origin.lon_deg}, {"h", s.origin.h_m}}}};
  j["lever_arm"] = {{"body_frd_m", vec_json(s.lever_arm_frd_m)}};
  j["noise"] = {{"gnss_sd_enu_m", vec_json(s.gnss.noise_sd_m)},
                {"gnss_float_noise_factor", s.gnss.float_noise_factor},
                {"survey_sd_m", s.survey_noise_m},
                {"pick_sd_px", s.pick_noise_px},
                {"read_noise_dn16", s.sky.read_noise},
                {"lamp_peak_dn16", s.lamp.peak},
                {"lamp_psf_sigma_px", s.lamp.psf_sigma_px},
                {"lamp_peak_snr", s.sky.read_noise > 0 ? s.lamp.peak / s.sky.read_noise : 0.0}};
  add_correlated_ppk_error_json(s.gnss.correlated_error, &j["noise"]);
  J cams = J::array();
  for (const SimCamera& c : m.cameras) {
    const Camera& cam = c.spec.camera;
    J cj;
    cj["id"] = c.spec.id;
    cj["image_size_px"] = {cam.intr.width_px, cam.intr.height_px};
    cj["pixel_size_um"] = {cam.intr.dx_mm * 1e3, cam.intr.dy_mm * 1e3};
    cj["focal_mm"] = cam.intr.f_mm;
    cj[parameter_name(CameraParameter::sx)] = cam.intr.sx;
    cj["principal_point_px"] = {cam.intr.u0_px, cam.intr.v0_px};
    J d;
    d["model"] = "seed000_eq7";
    const auto da = cam.intr.dist.as_array();
    for (std::size_t i = 0; i < 7; ++i) d[distortion_json_keys()[i]] = da[i];
    cj["distortion"] = d;
    J R = J::array();
    for (int r = 0; r < 3; ++r) R.push_back(vec_json(cam.pose.R.row(r).transpose()));
    cj["rotation_world_to_camera"] = R;
    cj["translation_m"] = vec_json(cam.pose.T);
    cj["center_enu_m"] = vec_json(cam.pose.center());
    cj["fps"] = c.spec.fps;
    cj["export_step"] = c.spec.export_step;
    cj["bit_depth"] = c.spec.bit_depth;
    cj["clock_offset_s"] = c.spec.clock_offset_s;
    cj["start_s"] = c.spec.start_s;
    J hp = J::array();
    for (const HotPixel& h : c.hot_pixels) hp.push_back({{"u", h.u}, {"v", h.v}, {"excess_dn16", h.excess}});
    cj["hot_pixels_uv"] = hp;
    J fr = J::array();
    for (const SimFrame& f : c.frames) {
      J fj;
      fj["frame"] = f.frame;
      fj["file"] = f.file;
      fj["stamp_utc"] = format_iso8601_utc(f.stamp_utc, 9);
      fj["true_utc"] = format_iso8601_utc(f.true_utc, 9);
      fj["lamp_enu_m"] = vec_json(f.lamp_enu);
      fj["lamp_px"] = f.projects ? J(vec_json(f.lamp_px)) : J(nullptr);
      fj["in_view"] = f.in_view;
      fr.push_back(fj);
    }
    cj["frames"] = fr;
    J pk = J::array();
    for (const SimPick& p : c.picks)
      pk.push_back({{"id", p.id}, {"true_px", vec_json(p.true_px)}, {"picked_px", vec_json(p.picked_px)}});
    cj["poles_px"] = pk;
    cams.push_back(cj);
  }
  j["cameras"] = cams;
  J poles = J::array();
  for (const SimPole& p : m.poles)
    poles.push_back({{"id", p.truth.id},
                     {"role", p.truth.role},
                     {"true_enu_m", vec_json(p.truth.enu_m)},
                     {"surveyed_enu_m", vec_json(p.surveyed_enu)}});
  j["poles"] = poles;
  J eps = J::array();
  for (const SimEpoch& e : m.epochs) {
    J ej;
    ej["utc"] = format_iso8601_utc(e.utc, 9);
    ej["t_s"] = e.t_s;
    ej["quality"] = e.quality;
    ej["antenna_true_enu_m"] = vec_json(e.antenna_true);
    ej["antenna_measured_enu_m"] = vec_json(e.antenna_measured);
    ej["lamp_true_enu_m"] = vec_json(e.lamp_true);
    ej["sd_enu_m"] = vec_json(e.sd_enu);
    ej["attitude_deg"] = {e.attitude.roll_deg, e.attitude.pitch_deg, e.attitude.yaw_deg};
    eps.push_back(ej);
  }
  j["epochs"] = eps;
  J legs = J::array();
  for (const FlightPathLeg& l : m.path.legs)
    legs.push_back({{"t0_s", l.t0_s},
                    {"t1_s", l.t1_s},
                    {"from_enu_m", vec_json(l.from)},
                    {"to_enu_m", vec_json(l.to)},
                    {"route", l.route},
                    {"hover", l.hover},
                    {"peak_speed_mps", l.peak_speed_mps}});
  j["flight_path"] = legs;
  return j.dump(1) + "\n";
}

namespace {

std::string format_mission_config(const SimMission& m) {
  using J = nlohmann::ordered_json;
  const Scenario& s = m.scenario;
  J j;
  j["mission"] = s.mission + " (simulated by rangecal simulate, seed " + std::to_string(s.seed) + ")";
  j["site"] = {{"origin", {{"lat", s.origin.lat_deg}, {"lon", s.origin.lon_deg}, {"h", s.origin.h_m}}}};
  // Never interpolate across a scenario gap; regular spacing is 1/rate.
  const double max_gap = std::max(0.5, 2.5 / s.gnss.rate_hz);
  j["gnss"] = {
      {"pos_files", {"gnss/rover.pos"}}, {"accept_quality", {1}}, {"max_sd_m", 0.05}, {"max_gap_s", max_gap}};
  // A correlated scenario's mission states the model its errors were drawn from, as a range states
  // the model of a receiver it has characterised (docs/gnss.md "PPK error model").
  const PpkErrorModel em = stated_error_model(s.gnss.noise_sd_m, s.gnss.correlated_error);
  if (!s.mission_error_model.is_null()) {
    j["gnss"]["error_model"] = s.mission_error_model;
  } else if (em.correlated()) {
    const auto hv = [](double h, double v) { return J{{"horizontal", h}, {"vertical", v}}; };
    j["gnss"]["error_model"] = {
        {"white_scale", hv(em.white_scale_h, em.white_scale_v)},
        {"gauss_markov", {{"sd_m", hv(em.gm_sd_h_m, em.gm_sd_v_m)}, {"tau_s", hv(em.tau_h_s, em.tau_v_s)}}}};
  }
  j["attitude"] = {{"file", "gnss/attitude.csv"}};
  j["lever_arm"] = {{"body_frd_m", vec_json(s.lever_arm_frd_m)}};
  if (!m.poles.empty()) j["poles"] = "survey/poles.csv";
  J cams = J::array();
  for (const SimCamera& c : m.cameras) {
    const CameraIntrinsics& in = c.spec.camera.intr;
    J cj;
    cj["id"] = c.spec.id;
    cj["frames"] = {{"timestamps", c.spec.id + "/timestamps.csv"}};
    cj["sensor"] = {{"width_px", in.width_px},
                    {"height_px", in.height_px},
                    {"pixel_size_um", {in.dx_mm * 1e3, in.dy_mm * 1e3}}};
    cj["lens"] = {{"nominal_focal_mm", c.spec.nominal_focal_mm}};
    if (!c.picks.empty()) {
      cj["pole_observations"] = c.spec.id + "/poles_px.csv";
      if (s.pick_noise_px > 0) cj["pixel_sigma_px"] = {{"pick", s.pick_noise_px}};
    }
    cams.push_back(cj);
  }
  j["cameras"] = cams;
  j["calibrate"] = {{"method", "bundle"}, {"seed", s.seed}};
  if (s.mission_calibrate.is_object()) {
    j["calibrate"] = s.mission_calibrate;
    if (!j["calibrate"].contains("seed")) j["calibrate"]["seed"] = s.seed;
  }
  // The survey's and the picks' σ stated as the range states those of its own instruments: the
  // σ the poles and picks were drawn with (else the run states the defaults, 5 mm and 0.5 px, and
  // its pole σ answer a question the scenario did not ask).
  if (!m.poles.empty() && s.survey_noise_m > 0 && !j["calibrate"].contains("control_sigma_m"))
    j["calibrate"]["control_sigma_m"] = s.survey_noise_m;
  if (!m.poles.empty() && s.pick_noise_px > 0) j["intersect"] = {{"pick_sigma_px", s.pick_noise_px}};
  j["output_dir"] = "out";
  return j.dump(2) + "\n";
}

std::string format_pos(const SimMission& m) {
  const Scenario& s = m.scenario;
  GeographicLib::LocalCartesian lc(s.origin.lat_deg, s.origin.lon_deg, s.origin.h_m);
  PosWriterHeader h;
  h.input_files = {"sim_rover.obs", "sim_base.obs", "sim_base.nav"};
  h.has_ref_pos = true;
  h.ref_lat_deg = s.origin.lat_deg;
  h.ref_lon_deg = s.origin.lon_deg;
  h.ref_h_m = s.origin.h_m;
  std::vector<PosWriterEpoch> eps;
  eps.reserve(m.epochs.size());
  for (const SimEpoch& e : m.epochs) {
    PosWriterEpoch p;
    p.time = utc_to_gps(e.utc);
    lc.Reverse(e.antenna_measured.x(), e.antenna_measured.y(), e.antenna_measured.z(), p.lat_deg, p.lon_deg,
               p.h_m);
    p.quality = e.quality;
    p.satellites = s.gnss.satellites;
    p.sdn_m = e.sd_enu.y();
    p.sde_m = e.sd_enu.x();
    p.sdu_m = e.sd_enu.z();
    // A 1 Hz base station: the differential age is the time since the last whole GPST second.
    p.age_s = std::fmod(static_cast<double>(p.time.ns % kNsPerSecond) * 1e-9, 1.0);
    p.ratio = e.quality == 1 ? 25.0 : 1.6;
    eps.push_back(p);
  }
  return format_rtklib_pos(h, eps);
}

std::string format_attitude_csv(const SimMission& m) {
  std::string out = "utc,roll_deg,pitch_deg,yaw_deg\n";
  for (const auto& a : m.attitude)
    out += format_iso8601_utc(a.utc, 6) + "," + format_number("%.6f", a.attitude.roll_deg) + "," +
           format_number("%.6f", a.attitude.pitch_deg) + "," + format_number("%.6f", a.attitude.yaw_deg) +
           "\n";
  return out;
}

std::string format_poles_csv(const SimMission& m) {
  const Scenario& s = m.scenario;
  GeographicLib::LocalCartesian lc(s.origin.lat_deg, s.origin.lon_deg, s.origin.h_m);
  const bool llh = s.poles_format == "llh";
  std::string out = llh ? "id,role,lat,lon,h\n" : "id,role,E,N,U\n";
  for (const SimPole& p : m.poles) {
    double a = p.surveyed_enu.x(), b = p.surveyed_enu.y(), c = p.surveyed_enu.z();
    if (llh) lc.Reverse(p.surveyed_enu.x(), p.surveyed_enu.y(), p.surveyed_enu.z(), a, b, c);
    out += p.truth.id + "," + p.truth.role + "," + format_number(llh ? "%.10f" : "%.4f", a) + "," +
           format_number(llh ? "%.10f" : "%.4f", b) + "," + format_number("%.4f", c) + "\n";
  }
  return out;
}

std::string format_picks_csv(const SimCamera& c) {
  std::string out = "id,u,v\n";
  for (const SimPick& p : c.picks)
    out += p.id + "," + format_number("%.3f", p.picked_px.x()) + "," +
           format_number("%.3f", p.picked_px.y()) + "\n";
  return out;
}

std::string format_timestamps_csv(const SimCamera& c) {
  std::string out = "frame,file,utc\n";
  for (const SimFrame& f : c.frames)
    out += std::to_string(f.frame) + "," + f.file + "," + format_iso8601_utc(f.stamp_utc, 9) + "\n";
  return out;
}

}  // namespace

WrittenMission write_mission(const SimMission& m, const std::string& out_dir) {
  namespace fs = std::filesystem;
  const fs::path root(out_dir);
  std::error_code ec;
  fs::create_directories(root, ec);
  if (ec) throw_input_error(out_dir, 0, "", "cannot create the output folder: " + ec.message());
  WrittenMission w;
  auto put = [&](const fs::path& rel, const std::string& text) {
    write_file_atomic((root / rel).string(), text);
    ++w.n_files;
  };
  put("gnss/rover.pos", format_pos(m));
  put("gnss/attitude.csv", format_attitude_csv(m));
  if (!m.poles.empty()) put("survey/poles.csv", format_poles_csv(m));
  for (const SimCamera& c : m.cameras) {
    put(fs::path(c.spec.id) / "timestamps.csv", format_timestamps_csv(c));
    if (!c.picks.empty()) put(fs::path(c.spec.id) / "poles_px.csv", format_picks_csv(c));
  }

  // Frames: rendered and PNG-encoded in parallel (each frame's noise has its own seed, so the
  // bytes do not depend on the schedule), each written atomically.
  std::vector<std::pair<std::size_t, std::size_t>> jobs;
  for (std::size_t ci = 0; ci < m.cameras.size(); ++ci)
    for (std::size_t fi = 0; fi < m.cameras[ci].frames.size(); ++fi) jobs.emplace_back(ci, fi);
  ProgressBar bar("render frames", jobs.size());
  tbb::parallel_for(std::size_t(0), jobs.size(), [&](std::size_t k) {
    const SimCamera& c = m.cameras[jobs[k].first];
    const SimFrame& f = c.frames[jobs[k].second];
    const cv::Mat img = render_sim_frame(m, c, f);
    std::vector<unsigned char> png;
    const fs::path path = root / c.spec.id / f.file;
    // Huffman-only deflate: sensor noise makes LZ77 matching futile; this is ~2× faster than the
    // default strategy and gives smaller files.
    if (!cv::imencode(".png", img, png,
                      {cv::IMWRITE_PNG_COMPRESSION, 1, cv::IMWRITE_PNG_STRATEGY,
                       cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY}))
      throw_input_error(path.string(), 0, "", "cannot encode the frame as PNG");
    write_file_atomic(path.string(), std::string(png.begin(), png.end()));
    bar.tick();
  });
  w.n_frames = jobs.size();
  w.n_files += jobs.size();
  w.n_epochs = m.epochs.size();

  // truth.json and the mission config last: a mission.json exists only once its inputs do.
  w.truth_path = (root / "truth.json").string();
  put("truth.json", format_truth_json(m));
  w.config_path = (root / "mission.json").string();
  put("mission.json", format_mission_config(m));
  return w;
}

}  // namespace rangecal
