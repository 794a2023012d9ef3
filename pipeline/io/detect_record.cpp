#include "pipeline/io/detect_record.hpp"

#include "config/error.hpp"
#include "config/json_view.hpp"
#include "pipeline/io/record_fields.hpp"

namespace rangecal {
namespace {

// The keys of a camera's line, in the order they are read: by_status stands between the two parts.
const RecordField<DetectCameraRecord> kFramesFields[] = {
    {"time_source", &DetectCameraRecord::time_source},
    {"frames_examined", &DetectCameraRecord::frames_examined},
};
const RecordField<DetectCameraRecord> kPairsFields[] = {
    {"correspondences", &DetectCameraRecord::correspondences},
};
const RecordField<TimestampCheckRecord> kTimestampCheckFields[] = {
    {"best_offset_s", &TimestampCheckRecord::best_offset_s},
    {"rms_at_zero_px", &TimestampCheckRecord::rms_at_zero_px},
    {"rms_at_best_px", &TimestampCheckRecord::rms_at_best_px},
};

nlohmann::json detect_camera_json(const DetectCameraRecord& c) {
  nlohmann::json j;
  write_fields(kFramesFields, c, &j);
  j["by_status"] = c.by_status;
  write_fields(kPairsFields, c, &j);
  if (c.timestamp_check) write_fields(kTimestampCheckFields, *c.timestamp_check, &j["timestamp_check"]);
  return j;
}

DetectCameraRecord parse_detect_camera(const JsonView& v) {
  v.require_object("an object {time_source, frames_examined, by_status, correspondences}");
  DetectCameraRecord c;
  read_fields(kFramesFields, v, &c);
  for (const auto& [status, n] : counts_field(v, "by_status")) c.by_status[status] = static_cast<int>(n);
  read_fields(kPairsFields, v, &c);
  if (const auto t = object_field(v, "timestamp_check", "an object {best_offset_s, rms_at_zero_px, ...}"))
    read_fields(kTimestampCheckFields, *t, &c.timestamp_check.emplace());
  return c;
}

}  // namespace

nlohmann::json detect_record_json(const DetectRecord& r) {
  return by_camera_json(r.cameras, detect_camera_json);
}

DetectRecord parse_detect_record(const nlohmann::json& j, const std::string& path, const std::string& field) {
  return {
      parse_by_camera<DetectCameraRecord>(JsonView(j, path, field, ErrorKind::input), parse_detect_camera)};
}

}  // namespace rangecal
