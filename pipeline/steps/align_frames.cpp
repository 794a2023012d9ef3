#include "pipeline/steps/align_frames.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "gnss/track/hermite_interpolation.hpp"

namespace rangecal {

const char* to_string(FrameRejection r) {
  switch (r) {
    case FrameRejection::offset_exceeded:
      return "offset_exceeded";
    case FrameRejection::in_gap:
      return "in_gap";
    case FrameRejection::outside_track:
      return "outside_track";
  }
  return "unknown";
}

namespace {

std::string frame_label(std::size_t i, const FrameStamp& f) {
  return "frame " + std::to_string(f.frame) + " (item " + std::to_string(i + 1) + ", " +
         format_iso8601_utc(f.utc) + ")";
}

void validate_frames(const std::vector<FrameStamp>& frames, const std::string& source) {
  if (frames.empty()) throw_input_error(source, 0, "frame", "the camera has no frames to align");
  for (std::size_t i = 1; i < frames.size(); ++i) {
    if (!(frames[i].utc > frames[i - 1].utc)) {
      throw_input_error(source, 0, "utc",
                        frame_label(i, frames[i]) + " is not after " + frame_label(i - 1, frames[i - 1]) +
                            ": frame times must be strictly increasing");
    }
    if (!(frames[i].frame > frames[i - 1].frame)) {
      throw_input_error(source, 0, "frame",
                        frame_label(i, frames[i]) + " does not follow " + frame_label(i - 1, frames[i - 1]) +
                            ": frame indices must be strictly increasing");
    }
  }
}

constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

/// Steps 1–2's result: per frame, the epoch that picked it (kNone: none) and frame − epoch (ns).
struct FramePicks {
  std::vector<std::size_t> by;
  std::vector<std::int64_t> dt_ns;
};

/// Steps 1–2: each epoch in the window picks a frame; each frame keeps its nearest picking epoch.
FramePicks pick_frames(const HermiteTrack& ht, const std::vector<FrameStamp>& frames, std::int64_t max_off_ns,
                       AlignReport* rep) {
  const std::int64_t window_lo = frames.front().utc.ns - max_off_ns;
  const std::int64_t window_hi = frames.back().utc.ns + max_off_ns;
  // A frame is usable for an epoch when it is close enough and the track is defined at its time.
  auto usable = [&](std::size_t j, std::int64_t epoch_ns) {
    return std::llabs(frames[j].utc.ns - epoch_ns) <= max_off_ns &&
           ht.sample(frames[j].utc).status == TrackSampleStatus::ok;
  };
  FramePicks picks{std::vector<std::size_t>(frames.size(), kNone),
                   std::vector<std::int64_t>(frames.size(), 0)};
  std::size_t j = 0;  // first frame with utc ≥ epoch (monotonic over epochs)
  for (std::size_t i = 0; i < ht.size(); ++i) {
    const std::int64_t te = ht.epoch_time(i).ns;
    if (te < window_lo || te > window_hi) {
      ++rep->epochs_outside_frames;
      continue;
    }
    while (j < frames.size() && frames[j].utc.ns < te) ++j;
    std::size_t nearest, other = kNone;
    if (j == 0) {
      nearest = 0;
    } else if (j == frames.size()) {
      nearest = j - 1;
    } else {
      const std::int64_t d_before = te - frames[j - 1].utc.ns, d_after = frames[j].utc.ns - te;
      nearest = d_after < d_before ? j : j - 1;
      other = d_after < d_before ? j - 1 : j;
    }
    std::size_t pick = nearest;
    if (other != kNone && !usable(nearest, te) && usable(other, te)) pick = other;
    const std::int64_t dt = frames[pick].utc.ns - te;
    if (picks.by[pick] == kNone || std::llabs(dt) < std::llabs(picks.dt_ns[pick])) {
      picks.by[pick] = i;
      picks.dt_ns[pick] = dt;
    }
  }
  return picks;
}

/// Step 3 for one picked frame: its track sample when it is kept; otherwise its rejection, with
/// the reason and the numbers, goes into `res` (and its count into the report) and nothing is
/// returned.
std::optional<TrackSample> keep_or_reject(const HermiteTrack& ht, const FrameStamp& f, std::int64_t dt_ns,
                                          std::int64_t max_off_ns, const AlignOptions& opt,
                                          AlignResult* res) {
  AlignReport& rep = res->report;
  const double dt_s = static_cast<double>(dt_ns) * 1e-9;
  RejectedFrame rej{f.frame, f.utc, dt_s, FrameRejection::offset_exceeded, ""};
  if (std::llabs(dt_ns) > max_off_ns) {
    rej.detail = "nearest lamp-track epoch is " + format_number("%.6f", std::fabs(dt_s)) +
                 " s away (max_frame_offset_s " + format_number("%g", opt.max_frame_offset_s) + ")";
    ++rep.rejected_offset;
    res->rejected.push_back(std::move(rej));
    return std::nullopt;
  }
  const TrackSample s = ht.sample(f.utc);
  if (s.status == TrackSampleStatus::in_gap) {
    rej.reason = FrameRejection::in_gap;
    rej.detail = "frame lies in a " + format_number("%.3f", s.interval_s) +
                 " s gap of the lamp track between " + format_iso8601_utc(ht.epoch_time(s.segment)) +
                 " and " + format_iso8601_utc(ht.epoch_time(s.segment + 1)) + " (max_gap_s " +
                 format_number("%g", opt.max_gap_s) + "): not interpolated across a gap";
    ++rep.rejected_gap;
    res->rejected.push_back(std::move(rej));
    return std::nullopt;
  }
  if (s.status != TrackSampleStatus::ok) {
    rej.reason = FrameRejection::outside_track;
    rej.detail = std::string("frame lies ") +
                 (s.status == TrackSampleStatus::before_track ? "before the first" : "after the last") +
                 " lamp-track epoch: not extrapolated";
    ++rep.rejected_outside_track;
    res->rejected.push_back(std::move(rej));
    return std::nullopt;
  }
  return s;
}

/// Sums over the kept frames for step 4's means.
struct DtSums {
  double dt = 0, abs_dt = 0;
};

/// Step 4 for one kept frame: the aligned frame, and its Δt, speed and position error in the report.
void keep_frame(const FrameStamp& f, const TrackSample& s, double dt_s, AlignResult* res, DtSums* sums) {
  AlignReport& rep = res->report;
  res->aligned.push_back(AlignedFrame{f.frame, f.utc, s.enu, s.sd_enu, dt_s, s.vel_enu});
  const double speed = s.vel_enu.norm(), err = speed * std::fabs(dt_s);
  sums->dt += dt_s;
  sums->abs_dt += std::fabs(dt_s);
  rep.max_abs_dt_s = std::max(rep.max_abs_dt_s, std::fabs(dt_s));
  rep.max_speed_mps = std::max(rep.max_speed_mps, speed);
  if (rep.worst_position_error_frame < 0 || err > rep.worst_position_error_m) {
    rep.worst_position_error_m = err;
    rep.worst_position_error_frame = f.frame;
  }
}

}  // namespace

AlignResult align_frames(const LampTrack& track, const std::vector<FrameStamp>& frames,
                         const AlignOptions& opt) {
  if (!(std::isfinite(opt.max_frame_offset_s) && opt.max_frame_offset_s > 0)) {
    throw_config_error("", "align.max_frame_offset_s",
                       "must be a positive number of seconds, got " + std::to_string(opt.max_frame_offset_s));
  }
  const HermiteTrack ht(track, opt.max_gap_s, opt.track_source);
  validate_frames(frames, opt.frames_source);

  AlignResult res;
  AlignReport& rep = res.report;
  rep.epochs = ht.size();
  rep.frames = frames.size();
  const auto max_off_ns = static_cast<std::int64_t>(std::llround(opt.max_frame_offset_s * 1e9));
  const FramePicks picks = pick_frames(ht, frames, max_off_ns, &rep);

  // Step 3–4: keep or reject every picked frame, in frame order.
  DtSums sums;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    if (picks.by[k] == kNone) continue;
    ++rep.frames_picked;
    const std::optional<TrackSample> s = keep_or_reject(ht, frames[k], picks.dt_ns[k], max_off_ns, opt, &res);
    if (s) keep_frame(frames[k], *s, static_cast<double>(picks.dt_ns[k]) * 1e-9, &res, &sums);
  }
  rep.frames_aligned = res.aligned.size();
  if (rep.frames_aligned > 0) {
    rep.mean_dt_s = sums.dt / static_cast<double>(rep.frames_aligned);
    rep.mean_abs_dt_s = sums.abs_dt / static_cast<double>(rep.frames_aligned);
  }
  return res;
}

std::string explain_no_alignment(const UtcSpan& track, const std::vector<CameraFrameSpan>& cameras,
                                 double max_frame_offset_s) {
  std::string s =
      "no camera has a frame that aligns with the lamp track; lamp track " + format_utc_span(track);
  for (const CameraFrameSpan& c : cameras) {
    const std::string name = "camera " + c.camera_id + " frames";
    const SpanComparison cmp = compare_spans(track, c.frames);
    s += "; " + name + " " + format_utc_span(c.frames) + ": " +
         describe_span_comparison(cmp, name, "the lamp track");
    if (cmp.relation == SpanRelation::overlap)
      s += ", but every frame lies in a track gap or farther than max_frame_offset_s " +
           format_number("%g", max_frame_offset_s) + " s from every lamp-track epoch";
  }
  return s;
}

}  // namespace rangecal
