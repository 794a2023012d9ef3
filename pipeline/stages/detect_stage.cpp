#include "pipeline/stages/detect_stage.hpp"

#include <algorithm>
#include <map>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "config/error.hpp"
#include "gnss/formats/lamp_track_csv.hpp"
#include "gnss/track/hermite_interpolation.hpp"
#include "pipeline/io/aligned_csv.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/io/detect_record.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/io/progress_bar.hpp"
#include "pipeline/mission/stage_options.hpp"
#include "pipeline/stages/stage_inputs.hpp"
#include "pipeline/steps/lamp_pairs.hpp"
#include "pipeline/steps/timestamp_check.hpp"
#include "vision/detection/detections_csv.hpp"
#include "vision/detection/lamp_detector.hpp"
#include "vision/frames/frame_source.hpp"

namespace rangecal {

namespace {

// "rejected_static 67, no_lamp 3": the reasons frames were not used, most frequent first.
std::string rejection_summary(const std::map<std::string, int>& by_status) {
  std::vector<std::pair<int, std::string>> rejected;
  for (const auto& [status, n] : by_status)
    if (status != "ok") rejected.emplace_back(n, status);
  std::sort(rejected.begin(), rejected.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::string s;
  for (const auto& [n, status] : rejected) s += (s.empty() ? "" : ", ") + status + " " + std::to_string(n);
  return s;
}

// A camera with an imported track: its labels at the aligned frames, as the detector's rows (status
// ok; peak, area and snr not known).
std::vector<LampDetection> track_detections(const CameraConfig& cam, const std::vector<AlignedFrame>& aligned,
                                            const std::string& aligned_path,
                                            std::map<std::int64_t, double>* sigma_by_utc) {
  const CameraTrackInput in = read_camera_track(cam);
  std::unordered_map<std::int64_t, std::size_t> index_of_frame;
  for (std::size_t i = 0; i < in.track.points.size(); ++i)
    index_of_frame.emplace(in.track.points[i].frame, i);
  std::vector<LampDetection> out;
  out.reserve(aligned.size());
  for (const AlignedFrame& a : aligned) {
    const auto it = index_of_frame.find(a.frame);
    if (it == index_of_frame.end())
      throw_input_error(aligned_path, 0, "frame",
                        "frame " + std::to_string(a.frame) + " is not labelled in " + cam.track->file +
                            " (aligned.csv is from another track; rerun the align stage)");
    LampDetection d;
    d.frame = a.frame;
    d.utc = a.utc;
    d.u = in.track.points[it->second].uv.x();
    d.v = in.track.points[it->second].uv.y();
    d.status = lamp_status::kOk;
    if (const auto& sigma = in.track.points[it->second].sigma_px) (*sigma_by_utc)[a.utc.ns] = *sigma;
    out.push_back(d);
  }
  return out;
}

}  // namespace

StageLog run_detect_stage(const MissionConfig& cfg) {
  StageLog log;
  log.stage = "detect";
  const LampDetectorOptions options = lamp_detector_options(cfg.detect);
  const std::string track_path = lamp_track_path(cfg);
  require_stage_output(track_path, "gnss");
  const HermiteTrack track(read_lamp_track_csv(track_path), cfg.gnss.max_gap_s, track_path);
  struct CameraDetections {
    std::vector<LampDetection> detections;
    std::vector<Correspondence> pairs;
  };
  std::vector<CameraDetections> out;
  std::size_t total_pairs = 0;
  DetectRecord record;
  for (const CameraConfig& cam : cfg.cameras) {
    const std::string aligned_path = camera_output(cfg, cam.id, kAlignedCsv);
    require_stage_output(aligned_path, "align");
    const std::vector<AlignedFrame> aligned = read_aligned_csv(aligned_path);
    DetectCameraRecord& counts = record.cameras[cam.id];
    CameraDetections cd;
    std::map<std::int64_t, double> sigma_by_utc;  // an imported track's own σ per label
    if (cam.track) {
      cd.detections = track_detections(cam, aligned, aligned_path, &sigma_by_utc);
      counts.time_source = "imported track";
    } else {
      const FrameSource source = open_camera_frames(cfg, cam);
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
      {
        ProgressBar bar("detect " + cam.id, indices.size());
        cd.detections = detect_lamp(source, indices, options, cfg.detect.threads, [&bar] { bar.tick(); });
      }
      counts.time_source = source.time_source();
    }
    cd.pairs = lamp_pairs(aligned, cd.detections);
    for (Correspondence& p : cd.pairs)
      if (const auto it = sigma_by_utc.find(p.utc.ns); it != sigma_by_utc.end())
        p.pixel_sigma_px = it->second;
    std::map<std::string, int> by_status;
    for (const LampDetection& d : cd.detections) ++by_status[d.status];
    counts.frames_examined = cd.detections.size();
    counts.by_status = by_status;
    counts.correspondences = cd.pairs.size();
    // A whole-second or leap-second error in the frame stamps: pairs that no pinhole camera
    // explains unless the track is shifted by δ (pipeline/steps/timestamp_check.hpp).
    std::vector<std::pair<UtcTime, Eigen::Vector2d>> stamped;
    for (const Correspondence& c : cd.pairs) stamped.emplace_back(c.utc, c.uv);
    const TimestampOffsetCheck tc = check_timestamp_offset(stamped, track);
    if (tc.n_points > 0) counts.timestamp_check = {tc.best_offset_s, tc.rms_at_zero_px, tc.rms_at_best_px};
    if (tc.offset_detected) log.warnings.push_back(cam.id + ": " + describe_timestamp_offset(tc));
    total_pairs += cd.pairs.size();
    if (cd.pairs.empty())
      log.warnings.push_back(cam.id + ": the lamp was not found in any of its " +
                             std::to_string(cd.detections.size()) + " aligned frames (see " +
                             camera_output(cfg, cam.id, kDetectionsCsv) + ")");
    else if (2 * cd.pairs.size() < cd.detections.size())
      log.warnings.push_back(cam.id + ": the lamp was found in only " + std::to_string(cd.pairs.size()) +
                             " of " + std::to_string(cd.detections.size()) + " aligned frames (" +
                             rejection_summary(by_status) +
                             "): the lamp is outside the image in most of them, or detect.min_snr is too "
                             "high (see " +
                             camera_output(cfg, cam.id, kDetectionsCsv) + ")");
    out.push_back(std::move(cd));
  }
  log.counts = detect_record_json(record);
  if (total_pairs == 0 && !cfg.cameras.empty())
    throw_input_error(cfg.output_dir, 0, "", "the lamp was found in no camera's frames");
  for (std::size_t c = 0; c < cfg.cameras.size(); ++c) {
    write_detections_csv(camera_output(cfg, cfg.cameras[c].id, kDetectionsCsv), out[c].detections);
    write_correspondences_csv(camera_output(cfg, cfg.cameras[c].id, kCorrespondencesCsv), out[c].pairs);
  }
  return log;
}

}  // namespace rangecal
