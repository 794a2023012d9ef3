#include "pipeline/steps/lamp_track_computation.hpp"

#include <algorithm>
#include <cmath>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "gnss/formats/rtklib_pos_reader.hpp"
#include "gnss/geodesy/local_enu.hpp"
#include "gnss/track/antenna_epochs.hpp"
#include "gnss/track/lever_arm.hpp"

namespace rangecal {
namespace {

constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;

std::string mm(double m) {
  return format_number("%.1f", m * 1e3) + " mm";
}

// The attitude must cover some of the GNSS epochs: a log of another flight (or one whose boot
// time was mapped to UTC wrongly) would otherwise only show as every epoch dropped, or silently
// unused in the vertical form.
void check_attitude_overlaps(const AttitudeSeries& att, const std::vector<AntennaEpoch>& epochs,
                             const std::vector<PosFile>& pos_files) {
  if (att.samples.empty() || epochs.empty()) return;
  const UtcTime a0 = att.samples.front().utc, a1 = att.samples.back().utc;
  const UtcTime g0 = epochs.front().utc, g1 = epochs.back().utc;
  if (a0 <= g1 && g0 <= a1) return;
  std::string files;
  for (const PosFile& f : pos_files) files += (files.empty() ? "" : ", ") + f.path;
  throw_input_error(att.path, 0, "utc",
                    "the attitude " + format_iso8601_utc(a0, 3) + " … " + format_iso8601_utc(a1, 3) +
                        " does not overlap the GNSS epochs " + format_iso8601_utc(g0, 3) + " … " +
                        format_iso8601_utc(g1, 3) + " of " + files +
                        ": the attitude log is of another flight, or its time is wrong");
}

std::string thousands(std::size_t n) {
  std::string s = std::to_string(n);
  for (int i = static_cast<int>(s.size()) - 3; i > 0; i -= 3) s.insert(static_cast<std::size_t>(i), ",");
  return s;
}

// A filter that drops most of a flight is usually a processing or configuration problem (a base
// station too far or mis-set, an sd limit in the wrong unit), not bad luck: say which, and the key.
void warn_when_most_epochs_dropped(const EpochFilterCounts& c, const EpochFilterOptions& opt,
                                   std::vector<std::string>* warnings) {
  if (c.read == 0) return;
  if (2 * c.dropped_quality > c.read) {
    int worst_q = 0;
    std::size_t worst_n = 0;
    for (const auto& [q, n] : c.dropped_by_quality)
      if (n > worst_n) worst_q = q, worst_n = n;
    std::string accept;
    for (int q : opt.accept_quality) accept += (accept.empty() ? "" : ", ") + std::to_string(q);
    accept += ", " + std::to_string(worst_q);
    warnings->push_back(thousands(worst_n) + " of " + thousands(c.read) + " epochs are " +
                        rtklib_quality_name(worst_q) + " (Q=" + std::to_string(worst_q) +
                        ") and were dropped: accept them with gnss.accept_quality [" + accept +
                        "] or check the base station and the processing");
  }
  if (2 * c.dropped_sd > c.read)
    warnings->push_back(thousands(c.dropped_sd) + " of " + thousands(c.read) +
                        " epochs have an sd above gnss.max_sd_m = " + format_number("%g", opt.max_sd_m) +
                        " m and were dropped: check the solution or raise gnss.max_sd_m");
}

}  // namespace

LampTrackResult compute_lamp_track(const LampTrackInputs& in) {
  const bool full = in.lever.form == ResolvedLeverArm::Form::body_frd;
  if (full && !in.attitude)
    throw Error(ErrorKind::usage, "", 0, "lever_arm.body_frd_m",
                "a body-frame lever arm needs the attitude (set attitude.file, or use lever_arm.vertical_m)");
  LampTrackResult res;
  LampTrackReport& rep = res.report;
  const LocalEnu site(in.origin);
  const std::vector<AntennaEpoch> kept =
      filter_epochs(merge_antenna_epochs(in.pos_files, site), in.filter, &rep.filter);
  if (in.attitude) check_attitude_overlaps(*in.attitude, kept, in.pos_files);

  res.track.epochs.reserve(kept.size());
  double max_tilt_deg = 0;
  double lever_motion_ss = 0;
  std::size_t lever_motion_n = 0;
  for (const AntennaEpoch& a : kept) {
    std::optional<Attitude> att;
    if (in.attitude) att = interpolate_attitude(*in.attitude, a.utc, in.max_attitude_gap_s);
    LampEpoch e;
    e.utc = a.utc;
    e.quality = a.quality;
    // The lamp moves with the antenna; the lever's rotation rate (ω × lever, a few mm/s) is ignored.
    e.vel_enu = a.vel_enu;
    Eigen::Vector3d var = a.cov_enu.diagonal();
    if (full) {
      if (!att) {
        ++rep.dropped_no_attitude;
        continue;
      }
      e.enu = lamp_enu_full(a.enu, rotation_nb(*att), in.lever.body_frd_m);
      if (const auto rate =
              lever_motion_mps(*in.attitude, a.utc, in.lever.body_frd_m, in.max_attitude_gap_s)) {
        rep.lever_motion_max_mm_per_ms = std::max(rep.lever_motion_max_mm_per_ms, *rate);
        lever_motion_ss += *rate * *rate;
        ++lever_motion_n;
      }
    } else {
      e.enu = lamp_enu_vertical(a.enu, in.lever.vertical_m);
      var[2] += in.lever.vertical_sd_m * in.lever.vertical_sd_m;
      if (att) {
        const double err = vertical_form_error_m(rotation_nb(*att), in.lever.vertical_m);
        if (err > rep.vertical_form_max_error_m) {
          rep.vertical_form_max_error_m = err;
          // The body z axis tilts from the vertical by acos(cos roll · cos pitch).
          max_tilt_deg = std::acos(std::min(1.0, std::cos(att->roll_deg * kRadPerDeg) *
                                                     std::cos(att->pitch_deg * kRadPerDeg))) /
                         kRadPerDeg;
        }
        if (err > kVerticalFormWarnM) ++rep.vertical_form_epochs_over_5mm;
      }
    }
    e.sd_enu = var.cwiseMax(0.0).cwiseSqrt();
    e.cov_enu = a.cov_enu;
    e.cov_enu.diagonal() = var;
    res.track.epochs.push_back(e);
  }
  if (lever_motion_n > 0) rep.lever_motion_rms_mm_per_ms = std::sqrt(lever_motion_ss / lever_motion_n);
  rep.track_epochs = res.track.epochs.size();
  warn_when_most_epochs_dropped(rep.filter, in.filter, &rep.warnings);
  if (res.track.epochs.size() < kMinLampTrackEpochs) {
    const EpochFilterCounts& c = rep.filter;
    const std::string counts = std::to_string(c.read) + " read, " + std::to_string(c.dropped_quality) +
                               " dropped for Q, " + std::to_string(c.dropped_sd) + " for sd, " +
                               std::to_string(rep.dropped_no_attitude) + " outside the attitude coverage";
    if (res.track.epochs.empty())
      throw_input_error(in.pos_files.empty() ? "" : in.pos_files.front().path, 0, "",
                        "no epoch is left for the lamp track: " + counts +
                            " (check gnss.accept_quality and gnss.max_sd_m)");
    // The one epoch left: its file and line.
    const auto it = std::find_if(kept.begin(), kept.end(), [&](const AntennaEpoch& a) {
      return a.utc == res.track.epochs.front().utc;
    });
    const bool found = it != kept.end() && !in.pos_files.empty();
    const std::string path = found ? in.pos_files[static_cast<std::size_t>(it->file_index)].path
                                   : (in.pos_files.empty() ? "" : in.pos_files.front().path);
    throw_input_error(path, found ? it->line : 0, "epochs",
                      "only 1 epoch is left for the lamp track (" + counts +
                          "): the track places the lamp "
                          "between consecutive epochs and needs at least " +
                          std::to_string(kMinLampTrackEpochs) +
                          ", and a calibration the lamp at many places");
  }
  rep.track_start = res.track.epochs.front().utc;
  rep.track_end = res.track.epochs.back().utc;
  std::vector<UtcTime> times;
  times.reserve(res.track.epochs.size());
  for (const LampEpoch& e : res.track.epochs) times.push_back(e.utc);
  rep.gaps = find_gaps(times, in.filter.max_gap_s);

  if (in.lever.source == "total_station" && in.lever.sessions == 1)
    rep.warnings.push_back(
        "the total-station lever arm has a single session: its sd is unknown (taken as 0)");
  if (rep.dropped_no_attitude > 0)
    rep.warnings.push_back(std::to_string(rep.dropped_no_attitude) +
                           " GNSS epochs lie outside the attitude coverage and were dropped");
  if (rep.vertical_form_max_error_m > kVerticalFormWarnM) {
    rep.warnings.push_back("vertical lever-arm form is wrong by up to " + mm(rep.vertical_form_max_error_m) +
                           " (tilt up to " + format_number("%.1f", max_tilt_deg) + " deg; " +
                           std::to_string(rep.vertical_form_epochs_over_5mm) +
                           " epochs over 5 mm): configure lever_arm.body_frd_m to use the attitude");
  }
  return res;
}

}  // namespace rangecal
