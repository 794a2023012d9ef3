#pragma once
// The lamp track (docs/gnss.md): antenna epochs of every .pos file in site ENU, merged and filtered
// (Q, sd; gnss/track/epoch_filter.hpp), GPST → UTC, the lever arm applied — with the attitude in
// the body-frame form (lamp = antenna + ENU(R_nb·lever), seed 002 eqs. 3–4), or straight down in
// the vertical form (seed 002 eq. 5) — and the σ of each epoch carried (plus the total station's
// σ in the vertical form). A pure function of parsed inputs; the gnss stage does the file I/O.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "gnss/formats/rtklib_pos_reader.hpp"
#include "gnss/geodesy/geodetic_origin.hpp"
#include "gnss/track/attitude.hpp"
#include "gnss/track/epoch_filter.hpp"
#include "gnss/track/lamp_track.hpp"

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

struct LampTrackInputs {
  std::vector<PosFile> pos_files;          ///< ≥ 1, each strictly increasing in time
  std::optional<AttitudeSeries> attitude;  ///< required for the body_frd form
  ResolvedLeverArm lever;
  GeodeticOrigin origin;  ///< site.origin
  EpochFilterOptions filter;
  /// Attitude samples farther apart than this are not interpolated across (s). Not fixed by any format;
  /// 1 s bridges any flight-controller log rate (≥ 5 Hz) with margin, not a dropout.
  double max_attitude_gap_s = 1.0;
};

/// The fewest epochs a lamp track can be made of: it places the lamp between consecutive epochs
/// (cubic Hermite, gnss/track/hermite_interpolation.hpp), so one epoch is no track — at most a frame
/// stamped at that very instant would pair with it, and a calibration from one lamp position fails
/// far downstream, naming the calibration instead of the `.pos` (docs/gnss.md "Filtering and gaps").
inline constexpr std::size_t kMinLampTrackEpochs = 2;

struct LampTrackReport {
  EpochFilterCounts filter;             ///< read / kept / dropped by Q and sd
  std::size_t dropped_no_attitude = 0;  ///< body_frd form: epochs outside the attitude coverage
  std::size_t track_epochs = 0;
  std::vector<TimeGap> gaps;  ///< in the final track, spacing > max_gap_s
  UtcTime track_start, track_end;
  /// Vertical form with attitude present: the largest error of the vertical form (m) over epochs
  /// with attitude, and how many epochs exceed 5 mm.
  double vertical_form_max_error_m = 0;
  std::size_t vertical_form_epochs_over_5mm = 0;
  /// Body-frame form: how fast the lever arm turns with the UAV, |d/dt (R_nb·lever)| — the lamp's
  /// displacement per ms of attitude time error (mm/ms, = m/s), largest and rms over the track's
  /// epochs (docs/gnss.md "Receiver lag"); 0 in the vertical form.
  double lever_motion_max_mm_per_ms = 0;
  double lever_motion_rms_mm_per_ms = 0;
  std::vector<std::string> warnings;
};

struct LampTrackResult {
  LampTrack track;
  LampTrackReport report;
};

/// Threshold of the vertical-form warning: more than 5 mm of lamp position error (half the PPK
/// noise of one epoch) from ignoring the attitude is worth the user's attention.
constexpr double kVerticalFormWarnM = 0.005;

/// The lamp track from parsed inputs. Throws rangecal::Error: usage when the body_frd form has no attitude;
/// input for overlapping .pos files, when no epoch survives filtering, or when the attitude's time span does
/// not overlap the filtered GNSS epochs' (the message names both files and both spans).
LampTrackResult compute_lamp_track(const LampTrackInputs& in);

}  // namespace rangecal
