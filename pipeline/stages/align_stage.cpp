#include "pipeline/stages/align_stage.hpp"

#include "config/error.hpp"
#include "gnss/formats/lamp_track_csv.hpp"
#include "pipeline/io/align_record.hpp"
#include "pipeline/io/aligned_csv.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/mission/stage_options.hpp"
#include "pipeline/stages/stage_inputs.hpp"
#include "pipeline/steps/align_frames.hpp"

namespace rangecal {

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
    const FrameSource source = open_camera_frames(cfg, cam);
    std::vector<FrameStamp> stamps;
    stamps.reserve(source.size());
    for (const auto& e : source.entries()) stamps.push_back({e.frame, e.utc});
    if (!stamps.empty()) spans.push_back({cam.id, UtcSpan{stamps.front().utc, stamps.back().utc}});
    AlignOptions opt;
    opt.max_frame_offset_s = cfg.align.max_frame_offset_s;
    opt.max_gap_s = cfg.gnss.max_gap_s;
    opt.track_source = track_path;
    opt.frames_source = source.origin();
    results.push_back(align_frames(track, stamps, opt));
    const AlignResult& r = results.back();
    record.cameras[cam.id] = {r.report, source.time_source()};
    if (source.time_source() == FrameSource::kTimeSourceMrawHeader)
      log.warnings.push_back(
          cam.id + ": frame times come from the Photron header (camera clock to the second, " +
          "shifted by clock_utc_offset_h, plus frame number / record rate): a coarse source; " +
          "a timestamps CSV from the range timing is better");
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
