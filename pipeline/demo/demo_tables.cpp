#include "pipeline/demo/demo_tables.hpp"

#include <cmath>
#include <cstdio>
#include "config/number_format.hpp"

namespace rangecal {
namespace {

// seed 002 Table 1 (camera of the paper's experiment): Tsai two-step and the proposed method.
struct PaperColumn {
  const char* name;
  double u0, v0, f, sx, k1;
  double R[9];
  double T[3];
};
constexpr PaperColumn kPaperTsai{"paper Tsai",
                                 639.68,
                                 399.89,
                                 132.43,
                                 1.0055,
                                 -0.0002187,
                                 {-0.8240, -0.0079, 0.5665, 0.0166, -0.9994, 0.0289, 0.5660, 0.0332, 0.8237},
                                 {-4.2561, -2.9849, 62.5149}};
constexpr PaperColumn kPaperSassa{"paper SA-SSA",
                                  640.27,
                                  399.67,
                                  136.12,
                                  0.9966,
                                  -0.0003443,
                                  {-0.8273, 0.0006, 0.5617, 0.0151, -0.9994, 0.0307, 0.5614, 0.0339, 0.8268},
                                  {-4.2194, -3.0224, 63.8206}};

const char* const kMethodOrder[] = {"tsai", "tsai_sassa", "dlt_lmqn", "bundle", "network"};

std::string cell(const std::string& s, int w = 13) {
  return s.size() >= static_cast<std::size_t>(w) ? " " + s : std::string(w - s.size(), ' ') + s;
}

}  // namespace

std::vector<ParameterCheck> parameter_checks(const DemoCamera& cam, const std::string& method) {
  std::vector<ParameterCheck> out;
  const auto it = cam.by_method.find(method);
  if (it == cam.by_method.end()) return out;
  const CalibrationResult& r = it->second;
  using P = CameraParameter;
  out.push_back({parameter_name(P::f), r.camera.intr.f_mm, cam.truth.intr.f_mm, r.sigma(P::f)});
  out.push_back({parameter_name(P::k1), r.camera.intr.dist.k1, cam.truth.intr.dist.k1, r.sigma(P::k1)});
  const Eigen::Vector3d c = r.camera.pose.center(), ct = cam.truth.pose.center(), sc = r.center_sigma_m();
  for (int k = 0; k < 3; ++k) out.push_back({parameter_name(kCenterParameters[k]), c[k], ct[k], sc[k]});
  return out;
}

std::string format_demo_table1(const DemoCamera& cam) {
  std::vector<std::string> heads = {kPaperTsai.name, kPaperSassa.name, "truth"};
  std::vector<const Camera*> ours;
  for (const char* m : kMethodOrder) {
    const auto it = cam.by_method.find(m);
    if (it == cam.by_method.end()) continue;
    heads.push_back(m);
    ours.push_back(&it->second.camera);
  }
  std::string s = "Table 1 (" + cam.id + "): calibration results (seed 002 Table 1 layout)\n" + cell("", 9);
  for (const auto& h : heads) s += cell(h);
  s += "\n";
  auto row = [&](const char* name, const char* f, double pt, double ps, auto get) {
    s += cell(name, 9) + cell(format_number(f, pt)) + cell(format_number(f, ps)) +
         cell(format_number(f, get(cam.truth)));
    for (const Camera* c : ours) s += cell(format_number(f, get(*c)));
    s += "\n";
  };
  row("u0/px", "%.2f", kPaperTsai.u0, kPaperSassa.u0, [](const Camera& c) { return c.intr.u0_px; });
  row("v0/px", "%.2f", kPaperTsai.v0, kPaperSassa.v0, [](const Camera& c) { return c.intr.v0_px; });
  row("f/mm", "%.2f", kPaperTsai.f, kPaperSassa.f, [](const Camera& c) { return c.intr.f_mm; });
  row(parameter_name(CameraParameter::sx), "%.4f", kPaperTsai.sx, kPaperSassa.sx,
      [](const Camera& c) { return c.intr.sx; });
  row("k1/mm-2", "%.3e", kPaperTsai.k1, kPaperSassa.k1, [](const Camera& c) { return c.intr.dist.k1; });
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const std::string name = "R" + std::to_string(i + 1) + std::to_string(j + 1);
      row(name.c_str(), "%.4f", kPaperTsai.R[3 * i + j], kPaperSassa.R[3 * i + j],
          [i, j](const Camera& c) { return c.pose.R(i, j); });
    }
  const char* tn[3] = {"Tx/m", "Ty/m", "Tz/m"};
  for (int k = 0; k < 3; ++k)
    row(tn[k], "%.4f", kPaperTsai.T[k], kPaperSassa.T[k], [k](const Camera& c) { return c.pose.T[k]; });
  s += "(R and T of the paper are in its own site frame; ours and the truth in the demo's ENU.)\n";
  return s;
}

std::string format_demo_tables23(const std::vector<DemoCamera>& cams) {
  std::string s =
      "Tables 2-3: reprojection error (px). Paper: Tsai mean dR 0.99, proposed 0.43 (its own PPK noise "
      "and point selection).\n" +
      cell("camera", 9) + cell("method") + cell("rms_px") + cell("mean_px") + cell("max_px") +
      cell("n_used") + cell("expected_rms") + cell("rms_adj") + "\n";
  for (const DemoCamera& c : cams)
    for (const char* m : kMethodOrder) {
      const auto it = c.by_method.find(m);
      if (it == c.by_method.end()) continue;
      const ReprojectionStats& r = it->second.reprojection;
      const bool network = std::string(m) == "network" && std::isfinite(c.network_rms_adjusted_px);
      s += cell(c.id, 9) + cell(m) + cell(format_number("%.3f", r.rms_px)) +
           cell(format_number("%.3f", r.mean_px)) + cell(format_number("%.3f", r.max_px)) +
           cell(std::to_string(r.n_used)) + cell(format_number("%.3f", c.expected_rms_px)) +
           cell(network ? format_number("%.3f", c.network_rms_adjusted_px) : "-") + "\n";
    }
  // The two kinds of fit leave different things against the same fixes (docs/optimisation.md
  // "Network bundle"): said under the table, so that the network's larger figure is not read as a
  // worse calibration.
  s += "(rms/mean/max_px: every method against the same PPK fixes (correspondences.csv) and control\n"
       " poles; a fix the network flagged as a PPK outlier is its adjusted position there. The per-camera\n"
       " methods fit those fixes, and their pose takes up part of the slow PPK error; the network fits its\n"
       " adjusted lamp positions (each fix plus its estimate of the PPK error, "
       "gnss/lamp_track_adjusted.csv),\n"
       " so against the fixes its residuals carry that estimate. rms_adj: the network's lamp pairs against\n"
       " its adjusted positions, what its fit minimised. expected_rms: what a perfect calibration leaves\n"
       " against the fixes, from the simulated PPK and centroid noise.)\n";
  return s;
}

std::string format_demo_table4(const std::vector<DemoIntersection>& by_method) {
  std::string s =
      "Table 4: intersection error of the check poles (cm), network and bundle calibrations, against the "
      "survey\n" +
      cell("pole", 9) + cell("method", 9) + cell("dE") + cell("dN") + cell("dU") + cell("dR") +
      cell("sigma") + "\n";
  for (const char* meth : {"network", "bundle"})
    for (const auto& d : by_method) {
      if (d.method != meth) continue;
      for (const PoleIntersection& p : d.result.poles) {
        if (!p.surveyed || p.role != PoleRole::check) continue;
        s += cell(p.id, 9) + cell(meth, 9);
        for (int k = 0; k < 3; ++k) s += cell(format_number("%.2f", 100 * p.d_enu[k]));
        s += cell(format_number("%.2f", 100 * p.dR)) + cell(format_number("%.2f", 100 * p.sigma_m)) + "\n";
      }
    }
  s += "Mean rows (cm): paper Tsai |dx| 1.2 |dy| 2.4 |dz| 1.3 dR 3.0; paper proposed 0.7 2.2 0.7 2.5\n" +
       cell("method", 12) + cell("n") + cell("|dE|") + cell("|dN|") + cell("|dU|") + cell("dR survey") +
       cell("dR truth") + cell("max truth") + cell("sigma") + "\n";
  for (const auto& d : by_method) {
    const IntersectionMeans& m = d.result.check;
    s += cell(d.method, 12) + cell(std::to_string(m.n));
    for (int k = 0; k < 3; ++k) s += cell(format_number("%.2f", 100 * m.mean_abs_d[k]));
    s += cell(format_number("%.2f", 100 * m.mean_dR)) + cell(format_number("%.2f", 100 * d.mean_dR_truth_m)) +
         cell(format_number("%.2f", 100 * d.max_dR_truth_m)) +
         cell(format_number("%.2f", 100 * m.mean_sigma_m)) + "\n";
  }
  return s;
}

}  // namespace rangecal
