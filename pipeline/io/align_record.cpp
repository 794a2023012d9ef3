#include "pipeline/io/align_record.hpp"

#include "config/error.hpp"
#include "config/json_view.hpp"
#include "pipeline/io/record_fields.hpp"

namespace rangecal {
namespace {

nlohmann::json camera_json(const AlignCameraRecord& c) {
  const AlignReport& r = c.report;
  nlohmann::json j;
  j["epochs"] = r.epochs;
  j["frames"] = r.frames;
  j["epochs_outside_frames"] = r.epochs_outside_frames;
  j["frames_picked"] = r.frames_picked;
  j["frames_aligned"] = r.frames_aligned;
  j["rejected_offset"] = r.rejected_offset;
  j["rejected_gap"] = r.rejected_gap;
  j["rejected_outside_track"] = r.rejected_outside_track;
  j["mean_dt_s"] = r.mean_dt_s;
  j["mean_abs_dt_s"] = r.mean_abs_dt_s;
  j["max_abs_dt_s"] = r.max_abs_dt_s;
  j["max_speed_mps"] = r.max_speed_mps;
  j["worst_position_error_m"] = r.worst_position_error_m;
  j["worst_position_error_frame"] = r.worst_position_error_frame;
  j["time_source"] = c.time_source;
  return j;
}

AlignCameraRecord parse_camera(const JsonView& v) {
  v.require_object("an object {epochs, frames, frames_aligned, ...}");
  AlignCameraRecord c;
  AlignReport& r = c.report;
  r.epochs = count_field(v, "epochs");
  r.frames = count_field(v, "frames");
  r.epochs_outside_frames = count_field(v, "epochs_outside_frames");
  r.frames_picked = count_field(v, "frames_picked");
  r.frames_aligned = count_field(v, "frames_aligned");
  r.rejected_offset = count_field(v, "rejected_offset");
  r.rejected_gap = count_field(v, "rejected_gap");
  r.rejected_outside_track = count_field(v, "rejected_outside_track");
  r.mean_dt_s = number_field(v, "mean_dt_s");
  r.mean_abs_dt_s = number_field(v, "mean_abs_dt_s");
  r.max_abs_dt_s = number_field(v, "max_abs_dt_s");
  r.max_speed_mps = number_field(v, "max_speed_mps");
  r.worst_position_error_m = number_field(v, "worst_position_error_m");
  if (v.has("worst_position_error_frame"))
    r.worst_position_error_frame = integer_field(v, "worst_position_error_frame");
  c.time_source = string_field(v, "time_source");
  return c;
}

}  // namespace

nlohmann::json align_record_json(const AlignRecord& r) {
  return by_camera_json(r.cameras, camera_json);
}

AlignRecord parse_align_record(const nlohmann::json& j, const std::string& path, const std::string& field) {
  return {parse_by_camera<AlignCameraRecord>(JsonView(j, path, field, ErrorKind::input), parse_camera)};
}

}  // namespace rangecal
