#pragma once
// The gnss stage (docs/gnss.md): RTKLIB .pos files → filter → GPST→UTC → site ENU → lever arm →
// lamp track, written to `<output_dir>/gnss/lamp_track.csv` (docs/outputs.md). The computation is a pure
// function of parsed inputs (pipeline/steps/lamp_track_computation.hpp); run_gnss_stage reads the
// .pos files, the attitude and the lever arm, calls it, and writes the track.
#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gnss/formats/attitude_file.hpp"
#include "gnss/formats/rtklib_pos_reader.hpp"
#include "gnss/track/attitude.hpp"
#include "gnss/track/epoch_filter.hpp"
#include "gnss/track/lamp_track.hpp"
#include "pipeline/io/gnss_record.hpp"
#include "pipeline/io/run_log.hpp"
#include "pipeline/mission/mission_config.hpp"
#include "pipeline/steps/lamp_track_computation.hpp"

namespace rangecal {

/// Resolves cfg.lever_arm (reads the total-station file when configured).
ResolvedLeverArm resolve_lever_arm(const LeverArmConfig& cfg);

/// The stage's run.json record (pipeline/io/gnss_record.hpp) without its attitude part.
GnssRecord gnss_record(const LampTrackReport& report, const std::vector<PosFile>& files,
                       const ResolvedLeverArm& lever);

/// The record of the attitude file: path, reader, samples, UTC span, and for an autopilot log the
/// message counts and the boot-time → UTC fit (docs/gnss.md).
AttitudeRecord attitude_record(const AttitudeFileReport& report, const std::string& path);

/// Reads cfg's .pos files, attitude (CSV, PX4 ULog or ArduPilot DataFlash, by content) and lever
/// arm, computes the track, writes `<output_dir>/gnss/lamp_track.csv` atomically, and returns the
/// stage log (wall time, counts, warnings). The caller merges the log into run.json (update_run_log).
StageLog run_gnss_stage(const MissionConfig& cfg);

}  // namespace rangecal
