#include "pipeline/stages/align_stage.hpp"

#include "config/error.hpp"
#include "gnss/formats/lamp_track_csv.hpp"
#include "pipeline/io/align_record.hpp"
#include "pipeline/io/aligned_csv.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/mission/stage_options.hpp"
#include "pipeline/stages/stage_inputs.hpp"
#include "pipeline/steps/align_frames.hpp"
#include "pipeline/steps/camera_clock.hpp"
#include "vision/frames/frame_formats.hpp"

#include <fmt/format.h>

namespace rangecal {

namespace {

// One camera's frames to align: their stamps, where they came from, and the estimated clock of a
// camera without time code.
struct CameraStamps {
  std::vector<FrameStamp> stamps;
  std::string origin;  ///< the file that named them, for messages
  std::string time_source;
  std::optional<ClockRecord> clock;
  std::vector<std::string> warnings;
};

ClockRecord clock_record(const CameraClock& c) {
  ClockRecord r;
  r.nominal_start_utc = format_iso8601_utc(c.nominal_start);
  r.offset_s = c.offset_s;
  r.offset_sd_s = c.offset_sd_s;
  r.rate_ppm = 1e6 * c.rate;
  r.rate_sd_ppm = 1e6 * c.rate_sd;
  r.mid_offset_sd_s = c.mid_offset_sd_s;
  r.span_s = c.span_s;
  r.rms_px = c.rms_px;
  r.points = c.points;
  r.blocks = c.blocks.size();
  r.variable_frame_rate = c.variable_frame_rate;
  r.worst_block_deviation_s = c.worst_block_deviation_s;
  r.search_best_score_px = c.search_best_score_px;
  r.search_other_score_px = c.search_other_score_px;
  r.search_other_offset_s = c.search_other_offset_s;
  r.track_sd_s = c.track_sd_s;
  r.wander_sd_s = c.wander_sd_s;
  r.readout_s = c.readout_s;
  r.readout_sd_s = c.readout_sd_s;
  return r;
}

// A camera with an imported track: its labelled frames at the config's times, or at the clock
// estimated from the data (pipeline/steps/camera_clock.hpp).
CameraStamps track_stamps(const MissionConfig& cfg, const CameraConfig& cam, const LampTrack& lamp,
                          const std::string& track_path) {
  const CameraTrackInput in = read_camera_track(cam);
  CameraStamps out;
  out.origin = cam.track->file;
  out.time_source = in.time_source;
  std::vector<UtcTime> times = in.times;
  if (!in.track.outside_image_lines.empty())
    out.warnings.push_back(
        fmt::format("{}: {} labels of {} lie outside the {}x{} image and are not used (first at line {})",
                    cam.id, in.track.outside_image_lines.size(), cam.track->file, cam.sensor.width_px,
                    cam.sensor.height_px, in.track.outside_image_lines.front()));
  if (cam.track->estimate_clock) {
    const HermiteTrack hermite(lamp, cfg.gnss.max_gap_s, track_path);
    std::vector<ClockObservation> labels(in.track.points.size());
    for (std::size_t i = 0; i < labels.size(); ++i)
      labels[i] = {in.track.points[i].frame, in.times[i], in.track.points[i].uv};
    ClockSearchOptions options;
    options.search_s = cam.track->clock_search_s;
    options.pixel_sigma_px = cam.pixel_sigma.track_px;
    options.readout_s = cam.track->readout_s;
    options.estimate_readout = cam.track->estimate_readout;
    const CameraClock clock =
        estimate_camera_clock(hermite, labels, sensor_geometry(cam.sensor), options, cam.track->file);
    for (std::size_t i = 0; i < times.size(); ++i)
      times[i] = clock.label_time(times[i], in.track.points[i].uv.y());
    out.clock = clock_record(clock);
    out.time_source += " + estimated clock";
    if (clock.variable_frame_rate)
      out.warnings.push_back(fmt::format(
          "{}: variable frame rate: a {:.0f}-s block of frames keeps its own clock {:.1f} ms off the "
          "camera's "
          "offset and rate; frame times carry errors of that size (docs/alignment.md \"Cameras without time "
          "code\")",
          cam.id, ClockSearchOptions{}.block_s, 1e3 * clock.worst_block_deviation_s));
  } else if (cam.track->readout_s != 0) {
    // A rolling shutter on a camera with time code: each label at its row's instant.
    CameraClock readout;
    readout.nominal_start = times.front();
    readout.readout_s = cam.track->readout_s;
    readout.image_height_px = cam.sensor.height_px;
    for (std::size_t i = 0; i < times.size(); ++i)
      times[i] = readout.label_time(times[i], in.track.points[i].uv.y());
  }
  for (std::size_t i = 0; i < times.size(); ++i) out.stamps.push_back({in.track.points[i].frame, times[i]});
  return out;
}

CameraStamps frame_stamps(const MissionConfig& cfg, const CameraConfig& cam) {
  const FrameSource source = open_camera_frames(cfg, cam);
  CameraStamps out;
  out.stamps.reserve(source.size());
  for (const auto& e : source.entries()) out.stamps.push_back({e.frame, e.utc});
  out.origin = source.origin();
  out.time_source = source.time_source();
  if (source.time_source() == frame_format(".mraw").own_time_source)
    out.warnings.push_back(
        cam.id + ": frame times come from the Photron header (camera clock to the second, " +
        "shifted by clock_utc_offset_h, plus frame number / record rate): a coarse source; " +
        "a timestamps CSV from the range timing is better");
  return out;
}

}  // namespace

StageLog run_align_stage(const MissionConfig& cfg) {
  StageLog log;
  log.stage = "align";
  const std::string track_path = lamp_track_path(cfg);
  require_stage_output(track_path, "gnss");
  const LampTrack track = read_lamp_track_csv(track_path);
  if (cfg.cameras.empty()) throw_config_error(cfg.config_path, "cameras", "no cameras to align");
  std::size_t total = 0;
  std::vector<AlignResult> results;
  std::vector<CameraFrameSpan> spans;
  AlignRecord record;
  for (const CameraConfig& cam : cfg.cameras) {
    CameraStamps in = cam.track ? track_stamps(cfg, cam, track, track_path) : frame_stamps(cfg, cam);
    const std::vector<FrameStamp>& stamps = in.stamps;
    if (!stamps.empty()) spans.push_back({cam.id, UtcSpan{stamps.front().utc, stamps.back().utc}});
    AlignOptions opt;
    opt.max_frame_offset_s = cfg.align.max_frame_offset_s;
    opt.max_gap_s = cfg.gnss.max_gap_s;
    opt.track_source = track_path;
    opt.frames_source = in.origin;
    results.push_back(align_frames(track, stamps, opt));
    const AlignResult& r = results.back();
    record.cameras[cam.id] = {r.report, in.time_source, in.clock};
    for (std::string& w : in.warnings) log.warnings.push_back(std::move(w));
    total += r.aligned.size();
    if (r.aligned.empty())
      log.warnings.push_back(
          cam.id + ": no frame lies within " + std::to_string(cfg.align.max_frame_offset_s) +
          " s of a usable lamp-track epoch (check the frame time stamps and the track span)");
  }
  log.counts = align_record_json(record);
  if (total == 0)
    throw_input_error(track_path, 0, "",
                      explain_no_alignment(UtcSpan{track.epochs.front().utc, track.epochs.back().utc}, spans,
                                           cfg.align.max_frame_offset_s));
  for (std::size_t c = 0; c < cfg.cameras.size(); ++c)
    write_aligned_csv(camera_output(cfg, cfg.cameras[c].id, kAlignedCsv), results[c].aligned);
  return log;
}

}  // namespace rangecal
