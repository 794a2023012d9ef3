#include "pipeline/mission/mission_config.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <set>
#include <utility>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/json_view.hpp"
#include "config/physical_ranges.hpp"
#include "config/sha256.hpp"
#include "gnss/track/ppk_error_model_json.hpp"
#include "pipeline/mission/calibration_method_names.hpp"
#include "vision/camera/camera_parameters.hpp"

namespace rangecal {
namespace fs = std::filesystem;

const std::vector<std::string>& reserved_camera_ids() {
  static const std::vector<std::string> names = {"gnss", "network", "method_choice"};
  return names;
}

namespace {

const std::vector<std::string>& kMethods = calibration_method_names();
const std::vector<std::string>& kFreeNames = free_parameter_choices();

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + v[i];
  return s;
}

// Everything the loader needs while walking the document.
struct Loader {
  std::string file;  // the config path, for messages
  fs::path dir;      // its folder: relative paths resolve here
  bool check_files;

  // A path-valued key: non-empty string, resolved against the config's folder, and (when checking)
  // an existing regular file. A missing file is a config error naming the key.
  std::string input_file(const JsonView& v, const std::string& expected) const {
    const std::string s = v.nonempty_string(expected);
    fs::path p(s);
    if (p.is_relative()) p = dir / p;
    p = p.lexically_normal();
    if (check_files) {
      std::error_code ec;
      if (!fs::exists(p, ec))
        v.fail("file not found: " + p.string() + " (relative paths resolve against " + dir.string() + ")");
      if (fs::is_directory(p, ec)) v.fail("expected a file, but " + p.string() + " is a folder");
    }
    return p.string();
  }

  static double positive(const JsonView& v, const std::string& expected) {
    const double x = v.number(expected);
    if (!(x > 0)) v.fail_expected(expected);
    return x;
  }

  static double in_range(const JsonView& v, double lo, double hi, const std::string& expected) {
    const double x = v.number(expected);
    if (x < lo || x > hi) v.fail_expected(expected);
    return x;
  }
};

GeodeticOrigin parse_site(const JsonView& site) {
  site.require_object("an object {\"origin\": {\"lat\", \"lon\", \"h\"}}");
  site.check_keys({"origin"});
  const JsonView o = site.at("origin", "an object {\"lat\": deg, \"lon\": deg, \"h\": m}");
  o.require_object("an object {\"lat\": deg, \"lon\": deg, \"h\": m}");
  o.check_keys({"lat", "lon", "h"});
  GeodeticOrigin g;
  g.lat_deg = Loader::in_range(o.at("lat", "a latitude in degrees in [-90, 90]"), -90, 90,
                               "a latitude in degrees in [-90, 90]");
  g.lon_deg = Loader::in_range(o.at("lon", "a longitude in degrees in [-180, 180]"), -180, 180,
                               "a longitude in degrees in [-180, 180]");
  // Ellipsoidal height of a place on the ground: the geoid stays within ±110 m of the ellipsoid.
  g.h_m = Loader::in_range(o.at("h", "an ellipsoidal height in metres in [-1000, 10000]"), -1000, 10000,
                           "an ellipsoidal height in metres in [-1000, 10000]");
  return g;
}

GnssConfig parse_gnss(const Loader& L, const JsonView& g) {
  g.require_object("an object {\"pos_files\": [...], ...}");
  g.check_keys({"pos_files", "accept_quality", "max_sd_m", "max_gap_s", "error_model"});
  GnssConfig c;
  const std::string files_form = "a non-empty array of RTKLIB .pos file paths";
  const JsonView pf = g.at("pos_files", files_form);
  const std::size_t n = pf.require_array(files_form, 1);
  for (std::size_t i = 0; i < n; ++i) c.pos_files.push_back(L.input_file(pf.element(i), "a .pos file path"));
  if (auto q = g.find("accept_quality")) {
    const std::string form =
        "a non-empty array of distinct RTKLIB Q values, integers 1-6 (1 fix, 2 float, "
        "3 sbas, 4 dgps, 5 single, 6 ppp)";
    const std::size_t m = q->require_array(form, 1, 6);
    c.accept_quality.clear();
    for (std::size_t i = 0; i < m; ++i) {
      const JsonView e = q->element(i);
      const std::int64_t v = e.integer(form);
      if (v < 1 || v > 6) e.fail_expected("an RTKLIB Q value, an integer 1-6");
      if (std::find(c.accept_quality.begin(), c.accept_quality.end(), v) != c.accept_quality.end())
        e.fail("Q value " + std::to_string(v) + " is listed twice; expected " + form);
      c.accept_quality.push_back(static_cast<int>(v));
    }
  }
  if (auto v = g.find("max_sd_m"))
    c.max_sd_m = Loader::positive(*v, "a positive standard deviation in metres");
  if (auto v = g.find("max_gap_s")) c.max_gap_s = Loader::positive(*v, "a positive duration in seconds");
  if (auto v = g.find("error_model")) {
    if (v->json().is_string()) {
      const std::string word = v->json().get<std::string>();
      if (word != "estimate" && word != "white")
        v->fail_expected("\"estimate\", \"white\" or an object {\"white_scale\", \"gauss_markov\"}");
      c.estimate_error_model = word == "estimate";
    } else {
      c.error_model = read_ppk_error_model(*v);
      c.estimate_error_model = false;
    }
  }
  return c;
}

LeverArmConfig parse_lever_arm(const Loader& L, const JsonView& v, bool have_attitude) {
  const std::string form =
      "an object with exactly one of {\"body_frd_m\": [x, y, z]} (needs attitude), {\"vertical_m\": d} or "
      "{\"total_station\": \"file.csv\"}";
  v.require_object(form);
  v.check_keys({"body_frd_m", "vertical_m", "total_station"});
  if (v.json().size() != 1) v.fail_expected(form);
  LeverArmConfig c;
  // A lever arm on a multirotor is at most a few metres; more is a unit mistake (mm given as m).
  if (auto b = v.find("body_frd_m")) {
    const std::string bform = "an array of 3 numbers, metres in the body FRD frame, each within ±10 m";
    const auto x = b->numbers(3, bform);
    for (double e : x)
      if (std::abs(e) > 10) b->fail_expected(bform);
    if (!have_attitude)
      b->fail(
          "the full lever arm needs the UAV attitude: add \"attitude\": {\"file\": ...}, or use "
          "{\"vertical_m\": d} (lamp d metres below the antenna)");
    c.kind = LeverArmConfig::Kind::body_frd;
    c.body_frd_m = Eigen::Vector3d(x[0], x[1], x[2]);
  } else if (auto d = v.find("vertical_m")) {
    c.kind = LeverArmConfig::Kind::vertical;
    c.vertical_m = Loader::in_range(*d, -10, 10, "a number of metres (lamp below the antenna) within ±10 m");
  } else {
    c.kind = LeverArmConfig::Kind::total_station;
    c.total_station_file =
        L.input_file(v.at("total_station", "a file path"), "a total-station CSV path (session,target,E,N,U)");
  }
  return c;
}

bool valid_id(const std::string& id) {
  if (id.empty()) return false;
  for (char ch : id)
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-')) return false;
  return true;
}

// The camera's id: it names the output folder and keys the camera's records in run.json, so it
// may not be one of the names those already use for the mission (reserved_camera_ids()).
std::string parse_camera_id(const JsonView& c) {
  const std::string id_form = "a camera id of letters, digits, '_' or '-' (it names the output folder)";
  const JsonView idv = c.at("id", id_form);
  const std::string id = idv.string(id_form);
  if (!valid_id(id)) idv.fail_expected(id_form);
  const std::vector<std::string>& reserved = reserved_camera_ids();
  if (std::find(reserved.begin(), reserved.end(), id) != reserved.end())
    idv.fail("'" + id + "' is reserved (" + join(reserved) +
             " name the mission's own outputs and records); expected " + id_form + " other than these");
  return id;
}

// Exactly one of three alternative keys in `v`, else a failure naming those given ("both 'a' and
// 'b' are given") or `none`, and the expected `form`.
void require_one_of(const JsonView& v, const std::array<const char*, 3>& keys, const std::string& none,
                    const std::string& form) {
  std::vector<std::string> given;
  for (const char* key : keys)
    if (v.has(key)) given.push_back(std::string("'") + key + "'");
  if (given.size() == 1) return;
  v.fail((given.empty()       ? none
          : given.size() == 2 ? "both " + given[0] + " and " + given[1] + " are given"
                              : "all of " + given[0] + ", " + given[1] + " and " + given[2] + " are given") +
         "; expected " + form);
}

FramesConfig parse_frames(const Loader& L, const JsonView& f) {
  const std::string form =
      "an object with one of {\"timestamps\": \"frame,file,utc CSV\"}, {\"cine\": \"file.cine\"} or "
      "{\"mraw\": \"file.mraw\", \"clock_utc_offset_h\": h}, and optionally \"allow_missing\": true|false";
  f.require_object(form);
  f.check_keys({"timestamps", "cine", "mraw", "clock_utc_offset_h", "allow_missing"});
  const bool has_ts = f.has("timestamps"), has_cine = f.has("cine"), has_mraw = f.has("mraw");
  require_one_of(f, {"timestamps", "cine", "mraw"}, "no frames given", form);
  FramesConfig frames;
  if (has_ts) frames.timestamps = L.input_file(*f.find("timestamps"), "a timestamps CSV path");
  if (has_cine) frames.cine = L.input_file(*f.find("cine"), "a Phantom .cine path");
  if (has_mraw) frames.mraw = L.input_file(*f.find("mraw"), "a Photron .mraw path");
  // Photron's header date and time are the camera clock's local time with no zone (Photron
  // FASTCAM Viewer .cihx fileInfo/date, time): the offset is stated, never assumed.
  if (auto o = f.find("clock_utc_offset_h")) {
    if (!has_mraw)
      o->fail("applies only to 'mraw' (the Photron header clock); timestamps CSVs and .cine stamps are UTC");
    frames.clock_utc_offset_h = Loader::in_range(
        *o, -14, 14, "the camera clock's offset from UTC in hours (clock - UTC), within ±14");
  } else if (has_mraw) {
    f.fail(
        "'mraw' needs \"clock_utc_offset_h\": the camera clock - UTC in hours (Photron's header time "
        "is the camera's local clock with no time zone); or give \"timestamps\": a frame,file,utc CSV "
        "naming the .mraw");
  }
  if (auto a = f.find("allow_missing")) frames.allow_missing = a->boolean("true or false");
  return frames;
}

// cameras[i].track (docs/config.md "Imported tracks"); the sensor gives the image the labels lie in.
// cameras[i].target_track (docs/trajectory.md) takes the same keys, with "clock" "time_code" or
// "calibration" and "timing_sigma_s".
TrackConfig parse_track(const Loader& L, const JsonView& t, const SensorConfig& sensor, bool target = false) {
  const std::string form =
      "an object {\"file\", \"format\", \"point\", \"camera\", \"y_origin\", \"timestamps\" | \"t0_utc\" + "
      "\"fps\" [+ \"t0_frame\"], \"clock\", " +
      std::string(target ? "\"readout_s\", \"timing_sigma_s\"}" : "\"clock_search_s\", \"readout_s\"}");
  t.require_object(form);
  if (target)
    t.check_keys({"file", "format", "point", "camera", "y_origin", "timestamps", "t0_utc", "t0_frame", "fps",
                  "clock", "readout_s", "timing_sigma_s"});
  else
    t.check_keys({"file", "format", "point", "camera", "y_origin", "timestamps", "t0_utc", "t0_frame", "fps",
                  "clock", "clock_search_s", "readout_s"});
  TrackConfig track;
  track.file = L.input_file(t.at("file", "a 2-D track file path"), "a 2-D track file path");
  std::string formats;
  for (const TrackFormat& f : track_formats()) formats += (formats.empty() ? "" : ", ") + f.name;
  if (auto f = t.find("format")) {
    track.format = f->string("one of " + formats);
    if (!find_track_format(track.format))
      f->fail("unknown track format '" + track.format + "'; expected one of " + formats);
  }
  for (const auto& [key, field] : {std::pair<const char*, int*>{"point", &track.read.point},
                                   std::pair<const char*, int*>{"camera", &track.read.camera}})
    if (auto v = t.find(key)) {
      const std::int64_t n = v->integer("a positive integer (xypts' pt<point>_cam<camera>_ columns)");
      if (n < 1 || n > 100000) v->fail_expected("a positive integer (xypts' pt<point>_cam<camera>_ columns)");
      *field = static_cast<int>(n);
    }
  if (auto y = t.find("y_origin")) {
    const std::string form_y = "\"top\" (DLTdv8) or \"bottom\" (DLTdv5-7, Argus)";
    const std::string w = y->string(form_y);
    if (w != "top" && w != "bottom") y->fail_expected(form_y);
    track.read.y_origin = w == "top" ? TrackReadOptions::YOrigin::top : TrackReadOptions::YOrigin::bottom;
  }
  track.read.width_px = sensor.width_px;
  track.read.height_px = sensor.height_px;
  const bool has_ts = t.has("timestamps"), has_t0 = t.has("t0_utc") || t.has("fps") || t.has("t0_frame");
  if (has_ts == has_t0)
    t.fail(std::string(has_ts ? "both 'timestamps' and 't0_utc'/'fps' are given"
                              : "the frames' times are not given") +
           ": expected \"timestamps\": a frame,utc CSV, or \"t0_utc\" and \"fps\" (frame t0_frame, default "
           "0, at "
           "t0_utc)");
  if (has_ts) track.timestamps = L.input_file(*t.find("timestamps"), "a frame,utc CSV path");
  if (has_t0) {
    const std::string form_t = "an ISO 8601 UTC time such as \"2026-05-04T10:00:00Z\"";
    const JsonView t0 = t.at("t0_utc", form_t);
    std::string why;
    track.t0_utc = parse_iso8601_utc(t0.string(form_t), &why);
    if (!track.t0_utc) t0.fail(why + "; expected " + form_t);
    track.fps = Loader::positive(t.at("fps", "the nominal frame rate (frames/s)"),
                                 "the nominal frame rate (frames/s)");
    if (track.fps > 1e7) t.find("fps")->fail_expected("a frame rate of at most 1e7 frames/s");
    if (auto f0 = t.find("t0_frame")) track.t0_frame = f0->integer("an integer frame number");
  }
  if (auto c = t.find("clock")) {
    const std::string form_c =
        target
            ? "\"time_code\" (the times are UTC) or \"calibration\" (nominal, on the clock the align stage "
              "found from this camera's calibration track)"
            : "\"time_code\" (the times are UTC) or \"estimate\" (nominal: find offset and rate)";
    const std::string w = c->string(form_c);
    if (w != "time_code" && w != (target ? "calibration" : "estimate")) c->fail_expected(form_c);
    track.estimate_clock = !target && w == "estimate";
    track.calibration_clock = target && w == "calibration";
  }
  if (auto x = t.find("timing_sigma_s")) {
    const std::string form_x = "a frame time's 1σ in seconds (0 to 1)";
    track.timing_sigma_s = Loader::in_range(*x, 0, 1, form_x);
  }
  if (auto r = t.find("clock_search_s")) {
    const std::string form_r = "[lo, hi]: the clock offsets to search (s, lo < hi, within ±1e6)";
    const auto x = r->numbers(2, form_r);
    if (!(x[0] < x[1]) || std::abs(x[0]) > 1e6 || std::abs(x[1]) > 1e6) r->fail_expected(form_r);
    if (!track.estimate_clock) r->fail("applies only with \"clock\": \"estimate\"");
    track.clock_search_s = std::make_pair(x[0], x[1]);
  }
  if (auto r = t.find("readout_s")) {
    const std::string form_r =
        "a rolling shutter's readout in seconds (within ±0.1; negative when the bottom row is read first), "
        "or "
        "\"estimate\" (with \"clock\": \"estimate\")";
    if (r->json().is_string()) {
      if (r->string(form_r) != "estimate") r->fail_expected(form_r);
      if (!track.estimate_clock)
        r->fail("\"estimate\" needs \"clock\": \"estimate\" (the readout is found with the clock)");
      track.estimate_readout = true;
    } else {
      track.readout_s = Loader::in_range(*r, -0.1, 0.1, form_r);
    }
  }
  return track;
}

SensorConfig parse_sensor(const JsonView& c) {
  const std::string sform = "an object {\"width_px\", \"height_px\", \"pixel_size_um\": [x, y]}";
  const JsonView s = c.at("sensor", sform);
  s.require_object(sform);
  s.check_keys({"width_px", "height_px", "pixel_size_um"});
  SensorConfig sensor;
  const std::string wform =
      "a positive integer number of pixels (at most " + std::to_string(ranges::kMaxImageSidePx) + ")";
  for (const char* key : {"width_px", "height_px"}) {
    const JsonView v = s.at(key, wform);
    const std::int64_t n = v.integer(wform);
    if (n < 1 || n > ranges::kMaxImageSidePx) v.fail_expected(wform);
    (std::string(key) == "width_px" ? sensor.width_px : sensor.height_px) = static_cast<int>(n);
  }
  const std::string pform = "an array of 2 positive numbers (µm), each at most 1000";
  const JsonView ps = s.at("pixel_size_um", pform);
  const auto pp = ps.numbers(2, pform);
  for (int i = 0; i < 2; ++i) {
    if (!(pp[i] > 0) || pp[i] > 1000) ps.fail_expected(pform);
    sensor.pixel_size_um[i] = pp[i];
  }
  return sensor;
}

double parse_nominal_focal_mm(const JsonView& c) {
  const std::string lform = "an object {\"nominal_focal_mm\": f}";
  const JsonView lens = c.at("lens", lform);
  lens.require_object(lform);
  lens.check_keys({"nominal_focal_mm"});
  const std::string fform = "a positive focal length in millimetres (at most 10000)";
  const JsonView fv = lens.at("nominal_focal_mm", fform);
  const double f = Loader::positive(fv, fform);
  if (f > 10000) fv.fail_expected(fform);
  return f;
}

// The priors; the principal point must lie inside `sensor`'s image.
CameraPriors parse_priors(const JsonView& pr, const SensorConfig& sensor) {
  pr.require_object("an object of priors");
  pr.check_keys({"principal_point_px", "principal_point_sigma_px", "center_enu_m", "center_sigma_m"});
  CameraPriors priors;
  if (auto pp2 = pr.find("principal_point_px")) {
    const std::string form = "an array of 2 numbers [u0, v0] in pixels, inside the image";
    const auto x = pp2->numbers(2, form);
    // Pixel centres run 0 … width−1; the image area extends half a pixel beyond them.
    if (x[0] < -0.5 || x[0] > sensor.width_px - 0.5 || x[1] < -0.5 || x[1] > sensor.height_px - 0.5)
      pp2->fail("principal point (" + pp2->json().dump() + ") lies outside the " +
                std::to_string(sensor.width_px) + "x" + std::to_string(sensor.height_px) +
                " image; expected " + form);
    priors.principal_point_px = Eigen::Vector2d(x[0], x[1]);
  }
  if (auto v = pr.find("principal_point_sigma_px"))
    priors.principal_point_sigma_px = Loader::positive(*v, "a positive standard deviation in pixels");
  if (auto v = pr.find("center_enu_m")) {
    const auto x = v->numbers(3, "an array of 3 numbers [E, N, U] in metres");
    priors.center_enu_m = Eigen::Vector3d(x[0], x[1], x[2]);
  }
  if (auto v = pr.find("center_sigma_m"))
    priors.center_sigma_m = Loader::positive(*v, "a positive standard deviation in metres");
  return priors;
}

// The a-priori pixel σ per kind of observation: each > 0 and at most 100 px.
PixelSigmaConfig parse_pixel_sigma(const JsonView& v) {
  v.require_object("an object {\"centroid\": px, \"pick\": px, \"track\": px}");
  v.check_keys({"centroid", "pick", "track"});
  PixelSigmaConfig out;
  const std::string form = "a positive standard deviation in pixels, at most 100";
  for (const auto& [key, field] : {std::pair<const char*, double*>{"centroid", &out.centroid_px},
                                   std::pair<const char*, double*>{"pick", &out.pick_px},
                                   std::pair<const char*, double*>{"track", &out.track_px}})
    if (auto x = v.find(key)) {
      *field = Loader::positive(*x, form);
      if (*field > 100) x->fail_expected(form);
    }
  return out;
}

std::vector<std::string> free_parameter_names(const JsonView& f, std::size_t min_size);

CameraConfig parse_camera(const Loader& L, const JsonView& c) {
  c.require_object("a camera object {\"id\", \"frames\", \"sensor\", \"lens\", ...}");
  c.check_keys({"id", "frames", "track", "sensor", "lens", "pole_observations", "priors", "pixel_sigma_px",
                "target_track", "free"});
  CameraConfig cam;
  cam.id = parse_camera_id(c);
  if (auto f = c.find("frames")) cam.frames = parse_frames(L, *f);
  cam.sensor = parse_sensor(c);
  if (auto t = c.find("track")) {
    if (c.has("frames"))
      t->fail("a camera gives either frames (the lamp is detected in them) or an imported track, not both");
    cam.track = parse_track(L, *t, cam.sensor);
  }
  if (auto t = c.find("target_track")) {
    cam.target_track = parse_track(L, *t, cam.sensor, true);
    if (cam.target_track->calibration_clock && !(cam.track && cam.track->estimate_clock))
      t->at("clock", "")
          .fail(
              "\"calibration\" takes the clock the align stage estimates from this camera's \"track\" with "
              "\"clock\": \"estimate\", and this camera has none; give UTC times (\"time_code\")");
  }
  cam.nominal_focal_mm = parse_nominal_focal_mm(c);
  if (auto p = c.find("pole_observations"))
    cam.pole_observations = L.input_file(*p, "a pole-pixel CSV path (id,u,v)");
  if (auto pr = c.find("priors")) cam.priors = parse_priors(*pr, cam.sensor);
  if (auto ps = c.find("pixel_sigma_px")) cam.pixel_sigma = parse_pixel_sigma(*ps);
  if (auto f = c.find("free")) cam.free = free_parameter_names(*f, 1);
  return cam;
}

// trajectory.imported_cameras[i].sigma: the σ a user states for a calibration made elsewhere.
StatedCalibrationSigma parse_stated_sigma(const JsonView& c) {
  const std::string sform =
      "an object {\"focal_px\", \"principal_point_px\", \"position_m\", \"rotation_mrad\"[, \"image_px\"]}: "
      "the calibration's stated 1σ";
  StatedCalibrationSigma out;
  const JsonView sg = c.at("sigma", sform);
  sg.require_object(sform);
  sg.check_keys({"focal_px", "principal_point_px", "position_m", "rotation_mrad", "image_px"});
  struct Field {
    const char* key;
    double* value;
    double hi;
    const char* form;
    bool required;
  };
  for (const Field& f :
       {Field{"focal_px", &out.focal_px, 1e4, "the focal length's 1σ in pixels, 0 to 10000", true},
        Field{"principal_point_px", &out.principal_point_px, 1e4,
              "the principal point's 1σ per axis in pixels, 0 to 10000", true},
        Field{"position_m", &out.position_m, 100, "the camera centre's 1σ per axis in metres, 0 to 100",
              true},
        Field{"rotation_mrad", &out.rotation_mrad, 1000,
              "the attitude's 1σ about each axis in milliradians, 0 to 1000", true},
        Field{"image_px", &out.image_px, 100,
              "the lens model's error at the pixel, 1σ per axis in pixels, 0 to 100", false}}) {
    if (f.required || sg.has(f.key)) *f.value = Loader::in_range(sg.at(f.key, f.form), 0, f.hi, f.form);
  }
  return out;
}

// trajectory.imported_cameras[i] (docs/trajectory.md "Imported calibrations"): every σ stated, none
// assumed — a calibration given without its uncertainty would be taken as exact.
ImportedCameraConfig parse_imported_camera(const Loader& L, const JsonView& c) {
  c.require_object(
      "an imported camera {\"id\", \"calibration\", \"sensor\", \"sigma\", \"target_track\", "
      "\"label_sigma_px\"}");
  c.check_keys({"id", "calibration", "sensor", "sigma", "target_track", "label_sigma_px"});
  ImportedCameraConfig cam;
  cam.id = parse_camera_id(c);
  cam.sensor = parse_sensor(c);
  const std::string cform =
      "an object {\"opencv_yml\": \"camera.yml\"}, {\"dlt\": \"coefficients.csv\", \"column\": n} or "
      "{\"rangecal_json\": \"calibration.json\"}";
  const JsonView cal = c.at("calibration", cform);
  cal.require_object(cform);
  cal.check_keys({"opencv_yml", "dlt", "column", "rangecal_json"});
  require_one_of(cal, {"opencv_yml", "dlt", "rangecal_json"}, "no calibration file given", cform);
  if (auto y = cal.find("opencv_yml")) cam.opencv_yml = L.input_file(*y, "an OpenCV camera YAML path");
  if (auto d = cal.find("dlt")) cam.dlt = L.input_file(*d, "a DLT-11 coefficient CSV path");
  if (auto r = cal.find("rangecal_json"))
    cam.rangecal_json = L.input_file(*r, "a rangecal calibration.json path");
  if (auto col = cal.find("column")) {
    if (cam.dlt.empty()) col->fail("applies only with \"dlt\" (the camera's column of the coefficient file)");
    const std::int64_t n = col->integer("the camera's column of the coefficient file, 1 to 1000");
    if (n < 1 || n > 1000) col->fail_expected("the camera's column of the coefficient file, 1 to 1000");
    cam.dlt_column = static_cast<int>(n);
  }
  // A rangecal calibration.json states its own covariance; a σ beside it would be a second statement.
  if (!cam.rangecal_json.empty()) {
    if (auto sv = c.find("sigma"))
      sv->fail(
          "a rangecal calibration.json states its own covariance; give \"sigma\" only with an OpenCV or DLT "
          "file");
  } else {
    cam.sigma = parse_stated_sigma(c);
  }
  const JsonView t = c.at("target_track", "the target's 2-D track in this camera (docs/trajectory.md)");
  cam.target_track = parse_track(L, t, cam.sensor, true);
  if (cam.target_track.calibration_clock)
    t.at("clock", "")
        .fail(
            "an imported camera has no clock the align stage estimated; its track's times must be UTC "
            "(\"time_code\")");
  if (auto v = c.find("label_sigma_px")) {
    const std::string form = "a label's 1σ per axis in pixels, positive, at most 100";
    cam.label_sigma_px = Loader::positive(*v, form);
    if (cam.label_sigma_px > 100) v->fail_expected(form);
  }
  return cam;
}

// A method name (pipeline/steps/calibration_methods.hpp); unknown names suggest the nearest.
std::string method_name(const JsonView& v) {
  const std::string form = "one of " + join(kMethods);
  const std::string m = v.string("a method name, " + form);
  if (std::find(kMethods.begin(), kMethods.end(), m) == kMethods.end())
    v.fail("unknown method '" + m + "'" + did_you_mean(m, kMethods) + "; expected " + form);
  return m;
}

// An array of distinct free-parameter names (docs/config.md `calibrate.free`), at least `min_size`.
std::vector<std::string> free_parameter_names(const JsonView& f, std::size_t min_size) {
  const std::string form = std::string(min_size > 0 ? "a non-empty" : "an") +
                           " array of distinct parameter names from " + join(kFreeNames);
  const std::size_t n = f.require_array(form, min_size);
  std::vector<std::string> names;
  for (std::size_t i = 0; i < n; ++i) {
    const JsonView e = f.element(i);
    const std::string name = e.string("a parameter name, one of " + join(kFreeNames));
    if (std::find(kFreeNames.begin(), kFreeNames.end(), name) == kFreeNames.end())
      e.fail("unknown parameter '" + name + "'" + did_you_mean(name, kFreeNames) + "; expected one of " +
             join(kFreeNames));
    if (std::find(names.begin(), names.end(), name) != names.end())
      e.fail("parameter '" + name + "' is listed twice");
    names.push_back(name);
  }
  return names;
}

CalibrateConfig parse_calibrate(const JsonView& c) {
  c.require_object(
      "an object {\"method\", \"free\", \"compare\", \"use_control_poles\", \"control_sigma_m\", \"seed\", "
      "\"image_sigma\", \"free_candidates\"}");
  c.check_keys({"method", "free", "compare", "use_control_poles", "control_sigma_m", "seed", "image_sigma",
                "free_candidates"});
  CalibrateConfig cal;
  if (auto m = c.find("method")) cal.method = method_name(*m);
  if (auto f = c.find("free")) cal.free = free_parameter_names(*f, 1);
  if (auto f = c.find("free_candidates")) {
    cal.free_candidates = free_parameter_names(*f, 0);
    // Each candidate is tested as one parameter (its t against its σ): a group has no single σ.
    for (std::size_t i = 0; i < cal.free_candidates.size(); ++i)
      if (!parameter_from_name(cal.free_candidates[i]))
        f->element(i).fail(
            "'" + cal.free_candidates[i] +
            "' is a group of parameters; a candidate is one parameter (f, sx, u0, v0, k1, k2, k3, "
            "p1, p2, a1, a2, clock_offset)");
  }
  if (auto cmp = c.find("compare")) {
    const std::size_t n = cmp->require_array("an array of method names (" + join(kMethods) + ")");
    for (std::size_t i = 0; i < n; ++i) {
      const JsonView e = cmp->element(i);
      const std::string m = method_name(e);
      if (std::find(cal.compare.begin(), cal.compare.end(), m) != cal.compare.end())
        e.fail("method '" + m + "' is listed twice");
      cal.compare.push_back(m);
    }
  }
  if (auto u = c.find("use_control_poles")) cal.use_control_poles = u->boolean("true or false");
  if (auto v = c.find("control_sigma_m"))
    cal.control_sigma_m = Loader::positive(*v, "a positive standard deviation in metres");
  if (auto s = c.find("seed")) cal.seed = s->unsigned_integer("a non-negative integer seed");
  if (auto v = c.find("image_sigma")) {
    const std::string form = "\"estimate\", \"estimate_independent\" or \"stated\"";
    const std::string w = v->string(form);
    if (w != "estimate" && w != "estimate_independent" && w != "stated") v->fail_expected(form);
    cal.estimate_image_sigma = w != "stated";
    cal.image_time_correlation = w == "estimate";
  }
  return cal;
}

RunConfig parse_run(const JsonView& r) {
  r.require_object("an object {\"fail_on_poorly_determined\", \"fail_on_degraded\"}");
  r.check_keys({"fail_on_poorly_determined", "fail_on_degraded"});
  RunConfig run;
  if (auto f = r.find("fail_on_poorly_determined"))
    run.fail_on_poorly_determined = f->boolean("true or false");
  if (auto f = r.find("fail_on_degraded")) run.fail_on_degraded = f->boolean("true or false");
  return run;
}

}  // namespace

const std::vector<std::string>& default_calibrate_free() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v = default_free_parameters();
    v.insert(v.begin() + 2, {parameter_name(CameraParameter::u0), parameter_name(CameraParameter::v0)});
    return v;
  }();
  return names;
}

MissionConfig parse_mission_config(const std::string& json_text, const std::string& path, bool check_files) {
  MissionConfig cfg;
  std::error_code ec;
  fs::path abs = fs::absolute(fs::path(path), ec);
  if (ec) abs = fs::path(path);
  abs = abs.lexically_normal();
  cfg.config_path = abs.string();
  cfg.config_dir = abs.parent_path().string();
  cfg.config_sha256 = sha256_hex(json_text);

  const nlohmann::json doc = parse_json_text(json_text, path, ErrorKind::usage);
  const JsonView root(doc, path, "", ErrorKind::usage);
  root.require_object("a mission config object (docs/config.md)");
  root.check_keys({"mission", "site", "gnss", "attitude", "lever_arm", "poles", "cameras", "align", "detect",
                   "calibrate", "intersect", "trajectory", "run", "output_dir"});
  const Loader L{path, abs.parent_path(), check_files};

  if (auto m = root.find("mission")) cfg.mission = m->string("a free-text string");
  cfg.origin = parse_site(root.at("site", "an object {\"origin\": {\"lat\", \"lon\", \"h\"}}"));
  cfg.gnss = parse_gnss(L, root.at("gnss", "an object {\"pos_files\": [...], ...}"));
  if (auto a = root.find("attitude")) {
    a->require_object("an object {\"file\": \"attitude.csv\"}");
    a->check_keys({"file", "gnss_lag_ms"});
    const char* expected =
        "an attitude file path (CSV utc,roll_deg,pitch_deg,yaw_deg, PX4 ULog or ArduPilot DataFlash)";
    cfg.attitude_file = L.input_file(a->at("file", expected), expected);
    if (auto lag = a->find("gnss_lag_ms"))
      cfg.attitude_gnss_lag_ms =
          Loader::in_range(*lag, 0, 1000, "the GNSS receiver's lag in ms, in [0, 1000]");
  }
  cfg.lever_arm = parse_lever_arm(
      L,
      root.at("lever_arm",
              "one of {\"body_frd_m\": [x,y,z]}, {\"vertical_m\": d}, {\"total_station\": file}"),
      !cfg.attitude_file.empty());
  if (auto p = root.find("poles")) cfg.poles_file = L.input_file(*p, "a pole survey CSV path");

  // An empty camera list is allowed: a gnss-only run (the lamp track alone) is a real use; the
  // camera stages refuse a config without cameras.
  const std::string cams_form = "an array of camera objects (empty for a gnss-only run)";
  const JsonView cams = root.at("cameras", cams_form);
  const std::size_t nc = cams.require_array(cams_form, 0);
  for (std::size_t i = 0; i < nc; ++i) {
    const JsonView cv = cams.element(i);
    CameraConfig cam = parse_camera(L, cv);
    for (std::size_t k = 0; k < cfg.cameras.size(); ++k)
      if (cfg.cameras[k].id == cam.id)
        cv.at("id", "").fail("duplicate camera id '" + cam.id + "' (also cameras[" + std::to_string(k) +
                             "].id); ids must be unique, they name the output folders");
    cfg.cameras.push_back(std::move(cam));
  }

  if (auto a = root.find("align")) {
    a->require_object("an object {\"max_frame_offset_s\"}");
    a->check_keys({"max_frame_offset_s"});
    if (auto v = a->find("max_frame_offset_s"))
      cfg.align.max_frame_offset_s = Loader::positive(*v, "a positive duration in seconds");
  }
  if (auto d = root.find("detect")) {
    d->require_object("an object {\"min_snr\", \"threads\"}");
    d->check_keys({"min_snr", "threads"});
    if (auto v = d->find("min_snr"))
      cfg.detect.min_snr = Loader::positive(*v, "a positive signal-to-noise ratio");
    if (auto v = d->find("threads")) {
      const std::string form = "a non-negative integer (0 = all hardware threads), at most 1024";
      const std::int64_t n = v->integer(form);
      if (n < 0 || n > 1024) v->fail_expected(form);
      cfg.detect.threads = static_cast<int>(n);
    }
  }
  if (auto c = root.find("calibrate")) {
    cfg.calibrate = parse_calibrate(*c);
    if (cfg.calibrate.use_control_poles && cfg.poles_file.empty())
      c->at("use_control_poles", "").fail("control poles are asked for but the config has no \"poles\" file");
  }
  if (auto x = root.find("intersect")) {
    x->require_object("an object {\"pick_sigma_px\", \"bar_mean_dR_m\"}");
    x->check_keys({"pick_sigma_px", "bar_mean_dR_m"});
    if (auto v = x->find("pick_sigma_px"))
      cfg.intersect.pick_sigma_px = Loader::positive(*v, "a positive pixel standard deviation");
    // At most 1 m: a bar meant in cm or mm but written as a number of metres is refused.
    if (auto v = x->find("bar_mean_dR_m")) {
      const std::string form = "a positive distance in metres, at most 1 (e.g. 0.01 for 1 cm)";
      cfg.intersect.bar_mean_dR_m = Loader::positive(*v, form);
      if (cfg.intersect.bar_mean_dR_m > 1) v->fail_expected(form);
    }
  }
  if (auto x = root.find("trajectory")) {
    x->require_object(
        "an object {\"rate_hz\", \"extrapolation_sigma_px_per_px\", \"smoothing\", \"label_sigma\", "
        "\"imported_cameras\"}");
    x->check_keys(
        {"rate_hz", "extrapolation_sigma_px_per_px", "smoothing", "label_sigma", "imported_cameras"});
    if (auto v = x->find("label_sigma")) {
      const std::string form = "\"estimate\" or \"stated\"";
      const std::string m = v->nonempty_string(form);
      if (m != "estimate" && m != "stated") v->fail_expected(form);
      cfg.trajectory.estimate_label_sigma = m == "estimate";
    }
    if (auto v = x->find("smoothing")) {
      const std::string form = "\"constant_acceleration\" or \"none\"";
      const std::string m = v->nonempty_string(form);
      if (m != "constant_acceleration" && m != "none") v->fail_expected(form);
      cfg.trajectory.smooth = m == "constant_acceleration";
    }
    if (auto v = x->find("rate_hz")) {
      const std::string form = "output instants per second, positive, at most 100000";
      cfg.trajectory.rate_hz = Loader::positive(*v, form);
      if (cfg.trajectory.rate_hz > 1e5) v->fail_expected(form);
    }
    // At most 1: a px of lens error per px outside the coverage is already no model at all.
    if (auto v = x->find("extrapolation_sigma_px_per_px")) {
      const std::string form = "px of lens-model error per px outside the coverage, from 0 to 1";
      cfg.trajectory.extrapolation_sigma_px_per_px = Loader::in_range(*v, 0, 1, form);
    }
    if (auto v = x->find("imported_cameras")) {
      const std::string form = "an array of imported cameras (docs/trajectory.md \"Imported calibrations\")";
      const std::size_t n = v->require_array(form, 0);
      for (std::size_t i = 0; i < n; ++i) {
        const JsonView e = v->element(i);
        ImportedCameraConfig cam = parse_imported_camera(L, e);
        for (const CameraConfig& other : cfg.cameras)
          if (other.id == cam.id)
            e.at("id", "").fail("duplicate camera id '" + cam.id +
                                "' (also in cameras[]); ids must be unique");
        for (const ImportedCameraConfig& other : cfg.trajectory.imported_cameras)
          if (other.id == cam.id)
            e.at("id", "").fail("duplicate camera id '" + cam.id + "'; ids must be unique");
        cfg.trajectory.imported_cameras.push_back(std::move(cam));
      }
    }
  }
  if (auto r = root.find("run")) cfg.run = parse_run(*r);
  fs::path out = "out";
  if (auto o = root.find("output_dir")) out = o->nonempty_string("a folder path");
  if (out.is_relative()) out = abs.parent_path() / out;
  cfg.output_dir = out.lexically_normal().string();
  return cfg;
}

MissionConfig load_mission_config(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error(ErrorKind::usage, path, 0, "", "mission config file not found");
  if (fs::is_directory(path, ec))
    throw Error(ErrorKind::usage, path, 0, "", "expected a mission config JSON file, got a folder");
  std::string text;
  try {
    text = read_file_text(path);
  } catch (const Error& e) {
    throw Error(ErrorKind::usage, path, 0, "", e.reason());
  }
  return parse_mission_config(text, path, true);
}

}  // namespace rangecal
