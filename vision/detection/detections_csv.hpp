#pragma once
// `<cam>/detections.csv` (docs/outputs.md): `frame,utc,u,v,peak,area,snr,status`, one line per frame the
// detect stage looked at, in frame order. Formatting is fixed so the same detections give the same
// bytes: utc ISO 8601 with 9 fraction digits, u v with 4 decimals (px), peak with 1 decimal (DN
// above the local background), area integer (pixels above the growth threshold), snr with 2
// decimals (peak / frame noise σ). Fields of a frame without any candidate are left empty.
// Statuses (docs/frames_and_detection.md): ok, ok_saturated, ok_by_motion — the lamp, usable;
// no_lamp, ambiguous, rejected_static, rejected_hot_pixel, rejected_low_snr, rejected_edge,
// rejected_extended, missing_frame — not usable (u, v then describe the strongest rejected
// candidate, if any).
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"

namespace rangecal {

namespace lamp_status {
inline constexpr const char* kOk = "ok";
inline constexpr const char* kOkSaturated = "ok_saturated";
inline constexpr const char* kOkByMotion = "ok_by_motion";
inline constexpr const char* kNoLamp = "no_lamp";
inline constexpr const char* kAmbiguous = "ambiguous";
inline constexpr const char* kStatic = "rejected_static";
inline constexpr const char* kHotPixel = "rejected_hot_pixel";
inline constexpr const char* kLowSnr = "rejected_low_snr";
inline constexpr const char* kEdge = "rejected_edge";
inline constexpr const char* kExtended = "rejected_extended";
inline constexpr const char* kMissingFrame = "missing_frame";
}  // namespace lamp_status

/// One row of detections.csv.
struct LampDetection {
  std::int64_t frame = 0;
  UtcTime utc;
  double u = NAN, v = NAN;  ///< sub-pixel centroid (px; docs/conventions.md pixel convention); NaN = none
  double peak = NAN;        ///< brightest pixel minus local background (DN)
  int area = 0;             ///< connected pixels above the growth threshold
  double snr = NAN;         ///< peak / frame noise σ
  std::string status = lamp_status::kNoLamp;

  /// True for the statuses whose position is the lamp's (ok, ok_saturated, ok_by_motion).
  bool usable() const { return status.rfind("ok", 0) == 0; }
};

/// The CSV text for `rows` (header included).
std::string format_detections_csv(const std::vector<LampDetection>& rows);
/// Writes detections.csv atomically.
void write_detections_csv(const std::string& path, const std::vector<LampDetection>& rows);
/// Reads detections.csv; throws rangecal::Error (input) naming file, line and field on a bad value
/// or an unknown status.
std::vector<LampDetection> read_detections_csv(const std::string& path);
/// As read_detections_csv from the file's text in memory (`path` is for messages).
std::vector<LampDetection> parse_detections_csv(const std::string& text, const std::string& path);
/// True when `status` is one of the statuses above.
bool is_known_lamp_status(const std::string& status);

}  // namespace rangecal
