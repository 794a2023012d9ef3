#include "pipeline/io/align_record.hpp"

#include "config/error.hpp"
#include "config/json_view.hpp"
#include "pipeline/io/record_fields.hpp"

namespace rangecal {
namespace {

// The keys of AlignReport, in the order they are read.
const RecordField<AlignReport> kReportFields[] = {
    {"epochs", &AlignReport::epochs},
    {"frames", &AlignReport::frames},
    {"epochs_outside_frames", &AlignReport::epochs_outside_frames},
    {"frames_picked", &AlignReport::frames_picked},
    {"frames_aligned", &AlignReport::frames_aligned},
    {"rejected_offset", &AlignReport::rejected_offset},
    {"rejected_gap", &AlignReport::rejected_gap},
    {"rejected_outside_track", &AlignReport::rejected_outside_track},
    {"mean_dt_s", &AlignReport::mean_dt_s},
    {"mean_abs_dt_s", &AlignReport::mean_abs_dt_s},
    {"max_abs_dt_s", &AlignReport::max_abs_dt_s},
    {"max_speed_mps", &AlignReport::max_speed_mps},
    {"worst_position_error_m", &AlignReport::worst_position_error_m},
    {"worst_position_error_frame", &AlignReport::worst_position_error_frame},
};

const RecordField<ClockRecord> kClockFields[] = {
    {"offset_s", &ClockRecord::offset_s},
    {"offset_sd_s", &ClockRecord::offset_sd_s},
    {"rate_ppm", &ClockRecord::rate_ppm},
    {"rate_sd_ppm", &ClockRecord::rate_sd_ppm},
    {"mid_offset_sd_s", &ClockRecord::mid_offset_sd_s},
    {"span_s", &ClockRecord::span_s},
    {"rms_px", &ClockRecord::rms_px},
    {"points", &ClockRecord::points},
    {"blocks", &ClockRecord::blocks},
    {"variable_frame_rate", &ClockRecord::variable_frame_rate},
    {"worst_block_deviation_s", &ClockRecord::worst_block_deviation_s},
    {"search_best_score_px", &ClockRecord::search_best_score_px},
    {"search_other_score_px", &ClockRecord::search_other_score_px},
    {"search_other_offset_s", &ClockRecord::search_other_offset_s},
    {"track_sd_s", &ClockRecord::track_sd_s},
    {"wander_sd_s", &ClockRecord::wander_sd_s},
    {"readout_s", &ClockRecord::readout_s},
    {"readout_sd_s", &ClockRecord::readout_sd_s},
};

nlohmann::json align_camera_json(const AlignCameraRecord& c) {
  nlohmann::json j;
  write_fields(kReportFields, c.report, &j);
  j["time_source"] = c.time_source;
  if (c.clock) {
    nlohmann::json k;
    k["nominal_start_utc"] = c.clock->nominal_start_utc;
    write_fields(kClockFields, *c.clock, &k);
    j["clock"] = k;
  }
  return j;
}

AlignCameraRecord parse_align_camera(const JsonView& v) {
  v.require_object("an object {epochs, frames, frames_aligned, ...}");
  AlignCameraRecord c;
  read_fields(kReportFields, v, &c.report);
  c.time_source = string_field(v, "time_source");
  if (auto k = v.find("clock")) {
    k->require_object("an object {offset_s, offset_sd_s, rate_ppm, ...}");
    ClockRecord clock;
    clock.nominal_start_utc = string_field(*k, "nominal_start_utc");
    read_fields(kClockFields, *k, &clock);
    c.clock = clock;
  }
  return c;
}

}  // namespace

nlohmann::json align_record_json(const AlignRecord& r) {
  return by_camera_json(r.cameras, align_camera_json);
}

AlignRecord parse_align_record(const nlohmann::json& j, const std::string& path, const std::string& field) {
  return {parse_by_camera<AlignCameraRecord>(JsonView(j, path, field, ErrorKind::input), parse_align_camera)};
}

}  // namespace rangecal
