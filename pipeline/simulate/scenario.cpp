#include "pipeline/simulate/scenario.hpp"

#include <cmath>
#include <filesystem>
#include <regex>
#include <set>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/json_view.hpp"
#include "config/number_format.hpp"
#include "config/physical_ranges.hpp"
#include "gnss/track/attitude.hpp"

namespace rangecal {
namespace {

constexpr ErrorKind kKind = ErrorKind::usage;

double positive(const JsonView& v, const std::string& what) {
  const double x = v.number("a positive number (" + what + ")");
  if (!(x > 0)) v.fail_expected("a positive number (" + what + ")");
  return x;
}

double non_negative(const JsonView& v, const std::string& what) {
  const double x = v.number("a number ≥ 0 (" + what + ")");
  if (x < 0) v.fail_expected("a number ≥ 0 (" + what + ")");
  return x;
}

Eigen::Vector3d vec3(const JsonView& v, const std::string& what) {
  const auto a = v.numbers(3, "an array of 3 numbers (" + what + ")");
  return {a[0], a[1], a[2]};
}

std::vector<TimeInterval> intervals(const JsonView& v) {
  const std::string expected = "an array of [start_s, end_s] pairs (mission seconds)";
  const std::size_t n = v.require_array(expected);
  std::vector<TimeInterval> out;
  for (std::size_t i = 0; i < n; ++i) {
    const JsonView e = v.element(i);
    const auto a = e.numbers(2, "a pair [start_s, end_s] with start_s ≤ end_s (mission seconds)");
    if (a[0] > a[1]) e.fail_expected("a pair [start_s, end_s] with start_s ≤ end_s (mission seconds)");
    out.push_back({a[0], a[1]});
  }
  return out;
}

// A per-axis quantity given as [E, N, U] or as {"horizontal": E and N, "vertical": U}; each ≥ 0 (or
// > 0 when `strictly_positive`).
Eigen::Vector3d enu_or_horizontal_vertical(const JsonView& v, const std::string& unit,
                                           bool strictly_positive) {
  const std::string each = strictly_positive ? "> 0" : "≥ 0";
  const std::string expected =
      "[E, N, U] or {\"horizontal\", \"vertical\"}, each " + each + " (" + unit + ")";
  Eigen::Vector3d x;
  if (v.json().is_object()) {
    v.check_keys({"horizontal", "vertical"});
    const double h =
        v.at("horizontal", "a number " + each + " (" + unit + ")").number("a number (" + unit + ")");
    const double u =
        v.at("vertical", "a number " + each + " (" + unit + ")").number("a number (" + unit + ")");
    x = Eigen::Vector3d(h, h, u);
  } else {
    x = vec3(v, expected);
  }
  if (strictly_positive ? !(x.array() > 0).all() : (x.array() < 0).any()) v.fail_expected(expected);
  return x;
}

// gnss.gauss_markov: {"sd_m": …, "tau_s": …}, both required (docs/simulator.md "PPK error model").
void parse_gauss_markov(const JsonView& v, PpkCorrelatedError* e) {
  v.require_object("an object {\"sd_m\", \"tau_s\"}");
  v.check_keys({"sd_m", "tau_s"});
  e->gm_sd_m = enu_or_horizontal_vertical(v.at("sd_m", "the process 1σ (m)"), "m", false);
  e->gm_tau_s = enu_or_horizontal_vertical(v.at("tau_s", "the correlation time (s)"), "s", true);
}

void parse_scenario_gnss(const JsonView& v, ScenarioGnss* g) {
  v.require_object("an object {\"rate_hz\", \"noise_sd_m\", …}");
  v.check_keys({"rate_hz", "noise_sd_m", "gauss_markov", "flight_bias_sd_m", "float_fraction",
                "float_intervals", "float_noise_factor", "gaps", "satellites"});
  if (auto x = v.find("rate_hz")) g->rate_hz = positive(*x, "Hz");
  if (auto x = v.find("noise_sd_m")) {
    g->noise_sd_m = vec3(*x, "1σ of E, N, U noise in metres, each ≥ 0");
    if ((g->noise_sd_m.array() < 0).any()) x->fail_expected("an array of 3 numbers ≥ 0 (m)");
  }
  if (auto x = v.find("gauss_markov")) parse_gauss_markov(*x, &g->correlated_error);
  if (auto x = v.find("flight_bias_sd_m"))
    g->correlated_error.flight_bias_sd_m = enu_or_horizontal_vertical(*x, "m", false);
  if (auto x = v.find("float_fraction")) {
    g->float_fraction = x->number("a fraction in [0, 1]");
    if (g->float_fraction < 0 || g->float_fraction > 1) x->fail_expected("a fraction in [0, 1]");
  }
  if (auto x = v.find("float_intervals")) g->float_intervals = intervals(*x);
  if (auto x = v.find("float_noise_factor")) {
    g->float_noise_factor = x->number("a number ≥ 1");
    if (g->float_noise_factor < 1) x->fail_expected("a number ≥ 1");
  }
  if (auto x = v.find("gaps")) g->gaps = intervals(*x);
  if (auto x = v.find("satellites")) {
    const auto n = x->integer("an integer in [4, 99]");
    if (n < 4 || n > 99) x->fail_expected("an integer in [4, 99]");
    g->satellites = static_cast<int>(n);
  }
}

void parse_scenario_attitude(const JsonView& v, ScenarioAttitude* a) {
  v.require_object("an object {\"rate_hz\", \"wobble_deg\", \"yaw_deg\"}");
  v.check_keys({"rate_hz", "wobble_deg", "yaw_deg", "tilt_with_acceleration"});
  if (auto x = v.find("rate_hz")) a->rate_hz = positive(*x, "Hz");
  if (auto x = v.find("wobble_deg")) {
    a->wobble_deg = non_negative(*x, "degrees, at most 20");
    if (a->wobble_deg > 20) x->fail_expected("a number in [0, 20] (degrees)");
  }
  if (auto x = v.find("yaw_deg")) {
    a->yaw_deg = x->number("a number in [-360, 360] (degrees clockwise from north)");
    if (std::abs(a->yaw_deg) > 360)
      x->fail_expected("a number in [-360, 360] (degrees clockwise from north)");
  }
  if (auto x = v.find("tilt_with_acceleration")) a->tilt_with_acceleration = x->boolean("true or false");
}

void parse_lamp(const JsonView& v, ScenarioLamp* l) {
  v.require_object("an object {\"psf_sigma_px\", \"peak\", \"saturation\"}");
  v.check_keys({"psf_sigma_px", "peak", "saturation"});
  if (auto x = v.find("psf_sigma_px")) l->psf_sigma_px = positive(*x, "px");
  if (auto x = v.find("peak")) l->peak = positive(*x, "DN, 16-bit scale");
  if (auto x = v.find("saturation")) {
    l->saturation = positive(*x, "DN, 16-bit scale, at most 65535");
    if (l->saturation > 65535) x->fail_expected("a positive number ≤ 65535 (DN, 16-bit scale)");
  }
}

void parse_sky(const JsonView& v, ScenarioSky* s) {
  v.require_object("an object {\"background\", \"gradient\", \"read_noise\", …}");
  v.check_keys({"background", "gradient", "read_noise", "hot_pixels", "hot_pixel_excess", "distractor"});
  if (auto x = v.find("background")) s->background = non_negative(*x, "DN, 16-bit scale");
  if (auto x = v.find("gradient")) {
    const auto g = x->numbers(2, "an array [dDN/du, dDN/dv] (DN per pixel)");
    s->gradient = {g[0], g[1]};
  }
  if (auto x = v.find("read_noise")) s->read_noise = non_negative(*x, "DN, 16-bit scale");
  if (auto x = v.find("hot_pixels")) {
    const auto n = x->integer("an integer in [0, 10000]");
    if (n < 0 || n > 10000) x->fail_expected("an integer in [0, 10000]");
    s->hot_pixels = static_cast<int>(n);
  }
  if (auto x = v.find("hot_pixel_excess")) s->hot_pixel_excess = positive(*x, "DN, 16-bit scale");
  if (auto x = v.find("distractor")) {
    x->require_object("an object {\"u\", \"v\", \"peak\"}");
    x->check_keys({"u", "v", "peak", "sigma_px"});
    ScenarioDistractor d;
    d.u_px = x->at("u", "a number (px)").number("a number (px)");
    d.v_px = x->at("v", "a number (px)").number("a number (px)");
    d.peak = positive(x->at("peak", "a positive number (DN)"), "DN, 16-bit scale");
    if (auto y = x->find("sigma_px")) d.sigma_px = positive(*y, "px");
    s->distractor = d;
  }
}

Eigen::Matrix3d matrix3(const JsonView& v) {
  const std::string expected = "3 rows of 3 numbers (world ENU → camera rotation)";
  v.require_array(expected, 3, 3);
  Eigen::Matrix3d R;
  for (int r = 0; r < 3; ++r) {
    const auto row = v.element(r).numbers(3, expected);
    for (int c = 0; c < 3; ++c) R(r, c) = row[c];
  }
  if ((R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 || R.determinant() < 0)
    v.fail("not a rotation matrix (R·Rᵀ must be I within 1e-6 and det(R) = +1)");
  return R;
}

ScenarioCamera parse_scenario_camera(const JsonView& v) {
  v.require_object("a camera object {\"id\", \"center_enu_m\", \"look_at_enu_m\", \"f_mm\", …}");
  // Keys: the pose and sensor, then the camera-model parameters by their names
  // (vision/camera/camera_parameters.hpp: sx and the distortion terms), then the recording.
  std::vector<std::string> keys = {
      "id",        "center_enu_m", "look_at_enu_m", "roll_deg",
      "R",         "f_mm",         "pixel_size_um", "width_px",
      "height_px", "u0_px",        "v0_px",         parameter_name(CameraParameter::sx)};
  for (const CameraParameter d : kDistortionParameters) keys.push_back(parameter_name(d));
  for (const char* k : {"fps", "export_step", "bit_depth", "clock_offset_s", "start_s", "nominal_focal_mm"})
    keys.push_back(k);
  v.check_keys(keys);
  ScenarioCamera c;
  const JsonView id = v.at("id", "a camera id ([A-Za-z0-9_-]+)");
  c.id = id.nonempty_string("a camera id ([A-Za-z0-9_-]+)");
  if (!std::regex_match(c.id, std::regex("[A-Za-z0-9_-]+"))) id.fail_expected("a camera id ([A-Za-z0-9_-]+)");
  c.camera.id = c.id;
  CameraIntrinsics& in = c.camera.intr;
  in.width_px = static_cast<int>(v.at("width_px", "a positive integer").integer("a positive integer (px)"));
  if (in.width_px <= 0 || in.width_px > ranges::kMaxImageSidePx)
    v.at("width_px", "")
        .fail_expected("a positive integer (px) up to " + std::to_string(ranges::kMaxImageSidePx));
  in.height_px = static_cast<int>(v.at("height_px", "a positive integer").integer("a positive integer (px)"));
  if (in.height_px <= 0 || in.height_px > ranges::kMaxImageSidePx)
    v.at("height_px", "")
        .fail_expected("a positive integer (px) up to " + std::to_string(ranges::kMaxImageSidePx));
  const JsonView ps = v.at("pixel_size_um", "a positive number or [x, y] (µm)");
  if (ps.json().is_array()) {
    const auto p = ps.numbers(2, "a positive number or an array [x, y] of positive numbers (µm)");
    if (!(p[0] > 0 && p[1] > 0))
      ps.fail_expected("a positive number or an array [x, y] of positive numbers (µm)");
    in.dx_mm = p[0] * 1e-3;
    in.dy_mm = p[1] * 1e-3;
  } else {
    in.dx_mm = in.dy_mm = positive(ps, "µm") * 1e-3;
  }
  in.f_mm = positive(v.at("f_mm", "a positive number (mm)"), "mm");
  in.u0_px = in.width_px / 2.0;
  in.v0_px = in.height_px / 2.0;
  if (auto x = v.find("u0_px")) in.u0_px = x->number("a number (px)");
  if (auto x = v.find("v0_px")) in.v0_px = x->number("a number (px)");
  if (auto x = v.find(parameter_name(CameraParameter::sx))) {
    in.sx = positive(*x, "dimensionless, near 1");
    if (in.sx < 0.5 || in.sx > 2) x->fail_expected("a number in [0.5, 2]");
  }
  double* dist[] = {&in.dist.k1, &in.dist.k2, &in.dist.k3, &in.dist.p1,
                    &in.dist.p2, &in.dist.a1, &in.dist.a2};
  for (std::size_t i = 0; i < kDistortionParameters.size(); ++i)
    if (auto x = v.find(parameter_name(kDistortionParameters[i])))
      *dist[i] = x->number("a number (seed 000 eq. 7 units, mm-based)");

  const Eigen::Vector3d center = vec3(v.at("center_enu_m", "an array [E, N, U] (m)"), "E, N, U in metres");
  const auto look = v.find("look_at_enu_m");
  const auto Rj = v.find("R");
  if (look && Rj) Rj->fail("give either 'look_at_enu_m' or 'R', not both");
  if (!look && !Rj) v.at("look_at_enu_m", "an array [E, N, U] (m) (or a rotation 'R')");
  Eigen::Matrix3d R;
  if (look) {
    const Eigen::Vector3d target = vec3(*look, "E, N, U in metres");
    if ((target - center).norm() < 1e-6) look->fail("the look-at point coincides with the camera centre");
    if ((target - center).normalized().head<2>().norm() < 1e-6)
      look->fail("the camera looks straight up or down; give 'R' instead");
    double roll = 0;
    if (auto x = v.find("roll_deg")) roll = x->number("a number (degrees about the optical axis)");
    R = look_at_rotation(center, target, roll);
  } else {
    if (auto x = v.find("roll_deg")) x->fail("'roll_deg' goes with 'look_at_enu_m', not with 'R'");
    R = matrix3(*Rj);
  }
  c.camera.pose.R = R;
  c.camera.pose.T = -R * center;

  if (auto x = v.find("fps")) c.fps = positive(*x, "frames per second");
  if (auto x = v.find("export_step")) {
    const auto n = x->integer("an integer ≥ 1");
    if (n < 1 || n > 1000000) x->fail_expected("an integer ≥ 1");
    c.export_step = static_cast<int>(n);
  }
  if (auto x = v.find("bit_depth")) {
    const auto n = x->integer("8 or 16");
    if (n != 8 && n != 16) x->fail_expected("8 or 16");
    c.bit_depth = static_cast<int>(n);
  }
  if (auto x = v.find("clock_offset_s")) {
    c.clock_offset_s = x->number("a number of seconds, |x| ≤ 10");
    if (std::abs(c.clock_offset_s) > 10) x->fail_expected("a number of seconds, |x| ≤ 10");
  }
  if (auto x = v.find("start_s")) c.start_s = x->number("a number (mission seconds)");
  c.nominal_focal_mm = std::round(in.f_mm);
  if (auto x = v.find("nominal_focal_mm")) c.nominal_focal_mm = positive(*x, "mm");
  return c;
}

ScenarioRoute parse_route(const JsonView& v) {
  v.require_object("a route object {\"type\", \"start_enu_m\", …}");
  v.check_keys({"type", "start_enu_m", "end_enu_m", "height_m", "speed_mps", "accel_mps2", "hover_s"});
  ScenarioRoute r;
  const JsonView type = v.at("type", "\"vertical\" or \"line\"");
  const std::string t = type.string("\"vertical\" or \"line\"");
  if (t == "vertical")
    r.type = ScenarioRoute::Type::vertical;
  else if (t == "line")
    r.type = ScenarioRoute::Type::line;
  else
    type.fail_expected("\"vertical\" or \"line\"");
  r.start_enu_m = vec3(v.at("start_enu_m", "an array [E, N, U] (m)"), "E, N, U in metres");
  const auto end = v.find("end_enu_m");
  const auto height = v.find("height_m");
  if (end && height) height->fail("give either 'end_enu_m' or 'height_m', not both");
  if (height) {
    if (r.type != ScenarioRoute::Type::vertical) height->fail("'height_m' is only for vertical routes");
    r.end_enu_m = r.start_enu_m + Eigen::Vector3d(0, 0, height->number("a number (m, negative descends)"));
  } else {
    r.end_enu_m = vec3(v.at("end_enu_m", "an array [E, N, U] (m) (or 'height_m' for a vertical route)"),
                       "E, N, U in metres");
    if (r.type == ScenarioRoute::Type::vertical &&
        (r.end_enu_m.head<2>() - r.start_enu_m.head<2>()).norm() > 1e-9)
      end->fail("a vertical route's end must have the start's E and N");
  }
  if ((r.end_enu_m - r.start_enu_m).norm() < 1e-3)
    v.fail("the route has no length (start and end closer than 1 mm)");
  if (auto x = v.find("speed_mps")) r.speed_mps = positive(*x, "m/s");
  if (auto x = v.find("accel_mps2")) r.accel_mps2 = positive(*x, "m/s²");
  if (auto x = v.find("hover_s")) r.hover_s = non_negative(*x, "s");
  return r;
}

ScenarioPole parse_pole(const JsonView& v) {
  v.require_object("a pole object {\"id\", \"role\", \"enu_m\"}");
  v.check_keys({"id", "role", "enu_m"});
  ScenarioPole p;
  const JsonView id = v.at("id", "a pole id (no commas or spaces)");
  p.id = id.nonempty_string("a pole id (no commas or spaces)");
  if (!std::regex_match(p.id, std::regex("[A-Za-z0-9_.-]+"))) id.fail_expected("a pole id ([A-Za-z0-9_.-]+)");
  const JsonView role = v.at("role", "\"control\" or \"check\"");
  p.role = role.string("\"control\" or \"check\"");
  if (p.role != "control" && p.role != "check") role.fail_expected("\"control\" or \"check\"");
  p.enu_m = vec3(v.at("enu_m", "an array [E, N, U] (m)"), "E, N, U in metres");
  return p;
}

// The lamp offset from the antenna in ENU for a level UAV with heading yaw (docs/conventions.md: R_nb·lever
// in NED, then NED → ENU).
Eigen::Vector3d level_lamp_offset_enu(const Eigen::Vector3d& lever_frd, double yaw_deg) {
  Attitude a;
  a.yaw_deg = yaw_deg;
  const Eigen::Vector3d ned = rotation_nb(a) * lever_frd;
  return {ned.y(), ned.x(), -ned.z()};
}

// The flight time and every derived count, checked before any work starts; the error names the
// key that makes the work too large.
void check_work_bounds(const Scenario& s) {
  const SimulationLimits lim;
  double duration = 0, longest = -1;
  std::string longest_key = "routes";
  for (std::size_t i = 0; i < s.routes.size(); ++i) {
    const ScenarioRoute& r = s.routes[i];
    const std::string key = "routes[" + std::to_string(i) + "]";
    if (i > 0) {
      const double transit = straight_leg_duration_s((r.start_enu_m - s.routes[i - 1].end_enu_m).norm(),
                                                     s.transit_speed_mps, s.transit_accel_mps2);
      duration += transit;
      if (transit > longest) longest = transit, longest_key = "transit.speed_mps";
    }
    const double leg =
        straight_leg_duration_s((r.end_enu_m - r.start_enu_m).norm(), r.speed_mps, r.accel_mps2);
    duration += leg + 2 * r.hover_s;
    if (leg > longest) longest = leg, longest_key = key + ".speed_mps";
    if (2 * r.hover_s > longest) longest = 2 * r.hover_s, longest_key = key + ".hover_s";
  }
  auto too_much = [&](const std::string& key, const std::string& what) {
    throw_config_error(s.file, key, what);
  };
  auto g = [](double v) { return format_number("%.3g", v); };
  if (!(duration <= lim.max_flight_s))
    too_much(longest_key, "the flight would last " + g(duration) + " s, more than the " +
                              g(lim.max_flight_s) +
                              " s a scenario may fly (a speed in m/s, not km/h or mm/s?)");
  if (duration * s.gnss.rate_hz > lim.max_gnss_epochs)
    too_much("gnss.rate_hz", g(s.gnss.rate_hz) + " Hz over " + g(duration) + " s is " +
                                 g(duration * s.gnss.rate_hz) + " epochs, more than " +
                                 g(lim.max_gnss_epochs));
  if (duration * s.attitude.rate_hz > lim.max_attitude_samples)
    too_much("attitude.rate_hz", g(s.attitude.rate_hz) + " Hz over " + g(duration) + " s is " +
                                     g(duration * s.attitude.rate_hz) + " samples, more than " +
                                     g(lim.max_attitude_samples));
  double pixels = 0;
  for (std::size_t i = 0; i < s.cameras.size(); ++i) {
    const ScenarioCamera& c = s.cameras[i];
    const double frames = duration * c.fps / c.export_step;
    const std::string key = "cameras[" + std::to_string(i) + "]";
    if (frames > lim.max_frames_per_camera)
      too_much(key + ".export_step", g(c.fps) + " fps exported every " + std::to_string(c.export_step) +
                                         " frames over " + g(duration) + " s is " + g(frames) +
                                         " frames, more than " + g(lim.max_frames_per_camera));
    pixels += frames * c.camera.intr.width_px * c.camera.intr.height_px;
    if (pixels > lim.max_rendered_pixels)
      too_much(key + ".width_px", "rendering the exported frames would take " + g(pixels) +
                                      " pixels, more than " + g(lim.max_rendered_pixels));
  }
}

// A camera must see part of some route, else the mission cannot calibrate it: sample every
// route densely and project the level-flight lamp position.
void check_cameras_see_routes(const Scenario& s, const JsonView& root) {
  const Eigen::Vector3d off = level_lamp_offset_enu(s.lever_arm_frd_m, s.attitude.yaw_deg);
  for (std::size_t i = 0; i < s.cameras.size(); ++i) {
    const Camera& cam = s.cameras[i].camera;
    bool seen = false;
    for (const auto& r : s.routes) {
      const int n = 400;
      for (int k = 0; k <= n && !seen; ++k) {
        const Eigen::Vector3d p = r.start_enu_m + (r.end_enu_m - r.start_enu_m) * (double(k) / n) + off;
        Eigen::Vector2d uv;
        if (project(cam, p, &uv) && inside_image(cam.intr, uv)) seen = true;
      }
    }
    if (!seen)
      root.at("cameras", "")
          .element(i)
          .fail("camera '" + s.cameras[i].id +
                "' sees no part of any route: the lamp never enters its image");
  }
}

}  // namespace

double straight_leg_duration_s(double L, double speed, double accel) {
  if (L < speed * speed / accel) return 2.0 * std::sqrt(accel * L) / accel;  // triangular profile
  return 2.0 * speed / accel + (L - speed * speed / accel) / speed;
}

Eigen::Matrix3d look_at_rotation(const Eigen::Vector3d& center, const Eigen::Vector3d& look_at,
                                 double roll_deg) {
  const Eigen::Vector3d z = (look_at - center).normalized();
  const Eigen::Vector3d x0 = z.cross(Eigen::Vector3d::UnitZ()).normalized();  // horizontal, to the right
  const Eigen::Vector3d y0 = z.cross(x0);                                     // down in the image
  const double r = roll_deg * M_PI / 180.0;
  const Eigen::Vector3d x = std::cos(r) * x0 + std::sin(r) * y0;
  const Eigen::Vector3d y = -std::sin(r) * x0 + std::cos(r) * y0;
  Eigen::Matrix3d R;
  R.row(0) = x.transpose();
  R.row(1) = y.transpose();
  R.row(2) = z.transpose();
  return R;
}

Scenario parse_scenario(const std::string& json_text, const std::string& path) {
  const nlohmann::json j = parse_json_text(json_text, path, kKind);
  const JsonView root(j, path, "", kKind);
  root.require_object("a scenario object {\"seed\", \"start_utc\", \"site\", \"cameras\", \"routes\", …}");
  root.check_keys({"mission", "seed", "start_utc", "site", "gnss", "lever_arm", "attitude", "lamp", "sky",
                   "cameras", "routes", "transit", "poles", "poles_format", "survey_noise_m", "pick_noise_px",
                   "mission_calibrate", "mission_error_model"});
  Scenario s;
  s.file = path;
  if (auto x = root.find("mission")) s.mission = x->string("a string");
  if (auto x = root.find("seed")) s.seed = x->unsigned_integer("a non-negative integer");
  {
    const JsonView t = root.at("start_utc", "an ISO 8601 UTC time (YYYY-MM-DDThh:mm:ss[.fff]Z)");
    std::string why;
    const auto u = parse_iso8601_utc(t.string("an ISO 8601 UTC time (YYYY-MM-DDThh:mm:ss[.fff]Z)"), &why);
    if (!u) t.fail("not an ISO 8601 UTC time: " + why);
    s.start_utc = *u;
  }
  {
    const JsonView site = root.at("site", "an object {\"origin\": {\"lat\", \"lon\", \"h\"}}");
    site.require_object("an object {\"origin\": {…}}");
    site.check_keys({"origin"});
    const JsonView o = site.at("origin", "an object {\"lat\", \"lon\", \"h\"}");
    o.require_object("an object {\"lat\", \"lon\", \"h\"}");
    o.check_keys({"lat", "lon", "h"});
    const JsonView lat = o.at("lat", "a latitude in degrees [-90, 90]");
    s.origin.lat_deg = lat.number("a latitude in degrees [-90, 90]");
    if (std::abs(s.origin.lat_deg) > 89.9) lat.fail_expected("a latitude in degrees (-89.9, 89.9)");
    const JsonView lon = o.at("lon", "a longitude in degrees [-180, 180]");
    s.origin.lon_deg = lon.number("a longitude in degrees [-180, 180]");
    if (std::abs(s.origin.lon_deg) > 180) lon.fail_expected("a longitude in degrees [-180, 180]");
    s.origin.h_m = o.at("h", "an ellipsoidal height (m)").number("an ellipsoidal height (m)");
  }
  if (auto x = root.find("gnss")) parse_scenario_gnss(*x, &s.gnss);
  if (auto x = root.find("lever_arm")) {
    x->require_object("an object {\"body_frd_m\": [x, y, z]}");
    x->check_keys({"body_frd_m"});
    s.lever_arm_frd_m = vec3(x->at("body_frd_m", "an array [x, y, z] (m, body FRD)"), "x, y, z in metres");
    if (s.lever_arm_frd_m.norm() > 10) x->at("body_frd_m", "").fail("lever arm longer than 10 m");
  }
  if (auto x = root.find("attitude")) parse_scenario_attitude(*x, &s.attitude);
  if (auto x = root.find("lamp")) parse_lamp(*x, &s.lamp);
  if (auto x = root.find("sky")) parse_sky(*x, &s.sky);

  const JsonView cams = root.at("cameras", "an array of camera objects");
  const std::size_t nc = cams.require_array("a non-empty array of camera objects", 1);
  std::set<std::string> ids;
  for (std::size_t i = 0; i < nc; ++i) {
    s.cameras.push_back(parse_scenario_camera(cams.element(i)));
    if (!ids.insert(s.cameras.back().id).second)
      cams.element(i).at("id", "").fail("duplicate camera id '" + s.cameras.back().id + "'");
  }
  const JsonView routes = root.at("routes", "an array of route objects");
  const std::size_t nr = routes.require_array("a non-empty array of route objects", 1);
  for (std::size_t i = 0; i < nr; ++i) s.routes.push_back(parse_route(routes.element(i)));
  if (auto x = root.find("transit")) {
    x->require_object("an object {\"speed_mps\", \"accel_mps2\"}");
    x->check_keys({"speed_mps", "accel_mps2"});
    if (auto y = x->find("speed_mps")) s.transit_speed_mps = positive(*y, "m/s");
    if (auto y = x->find("accel_mps2")) s.transit_accel_mps2 = positive(*y, "m/s²");
  }
  if (auto x = root.find("poles")) {
    const std::size_t np = x->require_array("an array of pole objects");
    std::set<std::string> pids;
    for (std::size_t i = 0; i < np; ++i) {
      s.poles.push_back(parse_pole(x->element(i)));
      if (!pids.insert(s.poles.back().id).second)
        x->element(i).at("id", "").fail("duplicate pole id '" + s.poles.back().id + "'");
    }
  }
  if (auto x = root.find("poles_format")) {
    s.poles_format = x->string("\"llh\" or \"enu\"");
    if (s.poles_format != "llh" && s.poles_format != "enu") x->fail_expected("\"llh\" or \"enu\"");
  }
  if (auto x = root.find("survey_noise_m")) s.survey_noise_m = non_negative(*x, "m");
  if (auto x = root.find("pick_noise_px")) s.pick_noise_px = non_negative(*x, "px");
  if (auto x = root.find("mission_calibrate")) {
    // Copied into the written mission's "calibrate" section; the mission loader validates it.
    x->require_object("an object, written as the mission config's \"calibrate\" section (docs/config.md)");
    s.mission_calibrate = x->json();
  }
  if (auto x = root.find("mission_error_model")) {
    // Copied as the written mission's gnss.error_model; the mission loader validates it.
    if (!x->json().is_string() && !x->json().is_object())
      x->fail_expected("\"estimate\", \"white\" or an error-model object (docs/gnss.md \"PPK error model\")");
    s.mission_error_model = x->json();
  }

  check_work_bounds(s);
  check_cameras_see_routes(s, root);
  return s;
}

Scenario load_scenario(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw_input_error(path, 0, "", "scenario file not found");
  return parse_scenario(read_file_text(path), path);
}

}  // namespace rangecal
