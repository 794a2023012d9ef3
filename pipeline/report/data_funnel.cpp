#include "pipeline/report/data_funnel.hpp"

#include <optional>

#include "pipeline/io/align_record.hpp"
#include "pipeline/io/calibrate_record.hpp"
#include "pipeline/io/detect_record.hpp"
#include "pipeline/io/gnss_record.hpp"
#include "pipeline/io/intersect_record.hpp"

namespace rangecal {
namespace {

// A stage's counts; none when the stage did not run or recorded none (it failed).
const nlohmann::json* counts_of(const nlohmann::json& stages, const char* stage) {
  if (!stages.is_object() || !stages.contains(stage) || !stages[stage].is_object() ||
      !stages[stage].contains("counts") || !stages[stage]["counts"].is_object() ||
      stages[stage]["counts"].empty())
    return nullptr;
  return &stages[stage]["counts"];
}

// The record of a stage's counts, read by `parse` (pipeline/io/<stage>_record.hpp).
template <typename Record>
std::optional<Record> record_of(const nlohmann::json& stages, const char* stage,
                                Record (*parse)(const nlohmann::json&, const std::string&,
                                                const std::string&)) {
  const nlohmann::json* counts = counts_of(stages, stage);
  if (!counts) return std::nullopt;
  return parse(*counts, "run.json", std::string("stages.") + stage + ".counts");
}

void add_drop(FunnelRow* row, const std::string& reason, long long n) {
  if (n != 0) row->dropped.push_back({reason, n});
}

long long ll(std::size_t n) {
  return static_cast<long long>(n);
}

FunnelRow gnss_row(const GnssRecord& g) {
  FunnelRow r{"gnss", "", "epochs", ll(g.epochs_read), ll(g.epochs_kept), {}};
  for (const auto& [q, n] : g.dropped_quality_by_q)
    add_drop(&r, "quality Q = " + std::to_string(q) + " not accepted", ll(n));
  add_drop(&r, "sd > gnss.max_sd_m", ll(g.dropped_sd));
  add_drop(&r, "no attitude", ll(g.dropped_no_attitude));
  return r;
}

FunnelRow align_row(const std::string& id, const AlignReport& c) {
  FunnelRow r{"align", id, "frames", ll(c.frames), ll(c.frames_aligned), {}};
  add_drop(&r, "no lamp-track epoch nearest", ll(c.frames) - ll(c.frames_picked));
  add_drop(&r, "offset > align.max_frame_offset_s", ll(c.rejected_offset));
  add_drop(&r, "in a track gap", ll(c.rejected_gap));
  add_drop(&r, "outside the lamp track", ll(c.rejected_outside_track));
  return r;
}

FunnelRow detect_row(const std::string& id, const DetectCameraRecord& c) {
  FunnelRow r{"detect", id, "frames", ll(c.frames_examined), ll(c.correspondences), {}};
  for (const auto& [status, n] : c.by_status)
    if (status != "ok") add_drop(&r, "lamp " + status, n);
  return r;
}

}  // namespace

std::vector<FunnelRow> data_funnel(const nlohmann::json& stages, const std::vector<std::string>& camera_ids) {
  std::vector<FunnelRow> rows;
  if (const auto g = record_of(stages, "gnss", parse_gnss_record)) rows.push_back(gnss_row(*g));
  const auto calibrate = record_of(stages, "calibrate", parse_calibrate_record);
  const auto align = record_of(stages, "align", parse_align_record);
  const auto detect = record_of(stages, "detect", parse_detect_record);
  for (const std::string& id : camera_ids) {
    if (align && align->cameras.count(id)) rows.push_back(align_row(id, align->cameras.at(id).report));
    if (detect && detect->cameras.count(id)) rows.push_back(detect_row(id, detect->cameras.at(id)));
    if (calibrate && calibrate->cameras.count(id) && calibrate->cameras.at(id).failed.empty()) {
      const CalibrateCameraRecord& c = calibrate->cameras.at(id);
      FunnelRow r{"calibrate", id, "observations", static_cast<long long>(c.pairs + c.control_poles),
                  c.n_used,    {}};
      add_drop(&r, "outlier", c.n_rejected);
      rows.push_back(r);
    }
  }
  const auto x = record_of(stages, "intersect", parse_intersect_record);
  if (x && x->skipped.empty()) {
    FunnelRow r{"intersect", "", "poles", ll(x->poles_picked), ll(x->poles_triangulated), {}};
    add_drop(&r, "seen by < 2 calibrated cameras or failed", ll(x->poles_picked) - ll(x->poles_triangulated));
    rows.push_back(r);
  }
  return rows;
}

}  // namespace rangecal
