#include "pipeline/stages/camera_stages.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <unordered_map>

#include "config/error.hpp"
#include "gnss/track/hermite_interpolation.hpp"
#include "gnss/formats/lamp_track_csv.hpp"
#include "pipeline/steps/align_frames.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/stages/gnss_stage.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/io/progress_bar.hpp"
#include "pipeline/steps/timestamp_check.hpp"
#include "vision/detection/detections_csv.hpp"
#include "vision/frames/frame_source.hpp"
#include "vision/detection/lamp_detector.hpp"

namespace rangecal {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// A stage's input file written by an earlier stage: a clear message when that stage has not run.
void require_stage_file(const std::string& path, const char* stage) {
  if (!std::filesystem::exists(path))
    throw_input_error(
        path, 0, "",
        std::string("missing; run the ") + stage + " stage first (rangecal " + stage + " CONFIG)");
}

}  // namespace

StageLog run_align_stage(const MissionConfig& cfg) {
  const auto t0 = std::chrono::steady_clock::now();
  StageLog log;
  log.stage = "align";
  const std::string track_path = lamp_track_path(cfg);
  require_stage_file(track_path, "gnss");
  const LampTrack track = read_lamp_track_csv(track_path);
  if (cfg.cameras.empty()) throw_config_error(cfg.config_path, "cameras", "no cameras to align");
  std::size_t total = 0;
  for (const CameraConfig& cam : cfg.cameras) {
    const FrameSource source = FrameSource::from_config(cam.frames, cam.sensor);
    std::vector<FrameStamp> stamps;
    stamps.reserve(source.size());
    for (const auto& e : source.entries()) stamps.push_back({e.frame, e.utc});
    AlignOptions opt;
    opt.max_frame_offset_s = cfg.align.max_frame_offset_s;
    opt.max_gap_s = cfg.gnss.max_gap_s;
    opt.track_source = track_path;
    opt.frames_source = source.origin();
    const AlignResult r = align_frames(track, stamps, opt);
    write_aligned_csv(camera_output(cfg, cam.id, kAlignedCsv), r.aligned);
    log.counts[cam.id] = to_json(r.report);
    log.counts[cam.id]["time_source"] = source.time_source();
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
  if (total == 0)
    throw_input_error(track_path, 0, "", "no camera has a frame that aligns with the lamp track");
  log.wall_time_s = seconds_since(t0);
  return log;
}

StageLog run_detect_stage(const MissionConfig& cfg) {
  const auto t0 = std::chrono::steady_clock::now();
  StageLog log;
  log.stage = "detect";
  const LampDetectorOptions options = lamp_detector_options(cfg.detect);
  const std::string track_path = lamp_track_path(cfg);
  require_stage_file(track_path, "gnss");
  const HermiteTrack track(read_lamp_track_csv(track_path), cfg.gnss.max_gap_s, track_path);
  std::size_t total_pairs = 0;
  for (const CameraConfig& cam : cfg.cameras) {
    const std::string aligned_path = camera_output(cfg, cam.id, kAlignedCsv);
    require_stage_file(aligned_path, "align");
    const std::vector<AlignedFrame> aligned = read_aligned_csv(aligned_path);
    const FrameSource source = FrameSource::from_config(cam.frames, cam.sensor);
    std::unordered_map<std::int64_t, std::size_t> index_of_frame;
    for (std::size_t i = 0; i < source.size(); ++i) index_of_frame.emplace(source.entry(i).frame, i);
    std::vector<std::size_t> indices;
    indices.reserve(aligned.size());
    for (const AlignedFrame& a : aligned) {
      const auto it = index_of_frame.find(a.frame);
      if (it == index_of_frame.end())
        throw_input_error(aligned_path, 0, "frame",
                          "frame " + std::to_string(a.frame) + " is not in " + source.origin() +
                              " (aligned.csv is from another frame list; rerun the align stage)");
      indices.push_back(it->second);
    }
    std::vector<LampDetection> det;
    {
      ProgressBar bar("detect " + cam.id, indices.size());
      det = detect_lamp(source, indices, options, cfg.detect.threads, [&bar] { bar.tick(); });
    }
    write_detections_csv(camera_output(cfg, cam.id, kDetectionsCsv), det);

    std::vector<Correspondence> pairs;
    std::map<std::string, int> by_status;
    for (std::size_t i = 0; i < det.size(); ++i) {
      ++by_status[det[i].status];
      if (!det[i].usable()) continue;
      Correspondence c;
      c.utc = aligned[i].utc;
      c.enu = aligned[i].enu;
      c.sd_enu = aligned[i].sd_enu;
      c.vel_enu = aligned[i].vel_enu;
      c.uv = {det[i].u, det[i].v};
      pairs.push_back(c);
    }
    write_correspondences_csv(camera_output(cfg, cam.id, kCorrespondencesCsv), pairs);
    nlohmann::json counts;
    counts["time_source"] = source.time_source();
    counts["frames_examined"] = det.size();
    counts["by_status"] = by_status;
    counts["correspondences"] = pairs.size();
    // A whole-second or leap-second error in the frame stamps (issue 6): pairs that no pinhole
    // camera explains unless the track is shifted by δ.
    std::vector<std::pair<UtcTime, Eigen::Vector2d>> stamped;
    for (const Correspondence& c : pairs) stamped.emplace_back(c.utc, c.uv);
    const TimestampOffsetCheck tc = check_timestamp_offset(stamped, track);
    if (tc.n_points > 0)
      counts["timestamp_check"] = {{"best_offset_s", tc.best_offset_s},
                                   {"rms_at_zero_px", tc.rms_at_zero_px},
                                   {"rms_at_best_px", tc.rms_at_best_px}};
    if (tc.offset_detected) {
      char b[400];
      std::snprintf(
          b, sizeof b,
          "%s: frame time stamps look off by %+.0f s: the lamp pairs fit one pinhole camera with rms "
          "%.2f px when the track is taken %+.0f s from each stamp, against %.1f px as stamped — a "
          "%s; correct the time stamps (the calibration of this camera will be wrong)",
          cam.id.c_str(), -tc.best_offset_s, tc.rms_at_best_px, tc.best_offset_s, tc.rms_at_zero_px,
          std::abs(std::abs(tc.best_offset_s) - 18) <= 1 ? "GPST/UTC leap-second mix-up"
                                                         : "whole-second clock error");
      log.warnings.push_back(b);
    }
    log.counts[cam.id] = counts;
    total_pairs += pairs.size();
    if (pairs.empty())
      log.warnings.push_back(cam.id + ": the lamp was not found in any of its " + std::to_string(det.size()) +
                             " aligned frames (see " + camera_output(cfg, cam.id, kDetectionsCsv) + ")");
  }
  if (total_pairs == 0 && !cfg.cameras.empty())
    throw_input_error(cfg.output_dir, 0, "", "the lamp was found in no camera's frames");
  log.wall_time_s = seconds_since(t0);
  return log;
}

}  // namespace rangecal
