#pragma once
// The mission config (docs/config.md), loaded and validated. All paths are absolute after loading
// (relative ones resolve against the config file's folder). Defaults are documented at each
// field and in docs/config.md.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gnss/geodesy/geodetic_origin.hpp"
#include "gnss/time/utc_time.hpp"
#include "gnss/track/ppk_error_model.hpp"
#include "vision/camera/camera_parameters.hpp"
#include "vision/tracks/track_formats.hpp"
#include "vision/triangulation/stated_calibration_sigma.hpp"

namespace rangecal {

struct GnssConfig {
  std::vector<std::string> pos_files;  ///< RTKLIB .pos files (≥ 1), absolute paths
  std::vector<int> accept_quality{1};  ///< Q values kept (1 fix … 6 ppp); default [1]
  double max_sd_m = 0.05;              ///< epochs with any of sdn/sde/sdu above this are dropped
  double max_gap_s = 0.5;              ///< never interpolate across a gap longer than this
  /// gnss.error_model (docs/gnss.md "PPK error model"): the fixes' error as the network weighs it —
  /// white scale, Gauss–Markov sd and τ, horizontal and vertical. "white": each fix under its own
  /// .pos covariance, and the robust first solve's model when estimating.
  PpkErrorModel error_model;
  /// gnss.error_model "estimate" (the default): the model is estimated from the mission by the
  /// network (optim/network/ppk_error_estimation.hpp). "white" or a model given in full: that model,
  /// not estimated.
  bool estimate_error_model = true;
};

struct LeverArmConfig {
  enum class Kind { body_frd, vertical, total_station };
  Kind kind = Kind::vertical;
  Eigen::Vector3d body_frd_m = Eigen::Vector3d::Zero();  ///< antenna → lamp, body FRD (m); kind body_frd
  double vertical_m = 0;           ///< lamp is this far below the antenna; kind vertical
  std::string total_station_file;  ///< `session,target,E,N,U`; kind total_station
};

struct SensorConfig {
  int width_px = 0;
  int height_px = 0;
  double pixel_size_um[2] = {0, 0};  ///< (x, y) pixel pitch in micrometres
};

struct FramesConfig {
  std::string timestamps;  ///< `frame,file,utc` CSV (files may be images, a video or a .cine); or empty
  std::string cine;        ///< a Phantom .cine alone, with its own time stamps; or empty
  std::string mraw;        ///< a Photron .mraw alone, timed by its .cihx/.cih header; or empty
  /// With `mraw`: camera clock − UTC in hours (Photron's header time has no zone); required there.
  std::optional<double> clock_utc_offset_h;
  bool allow_missing = false;  ///< a missing/unreadable frame is skipped (and reported) instead of failing
};

/// cameras[i].track: a 2-D track imported instead of frames (docs/config.md "Imported tracks"), the
/// times of its frames, and whether the camera's clock is estimated from the data.
struct TrackConfig {
  std::string file;               ///< the track file, absolute
  std::string format;             ///< vision/tracks/track_formats.hpp name; empty: recognised from the header
  TrackReadOptions read;          ///< point, camera, y_origin (the image size is the sensor's)
  std::string timestamps;         ///< `frame,utc` CSV (a `file` column is ignored); or empty
  std::optional<UtcTime> t0_utc;  ///< without timestamps: frame t0_frame's time …
  std::int64_t t0_frame = 0;
  double fps = 0;  ///< … and the nominal frame rate (frames/s)
  /// "estimate": the times above are nominal (a camera without time code): the clock's offset and
  /// rate are found from the data (pipeline/steps/camera_clock.hpp). "time_code": they are UTC.
  bool estimate_clock = false;
  std::optional<std::pair<double, double>> clock_search_s;  ///< offsets searched (s); default: the overlap
  /// A rolling shutter's readout (s; row v exposed (v/(H−1) − ½)·readout after the frame's time):
  /// given, or estimated with the clock (`"readout_s": "estimate"`); 0: a global shutter.
  double readout_s = 0;
  bool estimate_readout = false;
  /// A target's track (cameras[i].target_track) only. "calibration": the times above are nominal,
  /// on the same camera clock the align stage estimated from the camera's calibration track (the same
  /// recording or a free-running clock that kept running): that clock (and readout) applies.
  bool calibration_clock = false;
  /// A target's track only: the 1σ of a frame's time beyond the clock's own (s), e.g. a time-code
  /// reader's or the exposure's mid-point uncertainty; 0 by default.
  double timing_sigma_s = 0;
};

struct CameraPriors {
  std::optional<Eigen::Vector2d> principal_point_px;
  double principal_point_sigma_px = 30;  ///< default 30 px
  std::optional<Eigen::Vector3d> center_enu_m;
  double center_sigma_m = 0.05;  ///< default 5 cm
};

/// cameras[i].pixel_sigma_px: the a-priori σ per image axis of each kind of pixel observation (px).
/// The lamp centroids' σ is where the network's image variance component starts from and what it
/// scales (docs/optimisation.md "Image variance components"); a pick's is taken as stated.
struct PixelSigmaConfig {
  double centroid_px = 0.1;  ///< the lamp detector's centroid (pipeline/steps/calibration_problem.hpp)
  double pick_px = 0.3;      ///< a control-pole top picked by hand
  /// A label of an imported 2-D track (cameras[i].track) without its own sigma_px; estimated as the
  /// camera's image variance component, as the centroids' σ.
  double track_px = 1.0;
};

struct CameraConfig {
  std::string id;  ///< unique, [A-Za-z0-9_-]+, used as the output folder name
  FramesConfig frames;
  std::optional<TrackConfig> track;  ///< instead of frames
  /// The target whose trajectory the trajectory stage estimates, as this camera tracked it (2-D labels
  /// with their frame times, docs/trajectory.md).
  std::optional<TrackConfig> target_track;
  SensorConfig sensor;
  double nominal_focal_mm = 0;
  std::string pole_observations;  ///< `id,u,v` CSV, or empty
  CameraPriors priors;
  PixelSigmaConfig pixel_sigma;
  /// This camera's free parameters (docs/config.md `cameras[i].free`): a lens known to need k2, or
  /// known not to; empty: calibrate.free.
  std::vector<std::string> free;
};

struct AlignConfig {
  double max_frame_offset_s = 0.005;  ///< a frame farther than this from every epoch is not used
};

struct DetectConfig {
  double min_snr = 10;  ///< peak SNR below which a candidate is not the lamp
  int threads = 0;      ///< 0 = all hardware threads
};

/// calibrate.free when the config does not give it (docs/config.md "The principal point"): f, k1,
/// u0, v0, pose — the principal point free under its prior (cameras[i].priors; the image centre,
/// σ 30 px, when none is given). The library's own default (default_free_parameters, f, k1, pose)
/// holds it fixed; on simulated two-camera missions a fixed centre is the better estimate only when
/// the true principal point lies within ~2 px (network) or ~3.5 px (per camera) of it
/// (docs/accuracy_analysis.md "The principal point's default").
const std::vector<std::string>& default_calibrate_free();

struct CalibrateConfig {
  /// tsai | tsai_sassa | dlt_lmqn | bundle | network | planar; empty (not given): the calibrate
  /// stage picks `network` when two or more cameras see common lamp-track epochs, else `bundle`
  /// (docs/config.md "Default method").
  std::string method;
  std::vector<std::string> free = default_calibrate_free();  ///< bundle free parameters
  std::vector<std::string> compare;                          ///< extra methods for methods.csv
  bool use_control_poles = false;                            ///< add `control` poles as calibration points
  double control_sigma_m = 0.005;  ///< surveyed `control` pole-top σ per axis (m): total station / RTK
  std::uint64_t seed = 1;          ///< seed of every random search (RANSAC, SSA)
  /// calibrate.image_sigma "estimate" (the default): the network estimates each camera's lamp-centroid
  /// σ with the PPK model (when it estimates that); "stated": the cameras' pixel_sigma_px as given.
  bool estimate_image_sigma = true;
  /// With "estimate": a camera whose residuals repeat themselves in time is weighed by σ·√F
  /// (optim/network/image_time_correlation.hpp); "estimate_independent" counts every centroid as an
  /// independent look.
  bool image_time_correlation = true;
  /// calibrate.free_candidates: parameters each camera of the network may add to `free` when the
  /// data determine it significantly and it predicts the camera's rim no clearly worse
  /// (pipeline/steps/lens_selection.hpp); empty: every camera keeps `free`.
  std::vector<std::string> free_candidates = {"k2"};
};

struct IntersectConfig {
  double pick_sigma_px = 0.5;  ///< 1σ per axis of a hand-picked pole-top pixel (px)
  /// The check poles' mean ΔR the report's verdict holds the intersection to (m); 1 cm is
  /// rangecal's quality bar (docs/accuracy_analysis.md).
  double bar_mean_dR_m = 0.010;
};

/// trajectory.imported_cameras[i] (docs/trajectory.md "Imported calibrations"): a camera calibrated
/// elsewhere — an OpenCV camera file or a DLT-11 column with the σ its user states, or another
/// mission's calibration.json with its covariance — whose target track
/// the trajectory stage uses beside the mission's own cameras.
struct ImportedCameraConfig {
  std::string id;          ///< unique among cameras[] and these
  std::string opencv_yml;  ///< an OpenCV camera YAML (absolute), or empty
  std::string dlt;         ///< a DLTdv / Argus DLT-11 coefficient CSV (absolute), or empty
  /// a rangecal calibration.json from another mission on the same site (absolute), or empty: its own
  /// covariance, with its correlations, stands for the stated σ
  std::string rangecal_json;
  int dlt_column = 1;  ///< its camera's column (1-based)
  SensorConfig sensor;
  StatedCalibrationSigma sigma;
  TrackConfig target_track;   ///< its times UTC ("time_code")
  double label_sigma_px = 1;  ///< a label's 1σ per axis where the track gives none (px)
};

/// The trajectory stage's options (docs/trajectory.md).
struct TrajectoryConfig {
  /// Output instants per second, on a grid of whole UTC seconds (5: …00.0, …00.2, …); 0: the
  /// fastest target track's median frame rate.
  double rate_hz = 0;
  /// A label d px outside its camera's calibration coverage adds this × d px of lens-model error
  /// (docs/trajectory.md "Extrapolated views"); ≥ 0.
  double extrapolation_sigma_px_per_px = 0.05;
  /// The per-instant fixes smoothed by a constant-acceleration process (docs/trajectory.md
  /// "Method" 6); false (the default): each instant as triangulated.
  bool smooth = false;
  /// Each camera's label σ estimated from the views' disagreement (docs/trajectory.md "Label σ"),
  /// the σ given its a-priori value; false ("stated", the default): the σ given, as given.
  bool estimate_label_sigma = false;
  std::vector<ImportedCameraConfig> imported_cameras;
};

/// What the run's outcome counts as incomplete beyond the fixed rules (docs/reliability.md "Run
/// outcome").
struct RunConfig {
  /// A parameter the calibrate stage calls poorly determined makes the run partial (exit 4)
  /// instead of only warning.
  bool fail_on_poorly_determined = false;
  /// A degradation (docs/reliability.md "Run outcome") makes the run partial (exit 4) instead of
  /// degraded (exit 0).
  bool fail_on_degraded = false;
};

struct MissionConfig {
  std::string config_path;    ///< absolute path of the config file
  std::string config_dir;     ///< its folder (relative paths resolve here)
  std::string config_sha256;  ///< hash of the file bytes, for run.json
  std::string mission;        ///< free text
  GeodeticOrigin origin;
  GnssConfig gnss;
  std::string attitude_file;  ///< empty when absent
  /// attitude.gnss_lag_ms: an autopilot log's GNSS receiver lag (ms, [0, 1000]); none: the log
  /// type's documented default (gnss/formats/autopilot_attitude_report.hpp, docs/gnss.md).
  std::optional<double> attitude_gnss_lag_ms;
  LeverArmConfig lever_arm;
  std::string poles_file;  ///< empty when absent
  std::vector<CameraConfig> cameras;
  AlignConfig align;
  DetectConfig detect;
  CalibrateConfig calibrate;
  IntersectConfig intersect;
  TrajectoryConfig trajectory;
  RunConfig run;
  std::string output_dir;  ///< absolute; default "<config_dir>/out"
};

/// Names a camera id may not take: `gnss` is the mission's folder of track files
/// (pipeline/io/output_paths.hpp), `network` and `method_choice` the calibrate stage's mission-level
/// records (run.json `stages.calibrate.counts`, network.json), which a camera's records must never
/// be read as.
const std::vector<std::string>& reserved_camera_ids();

/// Loads and validates a mission config. Throws rangecal::Error (kind usage → exit 2) naming the
/// config file and the JSON path (e.g. `cameras[1].sensor.pixel_size_um`), the problem and the
/// expected form. Unknown keys are errors. Referenced input files must exist (named by key).
MissionConfig load_mission_config(const std::string& path);

/// As load_mission_config, from JSON text already read; `path` is used for messages and to
/// resolve relative paths. `check_files` = false skips the existence checks (for unit tests).
MissionConfig parse_mission_config(const std::string& json_text, const std::string& path,
                                   bool check_files = true);

}  // namespace rangecal
