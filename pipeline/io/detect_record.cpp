#include "pipeline/io/detect_record.hpp"

#include "config/error.hpp"
#include "config/json_view.hpp"
#include "pipeline/io/record_fields.hpp"

namespace rangecal {
namespace {

nlohmann::json camera_json(const DetectCameraRecord& c) {
  nlohmann::json j;
  j["time_source"] = c.time_source;
  j["frames_examined"] = c.frames_examined;
  j["by_status"] = c.by_status;
  j["correspondences"] = c.correspondences;
  if (c.timestamp_check)
    j["timestamp_check"] = {{"best_offset_s", c.timestamp_check->best_offset_s},
                            {"rms_at_zero_px", c.timestamp_check->rms_at_zero_px},
                            {"rms_at_best_px", c.timestamp_check->rms_at_best_px}};
  return j;
}

DetectCameraRecord parse_camera(const JsonView& v) {
  v.require_object("an object {time_source, frames_examined, by_status, correspondences}");
  DetectCameraRecord c;
  c.time_source = string_field(v, "time_source");
  c.frames_examined = count_field(v, "frames_examined");
  for (const auto& [status, n] : counts_field(v, "by_status")) c.by_status[status] = static_cast<int>(n);
  c.correspondences = count_field(v, "correspondences");
  if (const auto t = object_field(v, "timestamp_check", "an object {best_offset_s, rms_at_zero_px, ...}")) {
    TimestampCheckRecord& tc = c.timestamp_check.emplace();
    tc.best_offset_s = number_field(*t, "best_offset_s");
    tc.rms_at_zero_px = number_field(*t, "rms_at_zero_px", tc.rms_at_zero_px);
    tc.rms_at_best_px = number_field(*t, "rms_at_best_px", tc.rms_at_best_px);
  }
  return c;
}

}  // namespace

nlohmann::json detect_record_json(const DetectRecord& r) {
  return by_camera_json(r.cameras, camera_json);
}

DetectRecord parse_detect_record(const nlohmann::json& j, const std::string& path, const std::string& field) {
  return {parse_by_camera<DetectCameraRecord>(JsonView(j, path, field, ErrorKind::input), parse_camera)};
}

}  // namespace rangecal
