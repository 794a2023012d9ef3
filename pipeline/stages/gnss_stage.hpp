#pragma once
// The gnss stage (SPEC §4.1): RTKLIB .pos files → filter → GPST→UTC → site ENU → lever arm →
// lamp track, written to `<output_dir>/gnss/lamp_track.csv` (SPEC §5). The computation is a pure
// function of parsed inputs (compute_lamp_track); run_gnss_stage does the file I/O around it.
#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gnss/formats/attitude_file.hpp"
#include "pipeline/config/mission_config.hpp"
#include "gnss/track/attitude.hpp"
#include "gnss/track/epoch_filter.hpp"
#include "gnss/track/lamp_track.hpp"
#include "gnss/formats/rtklib_pos_reader.hpp"
#include "pipeline/io/run_log.hpp"

namespace rangecal {

/// The lever arm after resolving the config (a total-station file becomes a vertical offset).
struct ResolvedLeverArm {
  enum class Form { body_frd, vertical };
  Form form = Form::vertical;
  std::string source = "vertical";  ///< "body_frd", "vertical" or "total_station", for reports
  Eigen::Vector3d body_frd_m = Eigen::Vector3d::Zero();  ///< form body_frd: antenna → lamp, FRD (m)
  double vertical_m = 0;     ///< form vertical: lamp this far below the antenna (m)
  double vertical_sd_m = 0;  ///< 1σ of vertical_m (total station), added to sdU of the track
  int sessions = 0;          ///< total-station sessions averaged (0 otherwise)
};

struct GnssStageInputs {
  std::vector<PosFile> pos_files;          ///< ≥ 1, each strictly increasing in time
  std::optional<AttitudeSeries> attitude;  ///< required for the body_frd form
  ResolvedLeverArm lever;
  GeodeticOrigin origin;  ///< site.origin
  EpochFilterOptions filter;
  /// Attitude samples farther apart than this are not interpolated across (s). SPEC is silent;
  /// 1 s bridges any flight-controller log rate (≥ 5 Hz) with margin, not a dropout.
  double max_attitude_gap_s = 1.0;
};

struct GnssStageReport {
  EpochFilterCounts filter;             ///< read / kept / dropped by Q and sd
  std::size_t dropped_no_attitude = 0;  ///< body_frd form: epochs outside the attitude coverage
  std::size_t track_epochs = 0;
  std::vector<TimeGap> gaps;  ///< in the final track, spacing > max_gap_s
  UtcTime track_start, track_end;
  /// Vertical form with attitude present: the largest error of the vertical form (m) over epochs
  /// with attitude, and how many epochs exceed 5 mm.
  double vertical_form_max_error_m = 0;
  std::size_t vertical_form_epochs_over_5mm = 0;
  std::vector<std::string> warnings;
};

struct GnssStageResult {
  LampTrack track;
  GnssStageReport report;
};

/// Threshold of the vertical-form warning: more than 5 mm of lamp position error (half the PPK
/// noise of one epoch) from ignoring the attitude is worth the user's attention.
constexpr double kVerticalFormWarnM = 0.005;

/// The pure stage. Throws rangecal::Error: usage when the body_frd form has no attitude; input for
/// overlapping .pos files, when no epoch survives filtering, or when the attitude's time span does
/// not overlap the filtered GNSS epochs' (the message names both files and both spans).
GnssStageResult compute_lamp_track(const GnssStageInputs& in);

/// Resolves cfg.lever_arm (reads the total-station file when configured).
ResolvedLeverArm resolve_lever_arm(const LeverArmConfig& cfg);

/// The run.json "counts" of the stage (deterministic, keys sorted).
nlohmann::json gnss_stage_counts(const GnssStageReport& report, const std::vector<PosFile>& files,
                                 const ResolvedLeverArm& lever);

/// The run.json counts of the attitude file (key "attitude"): path, reader, samples, UTC span, and
/// for an autopilot log the message counts and the boot-time → UTC fit (docs/gnss.md).
nlohmann::json attitude_file_counts(const AttitudeFileReport& report, const std::string& path);

/// Reads cfg's .pos files, attitude (CSV, PX4 ULog or ArduPilot DataFlash, by content) and lever
/// arm, computes the track, writes `<output_dir>/gnss/lamp_track.csv` atomically, and returns the
/// stage log (wall time, counts, warnings). The caller merges the log into run.json (update_run_log).
StageLog run_gnss_stage(const MissionConfig& cfg);


}  // namespace rangecal
