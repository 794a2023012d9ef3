#include "pipeline/analysis/target_path_table.hpp"

#include <algorithm>
#include <cmath>

#include "config/number_format.hpp"
#include "optim/estimation/nearest_rank_quantile.hpp"

namespace rangecal {
namespace {

double rank_quantile(const std::vector<double>& v, double q) {
  return nearest_rank_quantile(v, q, std::nan(""));
}

std::string path_cm(double m) {
  return std::isfinite(m) ? format_number("%.2f", 100 * m) : "-";
}

std::string path_cameras(const std::vector<std::string>& ids, const std::vector<std::size_t>& which) {
  std::string s;
  for (const std::size_t c : which)
    s += (s.empty() ? "" : "+") + (c < ids.size() ? ids[c] : std::to_string(c));
  return s;
}

}  // namespace

std::string format_target_path_table(const std::vector<TargetPathCandidate>& candidates,
                                     const std::string& path_file, const std::vector<std::string>& free,
                                     const TargetPathOptions& options) {
  std::string free_list;
  for (const std::string& f : free) free_list += (free_list.empty() ? "" : ",") + f;
  std::string s = "\nTarget path " + path_file + ": labels " + format_number("%g", options.label_sigma_px) +
                  " px, timing " + format_number("%g", options.timing_sigma_s * 1e3) + " ms, " +
                  format_number("%g", options.rate_hz) +
                  " instants/s; the cameras calibrated together on each candidate's routes (the network's "
                  "Cramér–Rao bound, free " +
                  free_list + "). σ = √trace, cm:\n";
  s +=
      fmt::format("{:<24} {:>8}  {:>5}  {:>8}  {:>7}  {:<17}  {:>6}  {:>6}  {:>6}\n", "candidate", "instants",
                  "seen", "σ median", "σ 95 %", "σ worst (t s)", "labels", "timing", "calibration (medians)");
  for (const TargetPathCandidate& c : candidates) {
    std::vector<double> sigma, labels, timing, calibration;
    const PlannedTargetInstant* worst = nullptr;
    for (const PlannedTargetInstant& i : c.plan.instants) {
      sigma.push_back(i.sigma_m), labels.push_back(i.labels_m), timing.push_back(i.timing_m),
          calibration.push_back(i.calibration_m);
      if (!worst || i.sigma_m > worst->sigma_m) worst = &i;
    }
    const std::string worst_cell =
        worst ? path_cm(worst->sigma_m) + " (" + format_number("%.1f", worst->t_s) + ")" : "-";
    s += fmt::format("{:<24} {:>8}  {:>5}  {:>8}  {:>7}  {:<17}  {:>6}  {:>6}  {:>6}\n", c.name, c.plan.tried,
                     c.plan.instants.size(), path_cm(rank_quantile(sigma, 0.5)),
                     path_cm(rank_quantile(sigma, 0.95)), worst_cell, path_cm(rank_quantile(labels, 0.5)),
                     path_cm(rank_quantile(timing, 0.5)), path_cm(rank_quantile(calibration, 0.5)));
    if (!c.calibration_known)
      s += "  " + c.name +
           ": the network's bound is singular for this free set, so the σ above leave the calibration out\n";
    if (c.plan.unseen > 0)
      s += "  " + c.name + ": " + std::to_string(c.plan.unseen) + " of " + std::to_string(c.plan.tried) +
           " instants seen by fewer than two cameras (no position there)\n";
  }
  return s;
}

std::string target_path_csv_text(const std::vector<TargetPathCandidate>& candidates) {
  std::string s =
      "candidate,t_s,E,N,U,cameras,sigma_m,sigma_E,sigma_N,sigma_U,sigma_labels_m,sigma_timing_m,"
      "sigma_calibration_m\n";
  for (const TargetPathCandidate& c : candidates)
    for (const PlannedTargetInstant& i : c.plan.instants)
      s += fmt::format("{},{:.3f},{:.4f},{:.4f},{:.4f},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}\n",
                       c.name, i.t_s, i.enu_m.x(), i.enu_m.y(), i.enu_m.z(),
                       path_cameras(c.cameras, i.cameras), i.sigma_m, std::sqrt(i.cov_m2(0, 0)),
                       std::sqrt(i.cov_m2(1, 1)), std::sqrt(i.cov_m2(2, 2)), i.labels_m, i.timing_m,
                       i.calibration_m);
  return s;
}

}  // namespace rangecal
