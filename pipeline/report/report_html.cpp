#include "pipeline/report/report_html.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "config/number_format.hpp"
#include "pipeline/io/run_outcome.hpp"
#include "pipeline/report/attitude_timing.hpp"
#include "pipeline/report/data_funnel.hpp"
#include "pipeline/report/flight_volume_sigma.hpp"
#include "pipeline/report/html_escape.hpp"
#include "pipeline/report/intersection_prediction.hpp"
#include "pipeline/report/lamp_residuals.hpp"
#include "pipeline/report/ppk_error_model_html.hpp"
#include "pipeline/report/principal_point_cost.hpp"
#include "pipeline/report/projection_uncertainty.hpp"
#include "pipeline/report/report_plots.hpp"
#include "pipeline/report/svg_plot.hpp"
#include "pipeline/report/trajectory_html.hpp"
#include "pipeline/report/verdict.hpp"
#include "pipeline/steps/intersection.hpp"
#include "vision/camera/camera_model.hpp"

namespace rangecal {
namespace {

constexpr const char* kDash = "&#8212;";  // shown for a value that does not exist (σ not estimated)

// Fixed-format number; a dash for NaN / infinity.
std::string fmt(const char* f, double x) {
  return std::isfinite(x) ? format_number(f, x) : std::string(kDash);
}

std::string report_td(const std::string& html, const char* cls = "num") {
  return std::string("<td class=\"") + cls + "\">" + html + "</td>";
}
std::string report_th(const std::string& html) {
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
    "figcaption{font-size:12px;color:#555;max-width:640px}.ok{color:#1b7a1b}.bad{color:#b00020;font-weight:"
    "bold}"
    "@media print{figure,table{break-inside:avoid}body{margin:0}}";

std::string mission_section(const ReportData& d) {
  std::string s = "<section id=\"mission\">\n<h2>Mission</h2>\n<table class=\"kv\">\n";
  auto row = [&](const std::string& k, const std::string& v) {
    s += "<tr>" + report_th(k) + report_td(v, "txt") + "</tr>\n";
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
                  report_th("Camera") + report_th("Status") + report_th("Method") + report_th("RMS /px") +
                  report_th("n used") + report_th("n rejected") + "</tr>\n";
  for (const CameraReportData& c : d.cameras) {
    s += "<tr>" + report_td(html_escape(c.id), "txt") + report_td(html_escape(status_of(c)), "txt");
    if (c.calibration) {
      const ReprojectionStats& r = c.calibration->reprojection;
      s += report_td(html_escape(c.calibration->method), "txt") + report_td(fmt("%.3f", r.rms_px)) +
           report_td(std::to_string(r.n_used)) + report_td(std::to_string(r.n_rejected));
    } else {
      s += report_td(kDash, "txt") + report_td(kDash) + report_td(kDash) + report_td(kDash);
    }
    s += "</tr>\n";
  }
  return s + "</table>\n</section>\n";
}

// Parameters with 1σ (calibration.json `sigma`; a dash where the method held the parameter fixed).
std::string parameters_table(const CalibrationResult& r) {
  const CameraIntrinsics& in = r.camera.intr;
  std::string s = "<h3>Parameters (" + html_escape(r.method) + ")</h3>\n<table class=\"parameters\">\n<tr>" +
                  report_th("Parameter") + report_th("Value") + report_th("1&#963;") + report_th("Unit") +
                  "</tr>\n";
  auto row = [&](const std::string& name, const char* vf, double v, const char* sf, double sg,
                 const std::string& unit) {
    s += "<tr>" + report_td(name, "txt") + report_td(fmt(vf, v)) + report_td(fmt(sf, sg)) +
         report_td(unit, "txt") + "</tr>\n";
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
    for (int j = 0; j < 3; ++j) s += report_td(fmt("%.6f", r.camera.pose.R(i, j)));
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

using PairResidual = LampResidual;

// Seed 002 Tables 2–3: the headline statistics, then per point Δu, Δv, ΔR and the mean row.
std::string reprojection_tables(const CameraReportData& c, const std::vector<PairResidual>& res) {
  const ReprojectionStats& st = c.calibration->reprojection;
  std::string s =
      "<h3>Reprojection error (seed 002 Tables 2&#8211;3)</h3>\n<table class=\"reprojection\">\n<tr>" +
      report_th("RMS /px") + report_th("mean /px") + report_th("max /px") + report_th("n used") +
      report_th("n rejected") + "</tr>\n<tr>" + report_td(fmt("%.3f", st.rms_px)) +
      report_td(fmt("%.3f", st.mean_px)) + report_td(fmt("%.3f", st.max_px)) +
      report_td(std::to_string(st.n_used)) + report_td(std::to_string(st.n_rejected)) + "</tr>\n</table>\n";
  if (res.empty()) return s;
  s += "<details><summary>Per lamp point (" + std::to_string(res.size()) +
       ")</summary>\n<table class=\"points\">\n<tr>" + report_th("No.") + report_th("u /px") +
       report_th("v /px") + report_th("&#916;u /px") + report_th("&#916;v /px") + report_th("&#916;R /px") +
       report_th("used") + "</tr>\n";
  double su = 0, sv = 0, sr = 0;
  int n = 0;
  for (std::size_t i = 0; i < res.size(); ++i) {
    const PairResidual& p = res[i];
    const Eigen::Vector2d d = p.observed - p.reprojected;
    s += "<tr>" + report_td(std::to_string(i + 1)) + report_td(fmt("%.2f", p.observed.x())) +
         report_td(fmt("%.2f", p.observed.y()));
    if (p.projected) {
      s += report_td(fmt("%.2f", d.x())) + report_td(fmt("%.2f", d.y())) + report_td(fmt("%.2f", d.norm()));
      if (p.used) {
        su += std::abs(d.x());
        sv += std::abs(d.y());
        sr += d.norm();
        ++n;
      }
    } else {
      s += report_td(kDash) + report_td(kDash) + report_td(kDash);
    }
    s += report_td(p.used ? "yes" : "no", "txt") + "</tr>\n";
  }
  if (n > 0)
    s += "<tr class=\"mean\">" + report_td("mean", "txt") + report_td("") + report_td("") +
         report_td(fmt("%.2f", su / n)) + report_td(fmt("%.2f", sv / n)) + report_td(fmt("%.2f", sr / n)) +
         report_td(std::to_string(n) + " used", "txt") + "</tr>\n";
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
    resid.push_back(p.residual);
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
  s += "<figure>" + svg_histogram(norms, "residual |observed - reprojected| (px)", base + "-histogram") +
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
  std::string s = "<h3>Methods (seed 002 Table 1)</h3>\n" + note + "<table class=\"methods\">\n<tr>" +
                  report_th("Parameter");
  for (const MethodRow& m : rows) s += report_th(html_escape(m.method));
  s += "</tr>\n";
  auto row = [&](const std::string& name, auto value) {
    s += "<tr>" + report_td(name, "txt");
    for (const MethodRow& m : rows) s += report_td(value(m));
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

// What the report computes once per camera from its files (the plotted numbers come from the typed
// functions of pipeline/report/, tested there).
struct CameraFigures {
  std::vector<LampResidual> res;
  ResidualConsistency consistency;
  ClockOffsetSignature clock;
  double depth_m = std::nan("");  ///< median lamp depth: the flight distance of the uncertainty map
  std::optional<ProjectionUncertaintyMap> uncertainty;
  double centre_sigma_px = std::nan("");  ///< projection σ at the image centre (px)
};

/// The lamp centroids' own σ: calibration.json's `details.pixel_sigma_px` (the network's estimate of
/// the camera's image variance component, or the stated σ) over √`details.time_correlation_factor`
/// (what the network weighed it by beyond its scatter), else `fallback`.
double calibration_pixel_sigma_px(const CalibrationResult* cal, double fallback) {
  if (!cal || !cal->details.is_object() || !cal->details.contains("pixel_sigma_px")) return fallback;
  const nlohmann::json& v = cal->details["pixel_sigma_px"];
  if (!v.is_number() || !(v.get<double>() > 0)) return fallback;
  const nlohmann::json* f =
      cal->details.contains("time_correlation_factor") ? &cal->details["time_correlation_factor"] : nullptr;
  const double factor = f && f->is_number() && f->get<double>() >= 1 ? f->get<double>() : 1.0;
  return v.get<double>() / std::sqrt(factor);
}

CameraFigures camera_figures(const CameraReportData& c, double pixel_sigma_px) {
  CameraFigures f;
  if (!c.pairs) return f;
  const CalibrationResult* cal = c.calibration ? &*c.calibration : nullptr;
  f.res =
      lamp_residuals(*c.pairs, cal, c.residuals ? &*c.residuals : nullptr,
                     calibration_pixel_sigma_px(cal, pixel_sigma_px), c.ppk_model ? &*c.ppk_model : nullptr);
  if (!cal) return f;
  f.consistency = residual_consistency(f.res, static_cast<int>(cal->parameters.size()));
  f.clock = clock_offset_signature(f.res, c.ppk_model ? &*c.ppk_model : nullptr);
  f.depth_m = median_depth_m(cal->camera, *c.pairs);
  if (std::isfinite(f.depth_m) && !cal->parameters.empty() &&
      cal->covariance.rows() == static_cast<Eigen::Index>(cal->parameters.size())) {
    f.uncertainty = projection_uncertainty_map(*cal, f.depth_m, 41, 25);
    const CameraIntrinsics& in = cal->camera.intr;
    f.centre_sigma_px = projection_sigma_px(
        *cal, Eigen::Vector2d((in.width_px - 1) / 2.0, (in.height_px - 1) / 2.0), f.depth_m);
  }
  return f;
}

std::string figure(const std::string& svg, const std::string& caption) {
  return "<figure>" + svg + "<figcaption>" + caption + "</figcaption></figure>\n";
}

// Residuals against time and image height, u and v apart; the distortion; the projection
// uncertainty; the correlation matrix.
std::string diagnostic_plots(const CameraReportData& c, const CameraFigures& f) {
  if (!c.calibration) return "";
  const CalibrationResult& cal = *c.calibration;
  const std::string base = "cam-" + c.id;
  std::string s = "<h3>Residual diagnostics</h3>\n";
  std::vector<double> t, v, du, dv, su, sv;
  std::vector<bool> used;
  if (!f.res.empty()) {
    const UtcTime t0 = f.res.front().utc;
    for (const LampResidual& r : f.res) {
      if (!r.projected) continue;
      t.push_back(seconds_between(t0, r.utc));
      v.push_back(r.observed.y());
      du.push_back(r.residual.x());
      dv.push_back(r.residual.y());
      su.push_back(r.sigma_px.x());
      sv.push_back(r.sigma_px.y());
      used.push_back(r.used);
    }
  }
  if (!t.empty()) {
    s +=
        "<p>Observed &#8722; reprojected against time and against image row, with the &#177;2&#963; band the "
        "noise model expects (lamp centroid &#963; and the PPK sd projected into the image). A clock offset "
        "shows as residuals that follow the lamp's image speed (a trend with time along each ascent); a "
        "lever-arm or height error as a trend with image row.</p>\n";
    s += figure(svg_residual_scatter(t, du, su, used, "time since first pair (s)", "Δu (px)",
                                     base + "-du-time", "u residual against time"),
                "&#916;u against time");
    s += figure(svg_residual_scatter(t, dv, sv, used, "time since first pair (s)", "Δv (px)",
                                     base + "-dv-time", "v residual against time"),
                "&#916;v against time");
    s += figure(svg_residual_scatter(v, du, su, used, "image row v (px)", "Δu (px)", base + "-du-height",
                                     "u residual against image height"),
                "&#916;u against image row");
    s += figure(svg_residual_scatter(v, dv, sv, used, "image row v (px)", "Δv (px)", base + "-dv-height",
                                     "v residual against image height"),
                "&#916;v against image row");
  }
  const PlotFrame frame{c.width_px, c.height_px};
  s += "<h3>Uncertainty and model</h3>\n";
  if (f.uncertainty) {
    s += figure(svg_image_map(frame, f.uncertainty->u_px, f.uncertainty->v_px, f.uncertainty->sigma_px,
                              "projection σ (px)", base + "-uncertainty", "Projection uncertainty"),
                "Projection uncertainty: 1&#963; (px, worst direction) of where a point " +
                    fmt("%.1f", f.depth_m) +
                    " m in front of the camera (the median lamp depth) lands, from the parameter covariance "
                    "(centre: " +
                    fmt("%.3f", f.centre_sigma_px) + " px)");
  } else {
    s += "<p>No covariance in calibration.json: no projection-uncertainty map.</p>\n";
  }
  // Distortion: where each pixel's undistorted image lies (px), over a 16 × 10 grid.
  std::vector<Eigen::Vector2d> at, vec;
  const CameraIntrinsics& in = cal.camera.intr;
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < 16; ++i) {
      const Eigen::Vector2d q(-0.5 + (i + 0.5) * in.width_px / 16.0, -0.5 + (j + 0.5) * in.height_px / 10.0);
      const Eigen::Vector2d su2 = pixel_to_undistorted_sensor(in, q);
      const Eigen::Vector2d qu(in.u0_px + in.sx * su2.x() / in.dx_mm, in.v0_px + su2.y() / in.dy_mm);
      at.push_back(q);
      vec.push_back(qu - q);
    }
  s += figure(svg_image_vectors(frame, at, vec, "distortion", base + "-distortion", "Distortion"),
              "Distortion: from each pixel to where the undistorted (pinhole) model puts it (px)");
  const auto n = static_cast<Eigen::Index>(cal.parameters.size());
  if (n > 0 && cal.covariance.rows() == n) {
    Eigen::MatrixXd rho(n, n);
    for (Eigen::Index i = 0; i < n; ++i)
      for (Eigen::Index j = 0; j < n; ++j) rho(i, j) = cal.correlation(cal.parameters[i], cal.parameters[j]);
    s += figure(svg_correlation_grid(parameter_names(cal.parameters), rho, base + "-correlation"),
                "Correlation of the estimated parameters (calibration.json covariance)");
  }
  return s;
}

std::string camera_section(const CameraReportData& c, const CameraFigures& f) {
  std::string s = "<section class=\"camera\" id=\"cam-" + html_escape(c.id) + "\">\n<h2>Camera " +
                  html_escape(c.id) + "</h2>\n";
  if (!c.calibration)
    s += "<p class=\"missing\">" + html_escape(c.id) + ": " + html_escape(status_of(c)) + ".</p>\n";
  if (!c.pairs) s += "<p class=\"missing\">correspondences.csv missing.</p>\n";
  const std::vector<PairResidual>& res = f.res;
  if (c.calibration) s += parameters_table(*c.calibration) + reprojection_tables(c, res);
  s += plots(c, res);
  s += diagnostic_plots(c, f);
  s += methods_table(c);
  return s + "</section>\n";
}

std::string cm(const std::optional<double>& m_value, bool absolute = false) {
  if (!m_value) return kDash;
  return fmt("%.2f", (absolute ? std::abs(*m_value) : *m_value) * 100.0);
}

// Seed 002 Table 4, in cm: per pole ΔE ΔN ΔU ΔR and predicted 1σ, then the mean row (mean of
// |ΔE|, |ΔN|, |ΔU|, ΔR and σ over surveyed poles, as the paper's mean row) and the max ΔR.
std::string intersection_section(const ReportData& d, const std::string& plots) {
  std::string s = "<section id=\"intersection\">\n<h2>Intersection check (seed 002 Table 4)</h2>\n";
  if (!d.intersection)
    return s +
           "<p class=\"missing\">intersection.csv missing: the intersect stage has not run or found no pole "
           "seen by two calibrated cameras.</p>\n</section>\n";
  s += "<table class=\"intersection\">\n<tr>" + report_th("Pole") + report_th("E /m") + report_th("N /m") +
       report_th("U /m") + report_th("&#916;E /cm") + report_th("&#916;N /cm") + report_th("&#916;U /cm") +
       report_th("&#916;R /cm") + report_th("&#963; /cm") + "</tr>\n";
  for (const IntersectionRow& r : *d.intersection) {
    s += "<tr>" + report_td(html_escape(r.id), "txt") + report_td(fmt("%.4f", r.enu.x())) +
         report_td(fmt("%.4f", r.enu.y())) + report_td(fmt("%.4f", r.enu.z()));
    for (int i = 0; i < 3; ++i) s += report_td(cm(r.d_enu[i]));
    s += report_td(cm(r.dR)) + report_td(cm(r.sigma_m)) + "</tr>\n";
  }
  const IntersectionMeans m = intersection_means(*d.intersection);
  auto mean_cell = [&](double v) { return m.n > 0 ? fmt("%.2f", v * 100.0) : std::string(kDash); };
  s += "<tr class=\"mean\">" + report_td("mean", "txt") + report_td("") + report_td("") + report_td("");
  for (int i = 0; i < 3; ++i) s += report_td(mean_cell(m.mean_abs_d[i]));
  s += report_td(mean_cell(m.mean_dR)) + report_td(mean_cell(m.mean_sigma_m)) + "</tr>\n";
  s += "<tr class=\"mean\">" + report_td("max", "txt") + report_td("") + report_td("") + report_td("") +
       report_td("") + report_td("") + report_td("") + report_td(mean_cell(m.max_dR)) + report_td("") +
       "</tr>\n</table>\n";
  s +=
      "<p>&#916; = intersected &#8722; surveyed; mean row: mean |&#916;E|, |&#916;N|, |&#916;U|, &#916;R and "
      "&#963; over surveyed poles; &#963; = predicted 1&#963; of &#916;R (calibration covariance and pick "
      "noise).</p>\n";
  return s + plots + "</section>\n";
}

// Which calibration method ran (the verdict): the network when its adjusted track exists, else
// what the default rule or the config chose.
std::string method_sentence(const ReportData& d) {
  std::vector<std::string> methods;
  for (const CameraReportData& c : d.cameras)
    if (c.calibration && std::find(methods.begin(), methods.end(), c.calibration->method) == methods.end())
      methods.push_back(c.calibration->method);
  const std::string why = d.method_choice_why.empty() ? "" : " (" + html_escape(d.method_choice_why) + ")";
  if (d.network_track)
    return "<p class=\"method\">Calibration method: <b>network adjustment</b>, the cameras and the lamp "
           "track adjusted together" +
           why + "; its statistics and the track's corrections are in the network section below.</p>\n";
  std::string list;
  for (const std::string& m : methods) list += (list.empty() ? "" : ", ") + html_escape(m);
  if (list.empty()) list = html_escape(d.method_choice);  // no calibration.json: what the rule chose
  if (list.empty()) return "";
  const bool network = std::find(methods.begin(), methods.end(), "network") != methods.end();
  return "<p class=\"method\">Calibration method: <b>" + list + "</b>" + why +
         (network ? "; gnss/lamp_track_adjusted.csv is missing, so the network's track is not shown."
                  : "; each camera calibrated on its own, no network adjustment.") +
         "</p>\n";
}

// Where the flight volume's intersection σ stands against the network's datum floor
// (docs/accuracy_analysis.md "Datum floor"): within kDatumLimitedRatio of it the PPK fixes and control limit
// the calibration, not the images.
std::string datum_floor_sentence(const FlightVolumeSigma& v) {
  std::string s =
      "<p class=\"datum-floor\">The network's datum floor, the same prediction with every centroid and pick "
      "&#963; divided by " +
      fmt("%.0f", v.datum_floor_image_factor) +
      " (what the PPK fixes and control poles alone allow): median " +
      fmt("%.2f", v.datum_floor_stats.median * 100) + " cm; the calibration is " +
      fmt("%.2f", v.over_datum_floor) + "&#215; its floor. ";
  if (datum_limited(v))
    s += "The datum limits it, not the images: more fix epochs, or control poles surveyed better than the "
         "PPK average, would lower it; sharper centroids or more cameras would not.";
  else
    s += "The images still limit it: more epochs seen by two or more cameras, or sharper centroids, would "
         "bring it towards the floor.";
  return s + "</p>\n";
}

// The principal point's treatment per camera and what a true principal point 5 or 15 px from a fixed
// one would cost over the flight-volume slice (pipeline/report/principal_point_cost.hpp;
// docs/accuracy_analysis.md "The principal point's default").
std::string principal_point_sentence(const ReportData& d, const FlightVolumeSigma& v) {
  std::string s = "<p class=\"principal-point\">Principal point: ";
  std::vector<PrincipalPointCostCamera> cams;
  bool any_fixed = false, pairs_for_all = true;
  std::string sep;
  for (const CameraReportData& c : d.cameras) {
    if (!c.calibration) continue;
    const CalibrationResult& r = *c.calibration;
    const CameraIntrinsics& in = r.camera.intr;
    const bool fixed =
        r.parameter_index(CameraParameter::u0) < 0 && r.parameter_index(CameraParameter::v0) < 0;
    any_fixed |= fixed;
    s += sep + html_escape(c.id) +
         (fixed ? " fixed at (" + fmt("%.2f", in.u0_px) + ", " + fmt("%.2f", in.v0_px) + ") px"
                : " free, (" + fmt("%.2f", in.u0_px) + " &#177; " +
                      fmt("%.2f", r.sigma(CameraParameter::u0)) + ", " + fmt("%.2f", in.v0_px) + " &#177; " +
                      fmt("%.2f", r.sigma(CameraParameter::v0)) + ") px under its prior");
    sep = "; ";
    if (c.pairs)
      cams.push_back({&r, &*c.pairs});
    else
      pairs_for_all = false;
  }
  s += ". ";
  if (!any_fixed)
    return s + "An offset from the prior's centre is estimated and carried in the &#963; above.</p>\n";
  std::vector<Eigen::Vector3d> points;
  if (v.slice)
    for (Eigen::Index i = 0; i < v.slice->sigma_m.rows(); ++i)
      for (Eigen::Index j = 0; j < v.slice->sigma_m.cols(); ++j)
        if (std::isfinite(v.slice->sigma_m(i, j)))
          points.emplace_back(v.slice->e_m[static_cast<std::size_t>(j)],
                              v.slice->n_m[static_cast<std::size_t>(i)], v.slice->up_m);
  const double b5 =
      pairs_for_all ? principal_point_offset_bias_m(cams, points, 5, d.pixel_sigma_px) : std::nan("");
  if (!std::isfinite(b5)) return s + "</p>\n";
  return s +
         "A true principal point 5 / 15 px from a fixed one would bias the calibration-only intersection "
         "over the slice above by " +
         fmt("%.2f", b5 * 100) + " / " + fmt("%.2f", 3 * b5 * 100) +
         " cm rms (linear propagation through each camera's calibration, direction unknown), a bias the "
         "&#963; does not carry: free u<sub>0</sub>, v<sub>0</sub> under a prior unless the principal point "
         "was measured.</p>\n";
}

// Whether one of the camera's calibration warnings is of a poorly determined or correlated
// parameter (its code in run.json).
bool warns_of_weak_parameters(const CameraReportData& c) {
  for (const WarningCodeRecord& w : c.warning_codes)
    if (w.kind == CalibrationWarningKind::poorly_determined || w.kind == CalibrationWarningKind::correlated)
      return true;
  return false;
}

std::string reading_cell(const CameraVerdict& v) {
  switch (v.reading) {
    case ResidualReading::no_residuals:
      return "no lamp residuals to judge";
    case ResidualReading::as_expected:
      return "<span class=\"ok\">residuals as the noise model expects</span>";
    case ResidualReading::too_large:
      break;
  }
  // Only causes the residuals show: a clock offset when they follow the lamp's image velocity
  // (verdict.hpp kClockOffsetSignificance), never a mere trend with time, which a PPK error
  // correlated in time makes too.
  std::string causes = "with image row: lever arm or heights; ";
  causes += v.correlated_ppk
                ? "a wander with time beyond the PPK error model's &#963;<sub>g</sub>, &#964;: the "
                  "model (PPK error model section)"
                : "a slow wander with time: PPK errors correlated in time (gnss.error_model)";
  if (v.clock_offset_shown)
    causes += "; they follow the lamp's motion as a camera clock offset of " +
              fmt("%.2f", v.clock_offset_s * 1e3) +
              " ms would: add clock_offset to the camera's free set (calibrate.free, or its cameras[i].free)";
  return "<span class=\"bad\">residuals " + fmt("%.1f", v.residual_ratio) +
         "&#215; the noise model's: look at the residual plots (" + causes + ")</span>";
}

std::string verdict_table(const ReportData& d, const std::vector<CameraFigures>& figs,
                          const std::vector<CameraVerdict>& verdicts) {
  std::string s = "<table class=\"verdict\">\n<tr>" + report_th("Camera") + report_th("Method") +
                  report_th("RMS /px") + report_th("RMS expected /px") + report_th("ratio") +
                  report_th("projection &#963; at centre /px") + report_th("reading") + "</tr>\n";
  for (std::size_t i = 0; i < d.cameras.size(); ++i) {
    const CameraReportData& c = d.cameras[i];
    const CameraFigures& f = figs[i];
    s += "<tr>" + report_td(html_escape(c.id), "txt");
    if (!c.calibration) {
      s += report_td(kDash, "txt") + report_td(kDash) + report_td(kDash) + report_td(kDash) +
           report_td(kDash) +
           report_td("<span class=\"missing\">" + html_escape(status_of(c)) + "</span>", "txt") + "</tr>\n";
      continue;
    }
    s += report_td(html_escape(c.calibration->method), "txt") + report_td(fmt("%.3f", f.consistency.rms_px)) +
         report_td(fmt("%.3f", f.consistency.expected_rms_px)) +
         report_td(fmt("%.2f", verdicts[i].residual_ratio)) + report_td(fmt("%.3f", f.centre_sigma_px)) +
         report_td(reading_cell(verdicts[i]), "txt") + "</tr>\n";
  }
  return s + "</table>\n";
}

std::string check_pole_sentence(const std::optional<CheckPoleVerdict>& v, double bar_mean_dR_m) {
  if (!v)
    return "<p class=\"missing\">No check poles intersected: the calibration is not checked against an "
           "independent survey.</p>\n";
  const IntersectionMeans& m = v->means;
  return "<p class=\"" + std::string(v->met ? "ok" : "bad") + "\">Check poles (" + std::to_string(m.n) +
         "): mean &#916;R " + fmt("%.2f", m.mean_dR * 100) + " cm, max " + fmt("%.2f", m.max_dR * 100) +
         " cm, RMS " + fmt("%.2f", m.rms_dR * 100) + " cm against the predicted 1&#963; " +
         fmt("%.2f", m.mean_sigma_m * 100) + " cm (mean); bar: mean &#916;R &#8804; " +
         fmt("%.1f", bar_mean_dR_m * 100) +
         " cm (the config's intersect.bar_mean_dR_m; rangecal's quality bar is 1 cm, "
         "docs/accuracy_analysis.md): " +
         (v->met ? "met" : "NOT met") + ".</p>\n";
}

// What a camera's weak parameters mean for the intersection (judge_camera), in words.
std::string weak_parameter_paragraph(const CameraVerdict& v, const CameraFigures& f, const SliceStats& st,
                                     double bar_mean_dR_m) {
  if (v.weak == WeakParameterEffect::none) return "";
  if (v.weak == WeakParameterEffect::not_judgeable)
    return "<p>No covariance: their effect on the intersection cannot be judged.</p>\n";
  const bool small = v.weak == WeakParameterEffect::harmless;
  const double worst = f.uncertainty ? f.uncertainty->sigma_px.maxCoeff() : std::nan("");
  std::string w =
      "<p class=\"" + std::string(small ? "ok" : "bad") + "\">" +
      (small ? "Harmless for the intersection. " : "This matters for the intersection. ") +
      "What the images fix is the combination of these parameters that places a point of the flight "
      "volume; that combination is " +
      (small ? "well" : "poorly") +
      " determined: a point at the flight "
      "distance (" +
      fmt("%.1f", f.depth_m) + " m) projects with 1&#963; " + fmt("%.3f", f.centre_sigma_px) +
      " px at the image centre (up to " + fmt("%.2f", worst) +
      " px in the corners, where no lamp was seen; see the uncertainty map)";
  if (st.n > 0)
    w += ", and the predicted intersection &#963; from the calibrations is " + fmt("%.2f", st.median * 100) +
         " cm (median over the flight volume), against the bar of " + fmt("%.1f", bar_mean_dR_m * 100) +
         " cm";
  return w + ".</p>\n";
}

// Each camera's calibration warnings, then once what they mean for the intersection.
std::string verdict_warnings(const ReportData& d, const std::vector<CameraFigures>& figs,
                             const std::vector<CameraVerdict>& verdicts, const SliceStats& st) {
  std::string w;
  for (std::size_t i = 0; i < d.cameras.size(); ++i) {
    const CameraReportData& c = d.cameras[i];
    if (!c.calibration || c.calibration->warnings.empty()) continue;
    w += "<li><b>" + html_escape(c.id) + "</b>:<ul>\n";
    for (const std::string& x : c.calibration->warnings)
      w += "<li class=\"warn\">" + html_escape(x) + "</li>\n";
    w += "</ul>\n" + weak_parameter_paragraph(verdicts[i], figs[i], st, d.bar_mean_dR_m) + "</li>\n";
  }
  if (w.empty()) return "";
  return "<h3>Calibration warnings and what they mean</h3>\n<ul class=\"verdict-warnings\">\n" + w +
         "</ul>\n";
}

std::string verdict_section(const ReportData& d, const std::vector<CameraFigures>& figs,
                            const FlightVolumeSigma& volume) {
  const SliceStats& st = volume.stats;
  std::vector<CameraVerdict> verdicts(d.cameras.size());
  for (std::size_t i = 0; i < d.cameras.size(); ++i)
    if (d.cameras[i].calibration)
      verdicts[i] =
          judge_camera({figs[i].consistency, figs[i].centre_sigma_px, warns_of_weak_parameters(d.cameras[i]),
                        figs[i].clock, d.cameras[i].ppk_model && d.cameras[i].ppk_model->correlated()},
                       st, d.bar_mean_dR_m);
  std::string s = "<section id=\"verdict\">\n<h2>Verdict</h2>\n" + verdict_table(d, figs, verdicts) +
                  method_sentence(d) +
                  check_pole_sentence(judge_check_poles(d.intersection, d.bar_mean_dR_m), d.bar_mean_dR_m);
  if (st.n > 0)
    s += "<p>Predicted intersection &#963; from the calibrations alone over the flight volume at U = " +
         fmt("%.1f", volume.slice->up_m) + " m: " + fmt("%.2f", st.min * 100) + "&#8211;" +
         fmt("%.2f", st.max * 100) + " cm (median " + fmt("%.2f", st.median * 100) + " cm).</p>\n";
  if (st.n > 0 && std::isfinite(volume.over_datum_floor)) s += datum_floor_sentence(volume);
  if (st.n > 0) s += principal_point_sentence(d, volume);
  s += verdict_warnings(d, figs, verdicts, st);
  return s + "</section>\n";
}

std::string site_section(const ReportData& d, const std::vector<CameraFigures>& figs) {
  std::string s = "<section id=\"site-map\">\n<h2>Site map</h2>\n";
  SiteMap m;
  for (std::size_t i = 0; i < d.cameras.size(); ++i) {
    const CameraReportData& c = d.cameras[i];
    if (!c.calibration) continue;
    const Camera& cam = c.calibration->camera;
    SiteCamera sc;
    sc.id = c.id;
    sc.center = cam.pose.center();
    sc.center_cov_m2 = c.calibration->center_covariance_m2;
    sc.left_ray = pixel_ray_world(cam, Eigen::Vector2d(-0.5, (cam.intr.height_px - 1) / 2.0));
    sc.right_ray =
        pixel_ray_world(cam, Eigen::Vector2d(cam.intr.width_px - 0.5, (cam.intr.height_px - 1) / 2.0));
    double reach = 0;
    if (c.pairs)
      for (const Correspondence& p : *c.pairs)
        reach = std::max(reach, Eigen::Vector2d(p.enu.x() - sc.center.x(), p.enu.y() - sc.center.y()).norm());
    sc.wedge_m = reach > 0 ? 1.15 * reach : (std::isfinite(figs[i].depth_m) ? figs[i].depth_m : 10.0);
    m.cameras.push_back(sc);
    if (c.pairs)
      for (std::size_t k = 0; k < figs[i].res.size() && k < c.pairs->size(); ++k)
        if (!figs[i].res[k].used) m.outliers.push_back((*c.pairs)[k].enu);
  }
  if (d.lamp_track)
    for (const LampEpoch& e : d.lamp_track->epochs) {
      m.track.push_back(e.enu);
      m.track_t_s.push_back(seconds_between(d.lamp_track->epochs.front().utc, e.utc));
    }
  for (const SurveyedPole& p : d.survey) {
    SitePole sp;
    sp.id = p.id;
    sp.check = p.role == PoleRole::check;
    sp.enu = p.enu;
    m.poles.push_back(sp);
  }
  if (d.intersection)
    for (const IntersectionRow& r : *d.intersection) {
      SitePole* hit = nullptr;
      for (SitePole& sp : m.poles)
        if (sp.id == r.id) hit = &sp;
      if (!hit) {
        m.poles.push_back(SitePole{r.id, true, r.survey_enu, false, Eigen::Vector3d::Zero(), 0});
        hit = &m.poles.back();
      }
      hit->has_error = true;
      hit->d_enu = r.d_enu;
      hit->sigma_m = r.sigma_m;
    }
  if (m.cameras.empty() && m.track.empty() && m.poles.empty())
    return s + "<p class=\"missing\">Nothing to map: no calibration, lamp track or survey.</p>\n</section>\n";
  s += figure(
      svg_site_plan(m, "site-plan"),
      "Plan view: cameras with viewing wedges (image width) and 1&#963; centre ellipses, the lamp track "
      "coloured by time, poles; check-pole errors and their predicted &#963; magnified");
  s += figure(svg_site_side(m, "site-side"), "Side view: distance against height");
  return s + "</section>\n";
}

std::string funnel_section(const ReportData& d) {
  std::vector<std::string> ids;
  for (const CameraReportData& c : d.cameras) ids.push_back(c.id);
  const std::vector<FunnelRow> rows = data_funnel(d.run_stages, ids);
  std::string s = "<section id=\"funnel\">\n<h2>Data funnel</h2>\n";
  if (rows.empty()) return s + "<p class=\"missing\">run.json has no stage counts.</p>\n</section>\n";
  s += "<table class=\"funnel\">\n<tr>" + report_th("Stage") + report_th("Camera") + report_th("Counted") +
       report_th("In") + report_th("Kept") + report_th("Dropped") + report_th("Why") + "</tr>\n";
  for (const FunnelRow& r : rows) {
    std::string why;
    for (const FunnelDrop& x : r.dropped)
      why += (why.empty() ? "" : "; ") + html_escape(x.reason) + ": " + std::to_string(x.count);
    s += "<tr>" + report_td(html_escape(r.stage), "txt") +
         report_td(r.camera.empty() ? kDash : html_escape(r.camera), "txt") +
         report_td(html_escape(r.unit), "txt") + report_td(std::to_string(r.in)) +
         report_td(std::to_string(r.kept)) + report_td(std::to_string(r.in - r.kept)) +
         report_td(why.empty() ? kDash : why, "txt") + "</tr>\n";
  }
  s += "</table>\n";
  s += figure(svg_funnel(rows, "funnel-bars"),
              "Share kept (green) and dropped by reason (other colours) per stage");
  if (const std::optional<AttitudeTiming> timing = attitude_timing(d.run_stages))
    s += "<p class=\"attitude-timing\">" + html_escape(attitude_timing_sentence(*timing)) + "</p>\n";
  return s + "</section>\n";
}

std::string intersection_plots(const ReportData& d, const std::optional<IntersectionSigmaSlice>& slice) {
  std::string s;
  const std::vector<const CalibrationResult*> cams = calibrated_cameras(d);
  if (d.intersection && !d.intersection->empty()) {
    std::vector<std::string> ids;
    std::vector<Eigen::Vector3d> dcm, scm;
    for (const IntersectionRow& r : *d.intersection) {
      ids.push_back(r.id);
      dcm.push_back(r.d_enu * 100.0);
      const PredictedIntersection p =
          predict_intersection(cams, r.survey_enu, d.pick_sigma_px, network_cross_or_null(d));
      scm.push_back(
          p.n_cameras >= 2
              ? Eigen::Vector3d((p.cov_calibration_m2 + p.cov_pick_m2).diagonal().cwiseSqrt() * 100.0)
              : Eigen::Vector3d::Constant(std::nan("")));
    }
    s += figure(svg_pole_bars(ids, dcm, scm, "intersection-bars"),
                "Per check pole: &#916;E, &#916;N, &#916;U (cm) over the predicted &#177;1&#963; per axis "
                "(calibration covariances of the cameras that see the pole, and pick noise " +
                    fmt("%.2f", d.pick_sigma_px) + " px)");
  }
  if (slice) {
    std::vector<Eigen::Vector2d> poles;
    if (d.intersection)
      for (const IntersectionRow& r : *d.intersection) poles.emplace_back(r.survey_enu.x(), r.survey_enu.y());
    s += figure(
        svg_slice_map(*slice, poles, "intersection-slice"),
        "Predicted intersection &#963; (&#8730;trace of the covariance, cm) from the calibrations alone "
        "over a horizontal slice at the check poles' height: what a target flown through the calibrated "
        "volume can expect before pick noise");
  }
  return s;
}

// The largest correction component over the epochs whose fix was kept (a flagged epoch's
// correction is its PPK error, shown in its own table).
struct LargestCorrection {
  const LampTrackAdjustedRow* row = nullptr;
  int axis = 0;
};
LargestCorrection largest_kept_correction(const std::vector<LampTrackAdjustedRow>& rows) {
  LargestCorrection m;
  for (const LampTrackAdjustedRow& r : rows)
    for (int i = 0; i < 3; ++i)
      if (!r.flagged && (!m.row || std::abs(r.correction[i]) > std::abs(m.row->correction[m.axis])))
        m.row = &r, m.axis = i;
  return m;
}

// What the variance factor says: χ²/dof of a model whose σ are right has mean 1 and sd √(2/dof);
// within 3 sd it is read as agreeing (docs/optimisation.md: the σ are a-priori, not scaled).
std::string variance_factor_reading(const NetworkStatisticsRecord& st) {
  const double f = st.variance_factor;
  if (!std::isfinite(f) || st.dof <= 0) return "No redundancy: the variance factor cannot be computed.";
  const double sd = std::sqrt(2.0 / static_cast<double>(st.dof));
  if (std::abs(f - 1) <= 3 * sd)
    return "<span class=\"ok\">The variance factor is within its expected 1 &#177; " + fmt("%.3f", sd) +
           " (&#8730;(2/dof)): the residuals are as large as the assumed noise (lamp centroid &#963; and PPK "
           "sd) predicts, so the &#963; below are realistic.</span>";
  if (f > 1)
    return "<span class=\"bad\">The variance factor is " + fmt("%.2f", f) + ", above its expected 1 &#177; " +
           fmt("%.3f", sd) +
           ": the residuals are larger than the assumed noise; the &#963; below (a-priori, not scaled) are "
           "optimistic by about &#8730;" +
           fmt("%.2f", f) + " = " + fmt("%.2f", std::sqrt(f)) +
           "&#215;. Look at the residual plots and the flagged epochs.</span>";
  return "<span class=\"warn\">The variance factor is " + fmt("%.2f", f) + ", below its expected 1 &#177; " +
         fmt("%.3f", sd) +
         ": the residuals are smaller than the assumed noise, so the &#963; below are conservative.</span>";
}

// The network statistics (run.json stages.calibrate.counts.network) and what they mean.
std::string network_statistics_table(const NetworkStatisticsRecord& st, std::size_t rows) {
  std::string s = "<table class=\"network-stats\">\n";
  auto row = [&](const std::string& k, const std::string& v, const std::string& note) {
    s += "<tr>" + report_th(k) + report_td(v) + report_td(note, "txt") + "</tr>\n";
  };
  row("variance factor &#967;&#178;/dof", fmt("%.3f", st.variance_factor),
      "should be &#8776; 1 (&#967;&#178; " + fmt("%.1f", st.chi2) + ", dof " + std::to_string(st.dof) + ")");
  row("epochs in the adjusted track", std::to_string(rows), "rows of gnss/lamp_track_adjusted.csv");
  row("seen by 1 camera", std::to_string(st.epochs_seen_by_1), "enter as in the per-camera bundle");
  row("seen by 2 cameras", std::to_string(st.epochs_seen_by_2), "tie the cameras together");
  row("seen by &#8805; 3 cameras", std::to_string(st.epochs_seen_by_3_or_more), "tie the cameras together");
  row("PPK epochs flagged", std::to_string(st.ppk_outliers.size()),
      "fix disagrees with the rays: its prior dropped");
  if (st.float_epochs_used > 0)
    row("float epochs used", std::to_string(st.float_epochs_used), "PPK quality 2, with their own sd");
  row("image outliers", std::to_string(st.image_outliers), "lamp observations left out");
  s += "</table>\n";
  const long tied = st.epochs_seen_by_2 + st.epochs_seen_by_3_or_more;
  s +=
      "<p>" + variance_factor_reading(st) + " " + std::to_string(tied) +
      " epochs were seen by two or more cameras: at each of them the cameras must agree on one lamp "
      "position, which is what ties their relative geometry together; " +
      std::to_string(st.epochs_seen_by_1) +
      " seen by one camera add to that camera alone, as in its own bundle. " +
      (st.ppk_outliers.empty()
           ? std::string("No PPK fix was flagged.")
           : std::to_string(st.ppk_outliers.size()) +
                 " PPK fixes disagreed with what the cameras saw beyond the whitened &#967;&#178; test "
                 "(&#945; = 10<sup>&#8722;4</sup>): their priors were dropped, and those lamp positions come "
                 "from the rays alone.") +
      "</p>\n";
  if (!st.cameras_alone.empty()) {
    std::string ids;
    for (const std::string& c : st.cameras_alone) ids += (ids.empty() ? "" : ", ") + html_escape(c);
    s += "<p class=\"warn\">Sharing no epoch with another camera (calibrated from their own epochs alone): " +
         ids + ".</p>\n";
  }
  if (st.rank_deficient)
    s += "<p class=\"bad\">The network is rank-deficient: no joint covariance (see the calibrate stage's "
         "warnings).</p>\n";
  return s;
}

// What the float epochs add (network.json float_epochs): per camera and parameter the a-priori σ
// with them and without them, and the ratio.
std::string float_epochs_table(const FloatEpochsRecord& f) {
  std::string s =
      "<h3>What the " + std::to_string(f.epochs) +
      " float epochs add</h3>\n<p>PPK float epochs (quality 2, accepted by gnss.accept_quality) "
      "enter with their own, larger &#963;. Below, each camera's 1&#963; with them and without them "
      "(the covariance at the same solution with their fixes and image observations left out): a "
      "ratio near 1 says they add little.</p>\n<table class=\"float-epochs\">\n<tr>" +
      report_th("Camera") + report_th("Parameter") + report_th("1&#963; with") +
      report_th("1&#963; without") + report_th("without / with") + report_th("Unit") + "</tr>\n";
  for (const FloatEpochsRecord::Camera& c : f.cameras)
    for (std::size_t i = 0; i < c.parameters.size() && i < c.sigma_with.size(); ++i) {
      const bool has = i < c.sigma_without.size();
      s += "<tr>" + report_td(html_escape(c.id), "txt") + report_td(parameter_name(c.parameters[i]), "txt") +
           report_td(fmt("%.4g", c.sigma_with[i])) +
           report_td(has ? fmt("%.4g", c.sigma_without[i]) : "undetermined") +
           report_td(has && c.sigma_with[i] > 0 ? fmt("%.3f", c.sigma_without[i] / c.sigma_with[i]) : kDash) +
           report_td(parameter_unit(c.parameters[i]), "txt") + "</tr>\n";
    }
  return s + "</table>\n";
}

// The network section (docs/outputs.md): statistics, the corrections per axis against time over
// the adjusted position's ±1σ with the flagged epochs marked, and the flagged epochs' list.
std::string network_section(const ReportData& d) {
  if (!d.network_track) return "";
  const std::vector<LampTrackAdjustedRow>& rows = *d.network_track;
  std::string s =
      "<section id=\"network\">\n<h2>Network adjustment</h2>\n<p>The cameras and the lamp track were "
      "adjusted together (docs/optimisation.md, \"Network bundle\"): each lamp epoch is one point seen by "
      "the cameras, held by its PPK fix with the fix's own &#963;; the correction is adjusted &#8722; PPK "
      "fix.</p>\n";
  if (d.network_statistics)
    s += network_statistics_table(*d.network_statistics, rows.size());
  else
    s += "<p class=\"missing\">run.json has no network statistics (stages.calibrate.counts.network).</p>\n";
  if (d.network_float_epochs && d.network_float_epochs->epochs > 0)
    s += float_epochs_table(*d.network_float_epochs);
  if (rows.empty()) return s + "<p class=\"missing\">The adjusted track has no epochs.</p>\n</section>\n";

  const LargestCorrection big = largest_kept_correction(rows);
  if (big.row)
    s += "<p>Largest correction of a kept fix: &#916;" + std::string(1, "ENU"[big.axis]) + " " +
         fmt("%.2f", big.row->correction[big.axis] * 100) + " cm at " + format_iso8601_utc(big.row->utc, 3) +
         " (&#963; of the adjusted position " + fmt("%.2f", big.row->sd_enu[big.axis] * 100) + " cm).</p>\n";
  // What the corrections are measured against: the PPK fixes' own sd (the corrections' expected size
  // where the fix is sound); the band is the adjusted position's σ.
  if (d.lamp_track && !d.lamp_track->epochs.empty()) {
    Eigen::Vector3d median_sd;
    for (int i = 0; i < 3; ++i) {
      std::vector<double> sd;
      for (const LampEpoch& e : d.lamp_track->epochs) sd.push_back(e.sd_enu[i]);
      std::nth_element(sd.begin(), sd.begin() + static_cast<std::ptrdiff_t>(sd.size() / 2), sd.end());
      median_sd[i] = sd[sd.size() / 2];
    }
    s += "<p>The PPK fixes' own sd (gnss/lamp_track.csv, median) is " + fmt("%.2f", median_sd.x() * 100) +
         " / " + fmt("%.2f", median_sd.y() * 100) + " / " + fmt("%.2f", median_sd.z() * 100) +
         " cm in E / N / U: corrections of about that size are the PPK noise the network took out. The "
         "band in each chart is &#177;1&#963; of the adjusted position: how well the cameras and the fix "
         "together place each epoch.</p>\n";
  }
  std::vector<double> t;
  std::vector<bool> flagged;
  for (const LampTrackAdjustedRow& r : rows) {
    t.push_back(seconds_between(rows.front().utc, r.utc));
    flagged.push_back(r.flagged);
  }
  for (int i = 0; i < 3; ++i) {
    std::vector<double> dcm, scm;
    for (const LampTrackAdjustedRow& r : rows) {
      dcm.push_back(r.correction[i] * 100);
      scm.push_back(r.sd_enu[i] * 100);
    }
    const std::string axis(1, "ENU"[i]);
    s += figure(
        svg_correction_series(t, dcm, scm, flagged, "d" + axis + " (cm), adjusted − PPK",
                              std::string("network-d") + "ENU"[i],
                              "Lamp-track correction d" + axis + " against time"),
        "&#916;" + axis +
            " correction per epoch (cm); band: &#177;1&#963; of the adjusted position; red &#215;: flagged "
            "PPK epochs");
  }
  std::size_t n_flagged = 0;
  for (const LampTrackAdjustedRow& r : rows) n_flagged += r.flagged;
  s += "<h3>Flagged PPK epochs (" + std::to_string(n_flagged) + ")</h3>\n";
  if (n_flagged == 0) return s + "<p>None.</p>\n</section>\n";
  s += "<table class=\"flagged\">\n<tr>" + report_th("UTC") + report_th("t /s") + report_th("&#916;E /cm") +
       report_th("&#916;N /cm") + report_th("&#916;U /cm") + report_th("|&#916;| /cm") + "</tr>\n";
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const LampTrackAdjustedRow& r = rows[k];
    if (!r.flagged) continue;
    s += "<tr>" + report_td(format_iso8601_utc(r.utc, 3), "txt") + report_td(fmt("%.3f", t[k]));
    for (int i = 0; i < 3; ++i) s += report_td(fmt("%.2f", r.correction[i] * 100));
    s += report_td(fmt("%.2f", r.correction.norm() * 100)) + "</tr>\n";
  }
  return s +
         "</table>\n<p>The correction of a flagged epoch is how far its PPK fix lay from where the "
         "cameras put the lamp.</p>\n</section>\n";
}

// A partial or degraded mission says so before anything else (docs/reliability.md "Run outcome"): what
// the stages could not deliver or delivered degraded, as run.json's outcome lists it. Nothing for a
// complete one.
std::string outcome_banner(const ReportData& d) {
  const RunOutcome outcome = run_outcome(nlohmann::json{{"stages", d.run_stages}});
  if (outcome.status == "complete") return "";
  std::string s =
      "<p class=\"bad\">This mission is " + outcome.status + " (exit " + std::to_string(outcome.exit_code) +
      "): " +
      (outcome.status == "degraded" ? "its outputs are complete, but look at these before trusting them"
                                    : "its outputs are kept but incomplete") +
      ".</p>\n<ul>\n";
  for (const std::string& r : outcome.reasons) s += "<li>" + html_escape(r) + "</li>\n";
  return s + "</ul>\n";
}

}  // namespace

std::string render_report_html(const ReportData& d, const FlightVolumeSigma& volume) {
  std::vector<CameraFigures> figs;
  for (const CameraReportData& c : d.cameras) figs.push_back(camera_figures(c, d.pixel_sigma_px));
  std::string s =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>rangecal report: " +
      html_escape(d.mission) + "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n";
  s += "<h1>rangecal calibration report</h1>\n";
  s += outcome_banner(d);
  s += verdict_section(d, figs, volume);
  s += mission_section(d);
  s += overview_section(d);
  s += site_section(d, figs);
  for (std::size_t i = 0; i < d.cameras.size(); ++i) s += camera_section(d.cameras[i], figs[i]);
  s += intersection_section(d, intersection_plots(d, volume.slice));
  s += funnel_section(d);
  s += network_section(d);
  s += ppk_error_model_section(d);
  s += trajectory_section(d);
  s += "</body>\n</html>\n";
  return s;
}

}  // namespace rangecal
