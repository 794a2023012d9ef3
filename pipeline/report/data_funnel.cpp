#include "pipeline/report/data_funnel.hpp"

#include <optional>

#include "pipeline/io/calibrate_record.hpp"

namespace rangecal {
namespace {

std::optional<long long> count_at(const nlohmann::json& j, const char* key) {
  if (!j.is_object() || !j.contains(key) || !j[key].is_number()) return std::nullopt;
  return j[key].get<long long>();
}

const nlohmann::json* counts_of(const nlohmann::json& stages, const char* stage) {
  if (!stages.is_object() || !stages.contains(stage) || !stages[stage].is_object() ||
      !stages[stage].contains("counts") || !stages[stage]["counts"].is_object())
    return nullptr;
  return &stages[stage]["counts"];
}

void add_drop(FunnelRow* row, const std::string& reason, std::optional<long long> n) {
  if (n && *n != 0) row->dropped.push_back({reason, *n});
}

}  // namespace

std::vector<FunnelRow> data_funnel(const nlohmann::json& stages, const std::vector<std::string>& camera_ids) {
  std::vector<FunnelRow> rows;
  if (const nlohmann::json* g = counts_of(stages, "gnss")) {
    const auto in = count_at(*g, "epochs_read"), kept = count_at(*g, "epochs_kept");
    if (in && kept) {
      FunnelRow r{"gnss", "", "epochs", *in, *kept, {}};
      if (g->contains("dropped_quality_by_q") && (*g)["dropped_quality_by_q"].is_object())
        for (const auto& [q, n] : (*g)["dropped_quality_by_q"].items())
          if (n.is_number()) add_drop(&r, "quality Q = " + q + " not accepted", n.get<long long>());
      add_drop(&r, "sd > gnss.max_sd_m", count_at(*g, "dropped_sd"));
      add_drop(&r, "no attitude", count_at(*g, "dropped_no_attitude"));
      rows.push_back(r);
    }
  }
  std::optional<CalibrateRecord> calibrate;
  if (const nlohmann::json* k = counts_of(stages, "calibrate"))
    calibrate = parse_calibrate_record(*k, "run.json", "stages.calibrate.counts");
  for (const std::string& id : camera_ids) {
    const nlohmann::json* a = counts_of(stages, "align");
    if (a && a->contains(id)) {
      const nlohmann::json& c = (*a)[id];
      const auto in = count_at(c, "frames"), picked = count_at(c, "frames_picked"),
                 kept = count_at(c, "frames_aligned");
      if (in && kept) {
        FunnelRow r{"align", id, "frames", *in, *kept, {}};
        if (picked) add_drop(&r, "no lamp-track epoch nearest", *in - *picked);
        add_drop(&r, "offset > align.max_frame_offset_s", count_at(c, "rejected_offset"));
        add_drop(&r, "in a track gap", count_at(c, "rejected_gap"));
        add_drop(&r, "outside the lamp track", count_at(c, "rejected_outside_track"));
        rows.push_back(r);
      }
    }
    const nlohmann::json* d = counts_of(stages, "detect");
    if (d && d->contains(id)) {
      const nlohmann::json& c = (*d)[id];
      const auto in = count_at(c, "frames_examined"), kept = count_at(c, "correspondences");
      if (in && kept) {
        FunnelRow r{"detect", id, "frames", *in, *kept, {}};
        if (c.contains("by_status") && c["by_status"].is_object())
          for (const auto& [status, n] : c["by_status"].items())
            if (status != "ok" && n.is_number()) add_drop(&r, "lamp " + status, n.get<long long>());
        rows.push_back(r);
      }
    }
    if (calibrate && calibrate->cameras.count(id) && calibrate->cameras.at(id).failed.empty()) {
      const CalibrateCameraRecord& c = calibrate->cameras.at(id);
      FunnelRow r{"calibrate", id, "observations", static_cast<long long>(c.pairs + c.control_poles),
                  c.n_used,    {}};
      add_drop(&r, "outlier", c.n_rejected);
      rows.push_back(r);
    }
  }
  if (const nlohmann::json* x = counts_of(stages, "intersect")) {
    const auto picked = count_at(*x, "poles_picked"), tri = count_at(*x, "poles_triangulated");
    if (picked && tri) {
      FunnelRow r{"intersect", "", "poles", *picked, *tri, {}};
      add_drop(&r, "seen by < 2 calibrated cameras or failed", *picked - *tri);
      rows.push_back(r);
    }
  }
  return rows;
}

}  // namespace rangecal
