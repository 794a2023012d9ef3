#pragma once
// A simulation scenario (docs/simulator.md): everything `rangecal simulate` needs to render a synthetic
// mission — site, GNSS, lever arm, attitude, lamp, sky, cameras, routes, poles — loaded from
// JSON and validated. Every key is documented in docs/simulator.md. Errors are rangecal::Error
// (kind usage → exit 2) naming the scenario file and the JSON path (`cameras[1].f_mm`); unknown
// keys are errors. Times inside the scenario are seconds from `start_utc` ("mission time").
#include <Eigen/Core>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"
#include "pipeline/mission/mission_config.hpp"
#include "pipeline/simulate/ppk_error.hpp"
#include "vision/camera/camera_model.hpp"
#include "vision/camera/camera_parameters.hpp"

namespace rangecal {

/// A closed interval of mission time, seconds from start_utc.
struct TimeInterval {
  double start_s = 0;
  double end_s = 0;
  bool contains(double t) const { return t >= start_s && t <= end_s; }
};

struct ScenarioGnss {
  double rate_hz = 10;  ///< epoch rate (Hz)
  Eigen::Vector3d noise_sd_m =
      Eigen::Vector3d(0.01, 0.01, 0.015);     ///< 1σ of E, N, U WHITE noise (m), fix epochs
  PpkCorrelatedError correlated_error;        ///< Gauss–Markov + per-flight bias (none by default)
  double float_fraction = 0;                  ///< probability that an epoch is float (Q=2), [0, 1]
  std::vector<TimeInterval> float_intervals;  ///< every epoch inside is float
  double float_noise_factor = 10;             ///< float epochs: noise (and the sd columns) × this (≥ 1)
  std::vector<TimeInterval> gaps;             ///< no epochs inside these intervals
  int satellites = 14;                        ///< the `ns` column
};

struct ScenarioAttitude {
  double rate_hz = 50;      ///< attitude log rate (Hz)
  double wobble_deg = 1.5;  ///< amplitude scale of the roll/pitch wobble (deg; yaw wobbles half as much)
  double yaw_deg = 0;       ///< mean heading, clockwise from north (deg)
  bool tilt_with_acceleration = true;  ///< lean into horizontal accelerations like a multirotor
};

struct ScenarioLamp {
  double psf_sigma_px = 1.2;  ///< Gaussian PSF σ (px)
  double peak = 30000;        ///< PSF peak above the sky (DN of a 16-bit frame; scaled for 8-bit)
  double saturation = 65535;  ///< pixel values clip here (DN, 16-bit scale)
};

struct ScenarioDistractor {
  double u_px = 0, v_px = 0;  ///< a static light at this pixel (in every frame of every camera)
  double peak = 0;            ///< its peak above the sky (DN, 16-bit scale)
  double sigma_px = 1.5;      ///< its PSF σ (px)
};

struct ScenarioSky {
  double background = 2000;                          ///< sky level at the image centre (DN, 16-bit scale)
  Eigen::Vector2d gradient = Eigen::Vector2d(0, 0);  ///< dDN/du, dDN/dv (DN per px)
  double read_noise = 200;                           ///< Gaussian noise 1σ (DN, 16-bit scale)
  int hot_pixels = 0;                                ///< this many fixed hot pixels per camera
  double hot_pixel_excess = 40000;  ///< their excess over the sky: uniform in [½, 1]× this (DN, 16-bit scale)
  std::optional<ScenarioDistractor> distractor;
};

struct ScenarioCamera {
  std::string id;               ///< [A-Za-z0-9_-]+, unique
  Camera camera;                ///< true parameters (intrinsics, pose R, T) in rangecal's model
  double fps = 500;             ///< camera frame rate (Hz)
  int export_step = 50;         ///< every export_step-th frame is exported
  int bit_depth = 16;           ///< 8 or 16
  double clock_offset_s = 0;    ///< frame UTC stamp = true time + this
  double start_s = 0;           ///< recording starts at this mission time (frame 0)
  double nominal_focal_mm = 0;  ///< lens marking written to the mission config (default: f rounded to mm)
};

struct ScenarioRoute {
  enum class Type { vertical, line };
  Type type = Type::vertical;
  Eigen::Vector3d start_enu_m = Eigen::Vector3d::Zero();  ///< antenna position at the start (m)
  Eigen::Vector3d end_enu_m = Eigen::Vector3d::Zero();    ///< antenna position at the end (m)
  double speed_mps = 2;                                   ///< cruise speed (m/s)
  double accel_mps2 = 1;                                  ///< acceleration and deceleration (m/s²)
  double hover_s = 1;                                     ///< hover at the start and at the end (s)
};

struct ScenarioPole {
  std::string id;
  std::string role;                                 ///< "control" or "check"
  Eigen::Vector3d enu_m = Eigen::Vector3d::Zero();  ///< true pole-top position (m)
};

struct Scenario {
  std::string file;  ///< path it was loaded from (for messages)
  std::string mission = "rangecal simulated mission";
  std::uint64_t seed = 1;
  /// Optional "calibrate" section for the written mission config (empty: method bundle, the seed).
  nlohmann::json mission_calibrate;
  /// Optional gnss.error_model for the written mission config (null: the model the errors were
  /// drawn from when it is correlated, else none, which estimates it; docs/gnss.md "PPK error model").
  nlohmann::json mission_error_model;
  UtcTime start_utc;
  GeodeticOrigin origin;
  ScenarioGnss gnss;
  Eigen::Vector3d lever_arm_frd_m = Eigen::Vector3d::Zero();  ///< antenna → lamp, body FRD (m)
  ScenarioAttitude attitude;
  ScenarioLamp lamp;
  ScenarioSky sky;
  std::vector<ScenarioCamera> cameras;
  std::vector<ScenarioRoute> routes;
  double transit_speed_mps = 3;  ///< speed of the legs joining consecutive routes
  double transit_accel_mps2 = 1;
  std::vector<ScenarioPole> poles;
  std::string poles_format = "llh";  ///< poles.csv columns: "llh" (id,role,lat,lon,h) or "enu"
  double survey_noise_m = 0.005;     ///< 1σ per axis of the surveyed pole positions (m)
  double pick_noise_px = 0.2;        ///< 1σ per axis of the pole-top picks (px)
};

/// Parses and validates scenario JSON text; `path` names the file in messages. Besides types
/// and ranges it checks that every camera sees some part of some route (else the error names
/// `cameras[i]`).
/// Time a straight leg of `length_m` takes from rest to rest, with a trapezoidal speed profile
/// (accelerate at `accel_mps2` to `speed_mps`, cruise, brake) or a triangular one when the leg is
/// too short to reach the speed (s).
double straight_leg_duration_s(double length_m, double speed_mps, double accel_mps2);

/// Limits on the work a scenario may ask for (docs/reliability.md, "Bounded work"): checked when
/// the scenario is read, before anything is simulated or rendered.
struct SimulationLimits {
  double max_flight_s = 3 * 3600.0;      ///< a multirotor mission, with margin
  double max_gnss_epochs = 2.0e6;        ///< 3 h at 100 Hz and more
  double max_attitude_samples = 2.0e7;   ///< 3 h at 1 kHz and more
  double max_frames_per_camera = 2.0e5;  ///< exported frames
  double max_rendered_pixels = 4.0e10;   ///< all cameras' exported frames together (80 GB at 16 bit)
};

Scenario parse_scenario(const std::string& json_text, const std::string& path);

/// Reads and parses a scenario file (a missing file is an input error naming it).
Scenario load_scenario(const std::string& path);

/// The true camera (rangecal's model) from the pose keys: R = rows (x right, y down, z optical
/// axis in ENU) built so the optical axis points from `center` to `look_at` and the image x axis
/// is horizontal (camera roll 0), then rotated about the optical axis by `roll_deg`.
Eigen::Matrix3d look_at_rotation(const Eigen::Vector3d& center, const Eigen::Vector3d& look_at,
                                 double roll_deg);

}  // namespace rangecal
