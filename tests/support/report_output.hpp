#pragma once
// A mission output folder as the stages before the report leave it, written with the project's own
// writers from synthetic data (the report's unit tests and its command-line test): the lamp track,
// cam1 calibrated (pairs, residuals, calibration.json, methods.csv), cam2 whose calibration failed,
// intersection.csv, run.json, and optionally the network's adjusted track and statistics. The
// data are exposed so that tests compare the report's numbers with them.
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "pipeline/mission/mission_config.hpp"
#include "vision/camera/calibration_result.hpp"

namespace rangecal::test {

/// printf-style formatting of one number.
std::string fixed(const char* format, double x);

/// The check poles written to intersection.csv (metres): dE, dN, dU and sigma; dR follows.
struct Pole {
  const char* id;
  double dE, dN, dU, sigma;
};
inline constexpr Pole kPoles[] = {{"A1", 0.0120, -0.0050, 0.0031, 0.0110},
                                  {"A2", -0.0042, 0.0211, -0.0008, 0.0120},
                                  {"A3", 0.0007, 0.0033, 0.0152, 0.0105}};
double pole_dr(const Pole& p);

/// The network's adjusted track written to gnss/lamp_track_adjusted.csv (metres): time since the
/// first epoch, corrections, the adjusted position's σ and the PPK-outlier flag. Two ascents 30 s
/// apart; epochs 2 and 4 flagged (their corrections are their PPK errors).
struct AdjustedEpoch {
  double t_s, dE, dN, dU, sdE, sdN, sdU;
  int flag;
};
inline constexpr AdjustedEpoch kAdjusted[] = {{0.0, 0.0012, -0.0008, 0.0031, 0.0015, 0.0018, 0.0040, 0},
                                              {0.2, -0.0021, 0.0004, -0.0012, 0.0016, 0.0019, 0.0041, 0},
                                              {0.4, 0.1500, -0.0900, 0.2200, 0.0030, 0.0035, 0.0080, 1},
                                              {30.0, 0.0007, 0.0015, -0.0046, 0.0014, 0.0017, 0.0039, 0},
                                              {30.2, -0.0600, 0.1200, -0.0300, 0.0031, 0.0036, 0.0082, 1},
                                              {30.4, 0.0003, -0.0019, 0.0024, 0.0015, 0.0018, 0.0040, 0}};
inline constexpr std::int64_t kAdjustedStartNs = 1'700'000'000'000'000'000;
/// The ISO 8601 UTC of an adjusted epoch.
std::string adjusted_utc(const AdjustedEpoch& e);

/// run.json's network statistics as the calibrate stage writes them (pipeline/io/network_json.hpp),
/// the PPK error model white.
nlohmann::json network_counts();

struct ReportOutput {
  MissionConfig cfg;
  CalibrationResult cal;          ///< cam1's calibration.json
  std::size_t cam1_pairs = 0;     ///< lamp pairs in cam1/correspondences.csv
  std::size_t cam1_rejected = 0;  ///< of them marked used = 0
  std::size_t cam1_segments = 0;  ///< ascents (and the pole tops), each a separate time block
};

/// Writes the folder `dir`/out (config path `dir`/mission.json): see the file comment.
ReportOutput write_report_output(const std::filesystem::path& dir, bool with_intersection = true,
                                 bool with_network = false);

/// A JSON file parsed.
nlohmann::json read_json(const std::filesystem::path& p);

}  // namespace rangecal::test
