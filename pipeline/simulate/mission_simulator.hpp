#pragma once
// The mission simulator (docs/simulator.md). `simulate_mission` is pure: Scenario → SimMission, the whole
// synthetic truth and every observation (GNSS epochs with noise, attitude log, exported frames
// with the true lamp pixel, surveyed poles, pole picks). `write_mission` then writes it in
// exactly the input formats of docs/formats.md plus `truth.json`:
//   gnss/rover.pos            RTKLIB 2.4.3 .pos, GPST calendar time, lat/lon/h degrees
//   gnss/attitude.csv         utc,roll_deg,pitch_deg,yaw_deg
//   <cam>/timestamps.csv      frame,file,utc (only every export_step-th frame)
//   <cam>/frames/<cam>_NNNNNNN.png   8- or 16-bit grey PNG
//   <cam>/poles_px.csv        id,u,v (poles in view, with pick noise)
//   survey/poles.csv          id,role,lat,lon,h (or id,role,E,N,U), with survey noise
//   mission.json              mission config (docs/config.md) pointing at all of it
//   truth.json                true cameras, lamp/antenna per epoch and frame, poles, noise levels
//
// Truth model (docs/conventions.md): the antenna flies the routes in order, joined by transit legs, with a
// trapezoidal speed profile (accelerate, cruise, decelerate) and hovers at each route's ends;
// attitude = a seeded multirotor wobble (+ lean into horizontal accelerations); the lamp is
// antenna + ENU(R_nb·lever); a GNSS epoch carries the ANTENNA position + noise; a frame n of a
// camera is exposed at true time start + n/fps, stamped true time + clock_offset_s, and shows
// the LAMP at its true time. All randomness comes from seeded streams (same seed → same files).
#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"
#include "gnss/track/attitude.hpp"
#include "pipeline/simulate/scenario.hpp"
#include "vision/frames/frame_renderer.hpp"

namespace rangecal {

/// The true state at one instant.
struct SimState {
  Eigen::Vector3d antenna_enu = Eigen::Vector3d::Zero();   ///< m
  Eigen::Vector3d velocity_enu = Eigen::Vector3d::Zero();  ///< m/s
  Attitude attitude;
  Eigen::Vector3d lamp_enu = Eigen::Vector3d::Zero();  ///< antenna + ENU(R_nb·lever), m
};

/// One leg of the flight path: a move from `from` to `to` (trapezoidal speed profile) or a hover
/// (from == to).
struct FlightPathLeg {
  double t0_s = 0, t1_s = 0;  ///< mission time span
  Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
  double peak_speed_mps = 0;  ///< reached speed (≤ the cruise speed on short legs)
  double accel_mps2 = 0;
  int route = -1;  ///< scenario route index, -1 for transit legs
  bool hover = false;
};

struct FlightPath {
  std::vector<FlightPathLeg> legs;  ///< contiguous, starting at mission time 0
  double duration_s() const { return legs.empty() ? 0.0 : legs.back().t1_s; }
};

struct SimEpoch {
  UtcTime utc;
  double t_s = 0;  ///< mission time
  Eigen::Vector3d antenna_true = Eigen::Vector3d::Zero();
  Eigen::Vector3d antenna_measured = Eigen::Vector3d::Zero();  ///< what the .pos carries (ENU)
  Eigen::Vector3d lamp_true = Eigen::Vector3d::Zero();
  Eigen::Vector3d sd_enu = Eigen::Vector3d::Zero();  ///< reported 1σ √(white² + σ_GM²) (m): sde sdn sdu
  Attitude attitude;
  int quality = 1;  ///< 1 fix, 2 float
};

struct SimAttitudeSample {
  UtcTime utc;
  Attitude attitude;
};

struct SimFrame {
  std::int64_t frame = 0;  ///< camera frame number (0 at the camera's start_s)
  UtcTime true_utc;        ///< exposure instant
  UtcTime stamp_utc;       ///< what the camera wrote: true + clock_offset_s
  std::string file;        ///< relative to the camera folder, e.g. frames/cam1_0000050.png
  Eigen::Vector3d lamp_enu = Eigen::Vector3d::Zero();
  /// Lamp velocity at the exposure (m/s): antenna velocity + the lever arm's turn with the attitude
  /// (central difference over ±1 ms of the true lamp position).
  Eigen::Vector3d lamp_velocity_enu = Eigen::Vector3d::Zero();
  Eigen::Vector2d lamp_px = Eigen::Vector2d::Zero();  ///< true lamp pixel (undefined if !projects)
  bool projects = false;  ///< in front of the camera and the distortion inverse converged
  bool in_view = false;   ///< projects and 0 ≤ u ≤ W−1, 0 ≤ v ≤ H−1
};

struct SimPick {
  std::string id;
  Eigen::Vector2d true_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d picked_px = Eigen::Vector2d::Zero();
};

struct SimCamera {
  ScenarioCamera spec;
  std::vector<SimFrame> frames;      ///< exported frames only, in time order
  std::vector<SimPick> picks;        ///< poles in view, scenario order
  std::vector<HotPixel> hot_pixels;  ///< fixed hot pixels, excess in DN of the 16-bit scale
};

struct SimPole {
  ScenarioPole truth;
  Eigen::Vector3d surveyed_enu = Eigen::Vector3d::Zero();
};

struct SimMission {
  Scenario scenario;
  FlightPath path;
  std::vector<SimEpoch> epochs;  ///< GNSS epochs written to the .pos (gaps left out)
  std::vector<SimAttitudeSample> attitude;
  std::vector<SimCamera> cameras;
  std::vector<SimPole> poles;
};

/// The flight path of a scenario: for each route a transit leg from the previous route's end
/// (none before the first), a hover of hover_s, the route, another hover of hover_s.
FlightPath make_flight_path(const Scenario& s);

/// The true state at mission time t (s), clamped to [0, duration].
SimState state_at(const Scenario& s, const FlightPath& path, double t_s);

/// Simulates everything except the pixels of the frames (rendered by write_mission).
SimMission simulate_mission(const Scenario& s);

/// Renders the frame `f` of camera `cam` (deterministic in the scenario seed, camera and frame).
/// CV_16UC1 for 16-bit cameras, CV_8UC1 for 8-bit ones.
cv::Mat render_sim_frame(const SimMission& m, const SimCamera& cam, const SimFrame& f);

/// Files written by write_mission, for the CLI summary.
struct WrittenMission {
  std::string config_path;  ///< mission.json
  std::string truth_path;   ///< truth.json
  std::size_t n_epochs = 0;
  std::size_t n_frames = 0;  ///< over all cameras
  std::size_t n_files = 0;
};

/// Writes every file of the mission under `out_dir` (created if needed; files atomically; frames
/// rendered in parallel). Existing files of the same names are replaced.
WrittenMission write_mission(const SimMission& m, const std::string& out_dir);

/// truth.json's text (exposed for tests).
std::string format_truth_json(const SimMission& m);

}  // namespace rangecal
