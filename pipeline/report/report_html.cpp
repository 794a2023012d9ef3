#include "pipeline/report/report_html.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "config/number_format.hpp"
#include "pipeline/report/html_escape.hpp"
#include "pipeline/report/svg_plot.hpp"
#include "pipeline/steps/intersection.hpp"
#include "vision/camera/camera_model.hpp"

namespace rangecal {
namespace {

constexpr const char* kDash = "&#8212;";  // shown for a value that does not exist (σ not estimated)

// Fixed-format number; a dash for NaN / infinity.
std::string fmt(const char* f, double x) {
  return std::isfinite(x) ? format_number(f, x) : std::string(kDash);
}

std::string td(const std::string& html, const char* cls = "num") {
  return std::string("<td class=\"") + cls + "\">" + html + "</td>";
}
std::string th(const std::string& html) {
  return "<th>" + html + "</th>";
}

const char* kStyle =
    "body{font-family:sans-serif;margin:24px;color:#222;max-width:1200px}"
    "h1{font-size:22px}h2{font-size:18px;border-bottom:1px solid #ccc;padding-bottom:4px;margin-top:32px}"
    "h3{font-size:15px}table{border-collapse:collapse;margin:8px 0}"
    "th,td{border:1px solid #bbb;padding:3px 8px;font-size:13px}th{background:#eef2f7}"
    "td.num{text-align:right;font-family:monospace}td.txt{text-align:left}"
    "tr.mean td{font-weight:bold;background:#f6f6f6}"
    ".missing{color:#a33;font-weight:bold}.warn{color:#8a5a00}"
    "figure{display:inline-block;margin:8px 16px 8px 0;vertical-align:top}"
    "figcaption{font-size:12px;color:#555}";

std::string mission_section(const ReportData& d) {
  std::string s = "<section id=\"mission\">\n<h2>Mission</h2>\n<table class=\"kv\">\n";
  auto row = [&](const std::string& k, const std::string& v) {
    s += "<tr>" + th(k) + td(v, "txt") + "</tr>\n";
  };
  row("Mission", html_escape(d.mission.empty() ? std::string("(no description)") : d.mission));
  row("Program",
      "rangecal " + html_escape(d.program_version.empty() ? "(run.json missing)" : d.program_version));
  row("Config SHA-256", html_escape(d.config_sha256.empty() ? "(not recorded)" : d.config_sha256));
  if (d.track) {
    row("Lamp track", std::to_string(d.track->epochs) + " epochs, " + format_iso8601_utc(d.track->start, 3) +
                          " .. " + format_iso8601_utc(d.track->end, 3) + " (" +
                          fmt("%.3f", seconds_between(d.track->start, d.track->end)) + " s)");
  } else {
    row("Lamp track", "<span class=\"missing\">gnss/lamp_track.csv missing</span>");
  }
  row("Cameras", std::to_string(d.cameras.size()));
  s += "</table>\n<h3>Warnings</h3>\n";
  std::size_t n = 0;
  for (const StageWarnings& sw : d.stage_warnings) n += sw.warnings.size();
  if (n == 0) s += "<p>None.</p>\n";
  for (const StageWarnings& sw : d.stage_warnings) {
    if (sw.warnings.empty()) continue;
    s += "<p>" + html_escape(sw.stage) + " stage:</p>\n<ul class=\"warnings\">\n";
    for (const std::string& w : sw.warnings) s += "<li class=\"warn\">" + html_escape(w) + "</li>\n";
    s += "</ul>\n";
  }
  return s + "</section>\n";
}

std::string status_of(const CameraReportData& c) {
  if (c.calibration) return "calibrated";
  if (!c.calibration_failure.empty()) return "calibration failed: " + c.calibration_failure;
  return "not calibrated (calibration.json missing)";
}

std::string overview_section(const ReportData& d) {
  std::string s = "<section id=\"overview\">\n<h2>Overview</h2>\n<table class=\"overview\">\n<tr>" +
                  th("Camera") + th("Status") + th("Method") + th("RMS /px") + th("n used") +
                  th("n rejected") + "</tr>\n";
  for (const CameraReportData& c : d.cameras) {
    s += "<tr>" + td(html_escape(c.id), "txt") + td(html_escape(status_of(c)), "txt");
    if (c.calibration) {
      const ReprojectionStats& r = c.calibration->reprojection;
      s += td(html_escape(c.calibration->method), "txt") + td(fmt("%.3f", r.rms_px)) +
           td(std::to_string(r.n_used)) + td(std::to_string(r.n_rejected));
    } else {
      s += td(kDash, "txt") + td(kDash) + td(kDash) + td(kDash);
    }
    s += "</tr>\n";
  }
  return s + "</table>\n</section>\n";
}

// Parameters with 1σ (calibration.json `sigma`; a dash where the method held the parameter fixed).
std::string parameters_table(const CalibrationResult& r) {
  const CameraIntrinsics& in = r.camera.intr;
  std::string s = "<h3>Parameters (" + html_escape(r.method) + ")</h3>\n<table class=\"parameters\">\n<tr>" +
                  th("Parameter") + th("Value") + th("1&#963;") + th("Unit") + "</tr>\n";
  auto row = [&](const std::string& name, const char* vf, double v, const char* sf, double sg,
                 const std::string& unit) {
    s += "<tr>" + td(name, "txt") + td(fmt(vf, v)) + td(fmt(sf, sg)) + td(unit, "txt") + "</tr>\n";
  };
  using P = CameraParameter;
  row(parameter_name(P::f), "%.4f", in.f_mm, "%.4f", r.sigma(P::f), "mm");
  row("u<sub>0</sub>", "%.2f", in.u0_px, "%.2f", r.sigma(P::u0), "px");
  row("v<sub>0</sub>", "%.2f", in.v0_px, "%.2f", r.sigma(P::v0), "px");
  row("s<sub>x</sub>", "%.6f", in.sx, "%.6f", r.sigma(P::sx), "");
  const auto dist = in.dist.as_array();
  const char* units[7] = {
      "mm<sup>-2</sup>", "mm<sup>-4</sup>", "mm<sup>-6</sup>", "mm<sup>-1</sup>", "mm<sup>-1</sup>", "", ""};
  for (int i = 0; i < 7; ++i)
    if (i == 0 || dist[i] != 0)
      row(std::string(parameter_name(kDistortionParameters[i])).insert(1, "<sub>") + "</sub>", "%.4e",
          dist[i], "%.2e", r.sigma(kDistortionParameters[i]), units[i]);
  for (const P w : kRotationParameters)
    row(std::string("rotation ") + parameter_name(w), "%.1f", std::nan(""), "%.4f", r.sigma(w) * 1e3,
        "mrad (small rotation about R below)");
  for (int i = 0; i < 3; ++i)
    row(std::string("T") + "xyz"[i], "%.4f", r.camera.pose.T[i], "%.4f", r.sigma(kTranslationParameters[i]),
        "m");
  const Eigen::Vector3d C = r.camera.pose.center(), cs = r.center_sigma_m();
  for (int i = 0; i < 3; ++i) row(std::string("centre ") + "ENU"[i], "%.4f", C[i], "%.4f", cs[i], "m");
  if (r.parameter_index(P::clock_offset) >= 0)
    row("clock offset", "%.3f", r.clock_offset_s * 1e3, "%.3f", r.sigma(P::clock_offset) * 1e3,
        "ms (camera stamp &#8722; GNSS time)");
  s += "</table>\n<p>R (world ENU &#8594; camera):</p>\n<table class=\"matrix\">\n";
  for (int i = 0; i < 3; ++i) {
    s += "<tr>";
    for (int j = 0; j < 3; ++j) s += td(fmt("%.6f", r.camera.pose.R(i, j)));
    s += "</tr>\n";
  }
  s += "</table>\n<p>&#8212; : not estimated (held fixed by the method).</p>\n";
  if (!r.warnings.empty()) {
    s += "<ul class=\"warnings\">\n";
    for (const std::string& x : r.warnings) s += "<li class=\"warn\">" + html_escape(x) + "</li>\n";
    s += "</ul>\n";
  }
  return s;
}

// Per lamp pair: observed pixel, reprojection (if the world point projects) and the difference.
struct PairResidual {
  Eigen::Vector2d observed;
  bool projected = false;
  Eigen::Vector2d reprojected = Eigen::Vector2d::Zero();
  bool used = true;
};

std::vector<PairResidual> pair_residuals(const CameraReportData& c) {
  std::vector<PairResidual> out;
  if (!c.pairs) return out;
  // residuals.csv's lamp rows follow the pairs one to one: they say which the calibration used.
  std::vector<bool> used(c.pairs->size(), true);
  if (c.residuals) {
    std::size_t k = 0;
    for (const ResidualRow& row : *c.residuals)
      if (row.kind == ResidualRow::Kind::lamp && k < used.size()) used[k++] = row.used;
  }
  for (std::size_t i = 0; i < c.pairs->size(); ++i) {
    const Correspondence& p = (*c.pairs)[i];
    PairResidual r;
    r.observed = p.uv;
    r.used = used[i];
    if (c.calibration) {
      // Where the lamp stood at the true exposure time (optim/bundle/bundle_adjustment.hpp clock offset).
      const Eigen::Vector3d seen =
          p.enu - p.vel_enu.value_or(Eigen::Vector3d::Zero()) * c.calibration->clock_offset_s;
      r.projected = project(c.calibration->camera, seen, &r.reprojected);
    }
    out.push_back(r);
  }
  return out;
}

// Seed 002 Tables 2–3: the headline statistics, then per point Δu, Δv, ΔR and the mean row.
std::string reprojection_tables(const CameraReportData& c, const std::vector<PairResidual>& res) {
  const ReprojectionStats& st = c.calibration->reprojection;
  std::string s =
      "<h3>Reprojection error (seed 002 Tables 2&#8211;3)</h3>\n<table class=\"reprojection\">\n<tr>" +
      th("RMS /px") + th("mean /px") + th("max /px") + th("n used") + th("n rejected") + "</tr>\n<tr>" +
      td(fmt("%.3f", st.rms_px)) + td(fmt("%.3f", st.mean_px)) + td(fmt("%.3f", st.max_px)) +
      td(std::to_string(st.n_used)) + td(std::to_string(st.n_rejected)) + "</tr>\n</table>\n";
  if (res.empty()) return s;
  s += "<details><summary>Per lamp point (" + std::to_string(res.size()) +
       ")</summary>\n<table class=\"points\">\n<tr>" + th("No.") + th("u /px") + th("v /px") +
       th("&#916;u /px") + th("&#916;v /px") + th("&#916;R /px") + th("used") + "</tr>\n";
  double su = 0, sv = 0, sr = 0;
  int n = 0;
  for (std::size_t i = 0; i < res.size(); ++i) {
    const PairResidual& p = res[i];
    const Eigen::Vector2d d = p.observed - p.reprojected;
    s += "<tr>" + td(std::to_string(i + 1)) + td(fmt("%.2f", p.observed.x())) +
         td(fmt("%.2f", p.observed.y()));
    if (p.projected) {
      s += td(fmt("%.2f", d.x())) + td(fmt("%.2f", d.y())) + td(fmt("%.2f", d.norm()));
      if (p.used) {
        su += std::abs(d.x());
        sv += std::abs(d.y());
        sr += d.norm();
        ++n;
      }
    } else {
      s += td(kDash) + td(kDash) + td(kDash);
    }
    s += td(p.used ? "yes" : "no", "txt") + "</tr>\n";
  }
  if (n > 0)
    s += "<tr class=\"mean\">" + td("mean", "txt") + td("") + td("") + td(fmt("%.2f", su / n)) +
         td(fmt("%.2f", sv / n)) + td(fmt("%.2f", sr / n)) + td(std::to_string(n) + " used", "txt") +
         "</tr>\n";
  return s +
         "</table>\n<p>&#916; = observed &#8722; reprojected; the mean row averages |&#916;u|, |&#916;v| and "
         "&#916;R over used points, as the paper's tables do.</p>\n</details>\n";
}

// Where the lamp track restarts: a time step over 5× the median step (a new ascent after the UAV
// flew back down out of view), so Fig. 6 joins points only along one flown segment.
std::vector<std::size_t> track_breaks(const std::vector<Correspondence>& pairs) {
  std::vector<std::int64_t> steps;
  for (std::size_t i = 1; i < pairs.size(); ++i) steps.push_back(pairs[i].utc.ns - pairs[i - 1].utc.ns);
  std::vector<std::size_t> breaks;
  if (steps.empty()) return breaks;
  std::vector<std::int64_t> sorted = steps;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const std::int64_t median = sorted[sorted.size() / 2];
  for (std::size_t i = 0; i < steps.size(); ++i)
    if (steps[i] > 5 * median) breaks.push_back(i + 1);
  return breaks;
}

std::string plots(const CameraReportData& c, const std::vector<PairResidual>& res) {
  if (res.empty() || c.width_px <= 0 || c.height_px <= 0) return "";
  const PlotFrame frame{c.width_px, c.height_px};
  std::vector<Eigen::Vector2d> obs, proj, at, resid;
  std::vector<bool> used;
  std::vector<double> norms;
  for (const PairResidual& p : res) {
    obs.push_back(p.observed);
    used.push_back(p.used);
    if (!p.projected) continue;
    proj.push_back(p.reprojected);
    at.push_back(p.observed);
    resid.push_back(p.observed - p.reprojected);
    if (p.used) norms.push_back(resid.back().norm());
  }
  if (proj.size() != obs.size()) proj.clear();  // a point that does not project: plot no crosses
  const std::string base = "cam-" + c.id;
  std::string s = "<h3>Plots</h3>\n<figure>" +
                  svg_lamp_track(frame, obs, proj, used, track_breaks(*c.pairs), base + "-track") +
                  "<figcaption>Lamp track on the image (seed 002 Fig. 6)</figcaption></figure>\n";
  if (!c.calibration) return s;
  s += "<figure>" + svg_residual_vectors(frame, at, resid, base + "-residuals") +
       "<figcaption>Residual vectors, observed &#8722; reprojected</figcaption></figure>\n";
  s += "<figure>" + svg_histogram(norms, "residual |observed - reprojected| /px", base + "-histogram") +
       "<figcaption>Residual histogram (used points)</figcaption></figure>\n";
  return s;
}

// Seed 002 Table 1 layout: parameters down, methods across.
std::string methods_table(const CameraReportData& c) {
  std::vector<MethodRow> rows;
  std::string note;
  if (c.methods) {
    rows = *c.methods;
  } else if (c.calibration) {
    rows.push_back(method_row(*c.calibration));  // no methods.csv (no `compare`): the one method
    note =
        "<p>methods.csv missing (no <code>calibrate.compare</code> in the config): main method only.</p>\n";
  } else {
    return "";
  }
  std::string s =
      "<h3>Methods (seed 002 Table 1)</h3>\n" + note + "<table class=\"methods\">\n<tr>" + th("Parameter");
  for (const MethodRow& m : rows) s += th(html_escape(m.method));
  s += "</tr>\n";
  auto row = [&](const std::string& name, auto value) {
    s += "<tr>" + td(name, "txt");
    for (const MethodRow& m : rows) s += td(value(m));
    s += "</tr>\n";
  };
  row("u<sub>0</sub> /px", [](const MethodRow& m) { return fmt("%.2f", m.u0_px); });
  row("v<sub>0</sub> /px", [](const MethodRow& m) { return fmt("%.2f", m.v0_px); });
  row("f /mm", [](const MethodRow& m) { return fmt("%.3f", m.f_mm); });
  row("&#963;<sub>f</sub> /mm",
      [](const MethodRow& m) { return m.sigma_f_mm ? fmt("%.3f", *m.sigma_f_mm) : kDash; });
  row("s<sub>x</sub>", [](const MethodRow& m) { return fmt("%.4f", m.sx); });
  row("k<sub>1</sub> /mm<sup>-2</sup>", [](const MethodRow& m) { return fmt("%.4e", m.k1_per_mm2); });
  row("R", [](const MethodRow& m) {
    std::string x;
    for (int i = 0; i < 3; ++i)
      x += (i ? "<br>" : "") + fmt("%.4f", m.R(i, 0)) + " " + fmt("%.4f", m.R(i, 1)) + " " +
           fmt("%.4f", m.R(i, 2));
    return x;
  });
  row("T /m", [](const MethodRow& m) {
    return fmt("%.4f", m.T[0]) + "<br>" + fmt("%.4f", m.T[1]) + "<br>" + fmt("%.4f", m.T[2]);
  });
  row("RMS /px", [](const MethodRow& m) { return fmt("%.3f", m.rms_px); });
  row("n used / rejected",
      [](const MethodRow& m) { return std::to_string(m.n_used) + " / " + std::to_string(m.n_rejected); });
  // Wall times are in run.json (calibrate counts), not here: they differ between runs and the
  // report must be byte-identical for the same inputs.
  return s + "</table>\n";
}

std::string camera_section(const CameraReportData& c) {
  std::string s = "<section class=\"camera\" id=\"cam-" + html_escape(c.id) + "\">\n<h2>Camera " +
                  html_escape(c.id) + "</h2>\n";
  if (!c.calibration)
    s += "<p class=\"missing\">" + html_escape(c.id) + ": " + html_escape(status_of(c)) + ".</p>\n";
  if (!c.pairs) s += "<p class=\"missing\">correspondences.csv missing.</p>\n";
  const std::vector<PairResidual> res = pair_residuals(c);
  if (c.calibration) s += parameters_table(*c.calibration) + reprojection_tables(c, res);
  s += plots(c, res);
  s += methods_table(c);
  return s + "</section>\n";
}

std::string cm(const std::optional<double>& m_value, bool absolute = false) {
  if (!m_value) return kDash;
  return fmt("%.2f", (absolute ? std::abs(*m_value) : *m_value) * 100.0);
}

// Seed 002 Table 4, in cm: per pole ΔE ΔN ΔU ΔR and predicted 1σ, then the mean row (mean of
// |ΔE|, |ΔN|, |ΔU|, ΔR and σ over surveyed poles, as the paper's mean row) and the max ΔR.
std::string intersection_section(const ReportData& d) {
  std::string s = "<section id=\"intersection\">\n<h2>Intersection check (seed 002 Table 4)</h2>\n";
  if (!d.intersection)
    return s +
           "<p class=\"missing\">intersection.csv missing: the intersect stage has not run or found no pole "
           "seen by two calibrated cameras.</p>\n</section>\n";
  s += "<table class=\"intersection\">\n<tr>" + th("Pole") + th("E /m") + th("N /m") + th("U /m") +
       th("&#916;E /cm") + th("&#916;N /cm") + th("&#916;U /cm") + th("&#916;R /cm") + th("&#963; /cm") +
       "</tr>\n";
  for (const IntersectionRow& r : *d.intersection) {
    s += "<tr>" + td(html_escape(r.id), "txt") + td(fmt("%.4f", r.enu.x())) + td(fmt("%.4f", r.enu.y())) +
         td(fmt("%.4f", r.enu.z()));
    for (int i = 0; i < 3; ++i) s += td(cm(r.d_enu[i]));
    s += td(cm(r.dR)) + td(cm(r.sigma_m)) + "</tr>\n";
  }
  const IntersectionMeans m = intersection_means(*d.intersection);
  auto mean_cell = [&](double v) { return m.n > 0 ? fmt("%.2f", v * 100.0) : std::string(kDash); };
  s += "<tr class=\"mean\">" + td("mean", "txt") + td("") + td("") + td("");
  for (int i = 0; i < 3; ++i) s += td(mean_cell(m.mean_abs_d[i]));
  s += td(mean_cell(m.mean_dR)) + td(mean_cell(m.mean_sigma_m)) + "</tr>\n";
  s += "<tr class=\"mean\">" + td("max", "txt") + td("") + td("") + td("") + td("") + td("") + td("") +
       td(mean_cell(m.max_dR)) + td("") + "</tr>\n</table>\n";
  s +=
      "<p>&#916; = intersected &#8722; surveyed; mean row: mean |&#916;E|, |&#916;N|, |&#916;U|, &#916;R and "
      "&#963; over surveyed poles; &#963; = predicted 1&#963; of &#916;R (calibration covariance and pick "
      "noise).</p>\n";
  return s + "</section>\n";
}

}  // namespace

std::string render_report_html(const ReportData& d) {
  std::string s =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>rangecal report: " +
      html_escape(d.mission) + "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n";
  s += "<h1>rangecal calibration report</h1>\n";
  s += mission_section(d);
  s += overview_section(d);
  for (const CameraReportData& c : d.cameras) s += camera_section(c);
  s += intersection_section(d);
  s += "</body>\n</html>\n";
  return s;
}

}  // namespace rangecal
