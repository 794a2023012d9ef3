// The report stage (docs/outputs.md): an output folder built from synthetic data with the project's
// own writers → summary.json numbers equal the inputs', report.html has the tables and one <svg>
// per plot, reruns are byte-identical, a camera without calibration is reported (not an error), a
// malformed input names file and line, the network section draws the adjusted track and run.json's
// statistics, the verdict holds the check poles to the configured bar, and a headless browser
// renders the page.
#include "pipeline/stages/report_stage.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <regex>
#include <sstream>

#include "config/error.hpp"
#include "gnss/formats/lamp_track_csv.hpp"
#include "optim/network/network_options.hpp"
#include "pipeline/io/calibrate_record.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/io/methods_csv.hpp"
#include "pipeline/io/network_json.hpp"
#include "pipeline/io/residuals_csv.hpp"
#include "pipeline/report/correction_autocorrelation.hpp"
#include "pipeline/report/report_html.hpp"
#include "pipeline/report/svg_plot.hpp"
#include "pipeline/stages/calibrate_stage.hpp"
#include "support/paths.hpp"
#include "support/report_output.hpp"
#include "support/synthetic_camera.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;

std::size_t count(const std::string& hay, const std::string& needle) {
  std::size_t n = 0;
  for (std::size_t p = hay.find(needle); p != std::string::npos; p = hay.find(needle, p + needle.size())) ++n;
  return n;
}

std::string td_num(const std::string& v) {
  return "<td class=\"num\">" + v + "</td>";
}

using test::adjusted_utc;
using test::AdjustedEpoch;
using test::fixed;
using test::kAdjusted;
using test::kPoles;
using test::network_counts;
using test::Pole;
using test::pole_dr;
using test::read_json;
using Fixture = test::ReportOutput;

test::ReportOutput build_output(const fs::path& dir, bool with_intersection = true,
                                bool with_network = false) {
  return test::write_report_output(dir, with_intersection, with_network);
}

TEST(Report, SummaryNumbersEqualTheInputs) {
  const fs::path dir = test::scratch_dir("report_summary");
  const Fixture fx = build_output(dir);
  run_report_stage(fx.cfg);
  const nlohmann::json s = read_json(dir / "out/summary.json");
  const nlohmann::json& c1 = s["cameras"]["cam1"];
  EXPECT_EQ(c1["calibrated"], true);
  EXPECT_EQ(c1["method"], "bundle");
  EXPECT_EQ(c1["rms_px"].get<double>(), 0.2137);
  EXPECT_EQ(c1["n_used"].get<int>(), static_cast<int>(fx.cam1_pairs - fx.cam1_rejected));
  EXPECT_EQ(c1["n_rejected"].get<int>(), 2);
  const nlohmann::json& c2 = s["cameras"]["cam2"];
  EXPECT_EQ(c2["calibrated"], false);
  EXPECT_TRUE(c2["rms_px"].is_null());
  EXPECT_TRUE(c2["n_used"].is_null());
  EXPECT_EQ(c2["failure"], "points on one line <degenerate>");

  // Mean and max ΔR computed here from the poles' components (written to 1e-6 m in the CSV).
  double sum = 0, mx = 0;
  for (const Pole& p : kPoles) {
    const double dr = std::round(pole_dr(p) * 1e6) / 1e6;
    sum += dr;
    mx = std::max(mx, dr);
  }
  EXPECT_EQ(s["intersection"]["n_poles"].get<int>(), 3);
  EXPECT_NEAR(s["intersection"]["mean_dR_m"].get<double>(), sum / 3, 1e-12);
  EXPECT_NEAR(s["intersection"]["max_dR_m"].get<double>(), mx, 1e-12);
  EXPECT_GT(mx, 0.02);  // A2's ΔR ≈ 2.16 cm is the largest
  // One calibrated camera: no intersection to predict.
  for (const char* k :
       {"slice_up_m", "median_sigma_m", "max_sigma_m", "datum_floor_median_sigma_m", "over_datum_floor"})
    EXPECT_TRUE(s["prediction"][k].is_null()) << k;
}

TEST(Report, WithoutIntersectionCsvTheSummarySaysNull) {
  const fs::path dir = test::scratch_dir("report_no_intersection");
  const Fixture fx = build_output(dir, /*with_intersection=*/false);
  const StageLog log = run_report_stage(fx.cfg);
  const nlohmann::json s = read_json(dir / "out/summary.json");
  EXPECT_TRUE(s["intersection"]["mean_dR_m"].is_null());
  EXPECT_TRUE(s["intersection"]["max_dR_m"].is_null());
  EXPECT_EQ(s["intersection"]["n_poles"].get<int>(), 0);
  const std::string html = test::read_text(dir / "out/report.html");
  EXPECT_NE(html.find("intersection.csv missing"), std::string::npos);
  EXPECT_FALSE(log.warnings.empty());
}

TEST(Report, HtmlHasTheTablesPlotsAndEscapedText) {
  const fs::path dir = test::scratch_dir("report_html");
  const Fixture fx = build_output(dir);
  run_report_stage(fx.cfg);
  const std::string html = test::read_text(dir / "out/report.html");
  // Self-contained: no scripts, no external resources.
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("src="), std::string::npos);
  EXPECT_EQ(html.find("href="), std::string::npos);
  // Text from files is escaped.
  EXPECT_NE(html.find("Range 3 &lt;night&gt; &amp; &quot;dawn&quot; flights"), std::string::npos);
  EXPECT_EQ(html.find("<night>"), std::string::npos);
  EXPECT_EQ(html.find("<degenerate>"), std::string::npos);
  EXPECT_NE(html.find("f and Tz correlated &lt;0.995&gt;"), std::string::npos);

  // Parameters with 1σ from calibration.json.
  EXPECT_NE(html.find(fixed("%.4f", fx.cal.camera.intr.f_mm)), std::string::npos);
  EXPECT_NE(html.find(">0.0123<"), std::string::npos);    // σf
  EXPECT_NE(html.find(">2.50e-06<"), std::string::npos);  // σk1
  // Tables 2–3 headline row and methods table (Table 1) with both methods.
  EXPECT_NE(html.find("<td class=\"num\">0.214</td><td class=\"num\">0.188</td><td class=\"num\">0.654</td>"),
            std::string::npos);
  EXPECT_NE(html.find("<th>bundle</th><th>tsai</th>"), std::string::npos);
  EXPECT_NE(html.find(">132.430<"), std::string::npos);
  EXPECT_NE(html.find(">0.990<"), std::string::npos);
  // Table 4: every pole, its ΔR in cm, and the mean row.
  double sum = 0;
  for (const Pole& p : kPoles) {
    EXPECT_NE(html.find(">" + std::string(p.id) + "<"), std::string::npos) << p.id;
    EXPECT_NE(html.find(">" + fixed("%.2f", pole_dr(p) * 100) + "<"), std::string::npos) << p.id;
    sum += pole_dr(p);
  }
  EXPECT_NE(html.find("<td class=\"num\">" + fixed("%.2f", sum / 3 * 100) + "</td>"), std::string::npos);

  // One <svg> per plot: cam1 has ten (track, residual vectors, histogram, four residual plots,
  // uncertainty, distortion, correlation); cam2 (not calibrated) only its lamp track; the site plan
  // and side view; the check-pole bars (no slice: one calibrated camera; no funnel: no counts).
  EXPECT_EQ(count(html, "<svg"), 14u);
  EXPECT_NE(html.find("id=\"cam-cam1-track\""), std::string::npos);
  EXPECT_NE(html.find("id=\"cam-cam1-residuals\""), std::string::npos);
  EXPECT_NE(html.find("id=\"cam-cam1-histogram\""), std::string::npos);
  EXPECT_NE(html.find("id=\"cam-cam2-track\""), std::string::npos);
  // Fig. 6: every pair drawn (both cameras), rejected ones apart (only the calibrated cam1 has
  // residuals.csv, which says which were rejected); reprojections only for cam1.
  EXPECT_EQ(count(html, "<circle class=\"obs\"") + count(html, "<circle class=\"rejected\""),
            2 * fx.cam1_pairs);
  EXPECT_EQ(count(html, "<circle class=\"rejected\""), fx.cam1_rejected);
  EXPECT_EQ(count(html, "<path class=\"proj\""), fx.cam1_pairs);
  EXPECT_EQ(count(html, "<line class=\"resid\""), fx.cam1_pairs);
  EXPECT_GE(fx.cam1_segments, 4u);  // three ascents and the poles
  EXPECT_EQ(count(html, "<polyline class=\"track\""), 2 * fx.cam1_segments);
  // The histogram counts the used points.
  EXPECT_NE(html.find("(" + std::to_string(fx.cam1_pairs - fx.cam1_rejected) + " values;"),
            std::string::npos);
}

// The verdict reads what a calibration warning is about from its code in run.json
// (stages.calibrate.counts.cameras.<cam>.warnings), never from its words: cam1's warning says
// "correlated", but only once run.json codes it so does the verdict say what it means.
TEST(Report, WeakParametersAreKnownByTheirCodeNotTheirText) {
  const fs::path dir = test::scratch_dir("report_warning_codes");
  const Fixture fx = build_output(dir);
  const std::string meaning = "<p class=\"ok\">Harmless for the intersection. ";
  run_report_stage(fx.cfg);
  const std::string uncoded = test::read_text(dir / "out/report.html");
  EXPECT_NE(uncoded.find("f and Tz correlated &lt;0.995&gt;"), std::string::npos);
  EXPECT_EQ(uncoded.find("for the intersection. "), std::string::npos);

  CalibrateRecord record;
  record.cameras["cam2"].failed = "points on one line <degenerate>";
  CalibrateCameraRecord& cam1 = record.cameras["cam1"];
  cam1.method = "bundle";
  cam1.warnings = {{CalibrationWarningKind::correlated, "cam1", {CameraParameter::f, CameraParameter::k1}}};
  StageLog cal;
  cal.stage = "calibrate";
  cal.counts = calibrate_record_json(record);
  update_run_log(fx.cfg, cal);
  run_report_stage(fx.cfg);
  const std::string coded = test::read_text(dir / "out/report.html");
  // One calibrated camera, no flight-volume slice: its centre σ (well under 0.5 px) decides.
  EXPECT_EQ(count(coded, meaning), 1u);

  // Coded as another kind, the same words again say nothing about the intersection.
  cam1.warnings = {{CalibrationWarningKind::variance_factor, "cam1", {}}};
  cal.counts = calibrate_record_json(record);
  update_run_log(fx.cfg, cal);
  run_report_stage(fx.cfg);
  EXPECT_EQ(test::read_text(dir / "out/report.html").find("for the intersection. "), std::string::npos);
}

TEST(Report, ByteIdenticalOnRerun) {
  const fs::path dir = test::scratch_dir("report_rerun");
  const Fixture fx = build_output(dir);
  update_run_log(fx.cfg, run_report_stage(fx.cfg));
  const std::string html = test::read_text(dir / "out/report.html");
  const std::string summary = test::read_text(dir / "out/summary.json");
  // The second run sees run.json with the first report's own section: still the same bytes.
  update_run_log(fx.cfg, run_report_stage(fx.cfg));
  EXPECT_EQ(test::read_text(dir / "out/report.html"), html);
  EXPECT_EQ(test::read_text(dir / "out/summary.json"), summary);
}

TEST(Report, MissingCalibrationIsReportedNotAnError) {
  const fs::path dir = test::scratch_dir("report_missing_cal");
  const Fixture fx = build_output(dir);
  const StageLog log = run_report_stage(fx.cfg);
  const std::string html = test::read_text(dir / "out/report.html");
  EXPECT_NE(html.find("cam2: calibration failed: points on one line &lt;degenerate&gt;"), std::string::npos);
  bool warned = false;
  for (const auto& w : log.warnings) warned |= w.rfind("cam2:", 0) == 0;
  EXPECT_TRUE(warned);
  EXPECT_EQ(log.counts["calibrated"].get<int>(), 1);

  // Without run.json's reason and without any cam1 file either: still written, saying so.
  fs::remove(dir / "out/run.json");
  fs::remove_all(dir / "out/cam1");
  run_report_stage(fx.cfg);
  const std::string html2 = test::read_text(dir / "out/report.html");
  EXPECT_NE(html2.find("cam1: not calibrated (calibration.json missing)"), std::string::npos);
  EXPECT_NE(html2.find("correspondences.csv missing"), std::string::npos);
  const nlohmann::json s = read_json(dir / "out/summary.json");
  EXPECT_EQ(s["cameras"]["cam1"]["calibrated"], false);
}

TEST(Report, MalformedCorrespondencesNameFileAndLine) {
  const fs::path dir = test::scratch_dir("report_malformed");
  const Fixture fx = build_output(dir);
  const fs::path corr = dir / "out/cam1/correspondences.csv";
  std::string text = test::read_text(corr);
  // Line 4 (header is line 1): its u becomes text.
  std::size_t start = 0;
  for (int i = 0; i < 3; ++i) start = text.find('\n', start) + 1;
  std::size_t comma = start;
  for (int i = 0; i < 4; ++i) comma = text.find(',', comma) + 1;  // after utc,E,N,U
  text.replace(comma, text.find(',', comma) - comma, "12x.5");
  test::write_text(corr, text);
  try {
    run_report_stage(fx.cfg);
    FAIL() << "a malformed correspondences.csv was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.exit_code(), 3);
    EXPECT_EQ(e.file(), corr.string());
    EXPECT_EQ(e.line(), 4);
    EXPECT_NE(std::string(e.what()).find("correspondences.csv:4"), std::string::npos) << e.what();
  }
}

TEST(Report, MalformedIntersectionCsvNamesFileLineAndField) {
  const fs::path dir = test::scratch_dir("report_bad_intersection");
  const Fixture fx = build_output(dir);
  test::write_text(
      dir / "out/intersection.csv",
      "id,E,N,U,E_survey,N_survey,U_survey,dE,dN,dU,dR,sigma_m\nA1,1,2,3,1,2,3,0,0,0,-0.5,0.01\n");
  try {
    run_report_stage(fx.cfg);
    FAIL() << "a negative dR was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.exit_code(), 3);
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.field(), "dR");
  }
}

// ---- network section ---------------------------------------------------------------------------

// The svg with id `id` in `page`.
std::string svg_by_id(const std::string& page, const std::string& id) {
  const std::size_t a = page.find("<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"" + id + "\"");
  if (a == std::string::npos) return "";
  return page.substr(a, page.find("</svg>", a) - a);
}

// Data → drawing map of one axis, recovered from two of its tick labels (value, drawing coordinate).
struct AxisMap {
  double v0 = 0, c0 = 0, v1 = 1, c1 = 1;
  double value(double c) const { return v0 + (c - c0) * (v1 - v0) / (c1 - c0); }
  double per_unit() const { return std::abs((v1 - v0) / (c1 - c0)); }
};
AxisMap axis_from_ticks(const std::string& svg, bool y_axis) {
  // svg_axes: x ticks "<text x=X(v) y=… text-anchor=middle>v", y ticks "<text x=… y=Y(v)+3.5
  // text-anchor=end>v".
  const std::regex re(y_axis ? R"re(<text x="[^"]+" y="([^"]+)" text-anchor="end">([^<]+)</text>)re"
                             : R"re(<text x="([^"]+)" y="[^"]+" text-anchor="middle">([^<]+)</text>)re");
  std::vector<std::pair<double, double>> ticks;  // (value, coordinate)
  for (std::sregex_iterator it(svg.begin(), svg.end(), re), end; it != end; ++it)
    ticks.emplace_back(std::stod((*it)[2]), std::stod((*it)[1]) - (y_axis ? 3.5 : 0.0));
  AxisMap m;
  EXPECT_GE(ticks.size(), 2u);
  if (ticks.size() < 2) return m;
  m.v0 = ticks.front().first, m.c0 = ticks.front().second;
  m.v1 = ticks.back().first, m.c1 = ticks.back().second;
  return m;
}

TEST(Report, NetworkSectionDrawsTheAdjustedTrackAndRunJsonStatistics) {
  const fs::path dir = test::scratch_dir("report_network");
  Fixture fx = build_output(dir, true, /*with_network=*/true);
  run_report_stage(fx.cfg);
  const std::string html = test::read_text(dir / "out/report.html");
  const std::size_t sec = html.find("<section id=\"network\">");
  ASSERT_NE(sec, std::string::npos);
  EXPECT_NE(html.find("<h2>Network adjustment</h2>", sec), std::string::npos);
  // The verdict names the method that ran and the default rule's reason.
  const std::string verdict = html.substr(0, html.find("</section>"));
  EXPECT_NE(verdict.find("<b>network adjustment</b>"), std::string::npos);
  EXPECT_NE(verdict.find("default: 71 epochs seen by two or more cameras"), std::string::npos);

  // The statistics table: run.json's numbers.
  const std::string net = html.substr(sec, html.find("</section>", sec) - sec);
  auto cell = [&](const std::string& name, const std::string& value) {
    EXPECT_NE(net.find("<tr><th>" + name + "</th><td class=\"num\">" + value + "</td>"), std::string::npos)
        << name << " = " << value;
  };
  cell("variance factor &#967;&#178;/dof", "1.071");
  cell("epochs in the adjusted track", "6");
  cell("seen by 1 camera", "3");
  cell("seen by 2 cameras", "70");
  cell("seen by &#8805; 3 cameras", "1");
  cell("PPK epochs flagged", "2");
  cell("float epochs used", "2");
  cell("image outliers", "4");
  EXPECT_NE(net.find("&#967;&#178; 1284.4, dof 1199"), std::string::npos);
  // 1.0712 is within 3·√(2/1199) = 0.12 of 1.
  EXPECT_NE(net.find("within its expected 1 &#177; 0.041"), std::string::npos);

  // Each axis's chart: every epoch where the CSV puts it, read back through the chart's own ticks.
  std::size_t n_flagged = 0;
  for (const AdjustedEpoch& e : kAdjusted) n_flagged += e.flag;
  for (int axis = 0; axis < 3; ++axis) {
    const std::string svg = svg_by_id(html, std::string("network-d") + "ENU"[axis]);
    ASSERT_FALSE(svg.empty()) << axis;
    EXPECT_NE(svg.find("<rect class=\"area\""), std::string::npos);
    EXPECT_NE(svg.find("time since the first epoch (s)"), std::string::npos);
    EXPECT_NE(svg.find(std::string("d") + "ENU"[axis] + " (cm)"), std::string::npos);
    const AxisMap X = axis_from_ticks(svg, false), Y = axis_from_ticks(svg, true);
    std::vector<std::pair<double, double>> dots, crosses;
    const std::regex dot(R"re(<circle class="point" cx="([^"]+)" cy="([^"]+)")re");
    for (std::sregex_iterator it(svg.begin(), svg.end(), dot), end; it != end; ++it)
      dots.emplace_back(X.value(std::stod((*it)[1])), Y.value(std::stod((*it)[2])));
    // A red × of half-size 3 starts at its centre − (3, 3).
    const std::regex cross(R"re(<path class="flagged" d="M([^ ]+) ([^L]+)L)re");
    for (std::sregex_iterator it(svg.begin(), svg.end(), cross), end; it != end; ++it)
      crosses.emplace_back(X.value(std::stod((*it)[1]) + 3), Y.value(std::stod((*it)[2]) + 3));
    ASSERT_EQ(crosses.size(), n_flagged) << axis;
    ASSERT_EQ(dots.size(), std::size(kAdjusted) - n_flagged) << axis;
    // The band's upper edge: +1σ of each epoch, in time order; one polygon per ascent (the 29.6 s
    // gap is left open), each its upper edge left to right, then its lower edge back.
    const std::regex band(R"re(<polygon class="band" points="([^"]+)")re");
    std::vector<double> upper;
    int polygons = 0;
    for (std::sregex_iterator it(svg.begin(), svg.end(), band), end; it != end; ++it, ++polygons) {
      std::vector<std::string> xy;
      std::istringstream pts((*it)[1].str());
      for (std::string p; pts >> p;) xy.push_back(p);
      for (std::size_t q = 0; q < xy.size() / 2; ++q)
        upper.push_back(Y.value(std::stod(xy[q].substr(xy[q].find(',') + 1))));
    }
    EXPECT_EQ(polygons, 2) << axis;
    ASSERT_EQ(upper.size(), std::size(kAdjusted));
    const double tol_x = 0.011 * X.per_unit(), tol_y = 0.011 * Y.per_unit();  // 0.01-unit coordinates
    std::size_t kd = 0, kc = 0;
    for (std::size_t k = 0; k < std::size(kAdjusted); ++k) {
      const AdjustedEpoch& e = kAdjusted[k];
      const double d_cm = (axis == 0 ? e.dE : axis == 1 ? e.dN : e.dU) * 100;
      const double s_cm = (axis == 0 ? e.sdE : axis == 1 ? e.sdN : e.sdU) * 100;
      const std::pair<double, double>& p = e.flag ? crosses[kc++] : dots[kd++];
      EXPECT_NEAR(p.first, e.t_s, tol_x) << axis << " epoch " << k;
      EXPECT_NEAR(p.second, d_cm, tol_y) << axis << " epoch " << k;
      EXPECT_NEAR(upper[k], s_cm, tol_y) << axis << " epoch " << k;
    }
  }
  // The flagged epochs' list: their UTC and corrections (cm).
  const std::size_t list = net.find("<table class=\"flagged\">");
  ASSERT_NE(list, std::string::npos);
  EXPECT_EQ(count(net.substr(list), "<tr><td class=\"txt\">"), n_flagged);
  for (const AdjustedEpoch& e : kAdjusted) {
    const std::string utc = adjusted_utc(e).substr(0, 23);  // milliseconds, as shown
    EXPECT_EQ(net.find(utc, list) != std::string::npos, e.flag == 1) << utc;
    if (!e.flag) continue;
    EXPECT_NE(net.find(td_num(fixed("%.2f", e.dE * 100)) + td_num(fixed("%.2f", e.dN * 100)) +
                           td_num(fixed("%.2f", e.dU * 100)),
                       list),
              std::string::npos);
  }
  // The largest correction of a kept fix: epoch 3's dU, −0.46 cm with σ 0.39 cm.
  EXPECT_NE(net.find("&#916;U -0.46 cm at " + adjusted_utc(kAdjusted[3]).substr(0, 23)), std::string::npos);
  EXPECT_NE(net.find("adjusted position 0.39 cm"), std::string::npos);
  // The PPK sd the corrections compare with: the lamp track's 1, 1, 2 cm.
  EXPECT_NE(net.find("(gnss/lamp_track.csv, median) is 1.00 / 1.00 / 2.00 cm"), std::string::npos);

  // Without the adjusted track (another method ran): no section, and the verdict says so.
  fs::remove(dir / "out/gnss/lamp_track_adjusted.csv");
  StageLog bundle;
  bundle.stage = "calibrate";
  bundle.counts["method_choice"] = {{"method", "bundle"},
                                    {"why", "default: no epoch seen by two or more calibrated cameras"}};
  update_run_log(fx.cfg, bundle);
  run_report_stage(fx.cfg);
  const std::string without = test::read_text(dir / "out/report.html");
  EXPECT_EQ(without.find("id=\"network\""), std::string::npos);
  EXPECT_NE(
      without.find("Calibration method: <b>bundle</b> (default: no epoch seen by two or more calibrated "
                   "cameras); each camera calibrated on its own"),
      std::string::npos);
}

TEST(Report, MalformedNetworkInputsNameFileLineAndField) {
  const fs::path dir = test::scratch_dir("report_bad_network");
  const Fixture fx = build_output(dir, true, /*with_network=*/true);
  const fs::path csv = dir / "out/gnss/lamp_track_adjusted.csv";
  const std::string good = test::read_text(csv);
  std::string bad = good;
  bad.replace(bad.rfind(",0\n"), 3, ",2\n");  // the last row's flag
  test::write_text(csv, bad);
  try {
    run_report_stage(fx.cfg);
    FAIL() << "a flag of 2 was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.exit_code(), 3);
    EXPECT_EQ(e.file(), csv.string());
    EXPECT_EQ(e.line(), 7);
    EXPECT_EQ(e.field(), "flag");
  }
  test::write_text(csv, good);
  StageLog cal;
  cal.stage = "calibrate";
  cal.counts["network"] = network_counts();
  cal.counts["network"]["epochs_seen_by_2"] = "70";
  update_run_log(fx.cfg, cal);
  try {
    run_report_stage(fx.cfg);
    FAIL() << "a string count was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.exit_code(), 3);
    EXPECT_EQ(e.field(), "stages.calibrate.counts.network.epochs_seen_by_2");
    EXPECT_NE(std::string(e.what()).find("run.json"), std::string::npos) << e.what();
  }
}

// The PPK error model section (docs/outputs.md): on the fixture's white run the model reads white,
// fixed in the config, with a flat model curve; on a correlated run (a Gauss–Markov track of two
// flights written to gnss/lamp_track_adjusted.csv, run.json's model with σ on two values and 6.5
// looks) the table shows each value with its σ or "fixed in the config", each chart's points are
// the empirical autocorrelation of the file's corrections (flagged epoch left out, E and N pooled)
// and its model curve starts at σ_g²/(σ_w² + σ_g²), and the few looks are warned of.
TEST(Report, PpkErrorModelSectionShowsTheModelItsAutocorrelationAndTheLooks) {
  const fs::path dir = test::scratch_dir("report_ppk_model");
  Fixture fx = build_output(dir, true, /*with_network=*/true);
  run_report_stage(fx.cfg);
  const auto section = [&]() {
    const std::string html = test::read_text(dir / "out/report.html");
    const std::size_t a = html.find("<section id=\"ppk-error-model\">");
    return a == std::string::npos ? std::string() : html.substr(a, html.find("</section>", a) - a);
  };
  const std::string white = section();
  ASSERT_FALSE(white.empty());
  EXPECT_NE(white.find("<h2>PPK error model</h2>"), std::string::npos);
  EXPECT_NE(
      white.find("<td class=\"num\">1.000</td><td class=\"num\">1.000</td><td class=\"txt\">fixed in the "
                 "config</td>"),
      std::string::npos)
      << white;
  EXPECT_NE(white.find("white (every fix independent)"), std::string::npos);
  EXPECT_NE(white.find("Under a white model every fix is an independent look"), std::string::npos);
  EXPECT_EQ(white.find("class=\"warn\""), std::string::npos);
  for (const char* id : {"ppk-acf-h", "ppk-acf-v"}) {
    const std::string svg = svg_by_id(white, id);
    ASSERT_FALSE(svg.empty()) << id;
    const AxisMap Y = axis_from_ticks(svg, true);
    const std::smatch m = [&] {
      std::smatch r;
      std::regex_search(svg, r, std::regex(R"re(<polyline class="model" points="[^,]+,([^ ]+) )re"));
      return r;
    }();
    ASSERT_EQ(m.size(), 2u) << id;
    // Six epochs: no lag bin reaches the 30 pairs a point is drawn from.
    EXPECT_EQ(svg.find("<circle class=\"acf\""), std::string::npos) << id;
    EXPECT_NEAR(Y.value(std::stod(m[1])), 0, 0.011 * Y.per_unit()) << id;  // white: ρ = 0
  }

  // A correlated run: g per axis exactly discretised, plus 2 mm white, 0.2 s epochs, two flights of
  // 240 s 1000 s apart; one epoch flagged with a blunder.
  PpkErrorModel model;
  model.white_scale_h = 0.5, model.white_scale_v = 0.8;
  model.gm_sd_h_m = 0.008, model.gm_sd_v_m = 0.014;
  model.tau_h_s = 20, model.tau_v_s = 30;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> z;
  std::vector<double> t;
  for (double t0 : {0.0, 1240.0})
    for (int k = 0; k < 1200; ++k) t.push_back(t0 + 0.2 * k);
  std::vector<Eigen::Vector3d> d(t.size());
  Eigen::Vector3d g = model.gm_sd().cwiseProduct(Eigen::Vector3d(z(rng), z(rng), z(rng)));
  std::string csv = "utc,E,N,U,sdE,sdN,sdU,dE,dN,dU,flag\n";
  for (std::size_t k = 0; k < t.size(); ++k) {
    const Eigen::Vector3d phi = gauss_markov_transition(model, k ? t[k] - t[k - 1] : 0);
    for (int a = 0; a < 3; ++a)
      g[a] = phi[a] * g[a] + model.gm_sd()[a] * std::sqrt(1 - phi[a] * phi[a]) * z(rng);
    for (int a = 0; a < 3; ++a) d[k][a] = -(g[a] + 0.002 * z(rng));
    const bool flag = k == 700;
    if (flag) d[k] = Eigen::Vector3d(0.3, -0.2, 0.5);
    csv += format_iso8601_utc(
               UtcTime{test::kAdjustedStartNs + static_cast<std::int64_t>(std::llround(t[k] * 1e9))}) +
           ",0.5000,64.0000,3.0000,0.0020,0.0020,0.0040," + fixed("%.4f", d[k].x()) + "," +
           fixed("%.4f", d[k].y()) + "," + fixed("%.4f", d[k].z()) + "," + (flag ? "1" : "0") + "\n";
  }
  test::write_text(dir / "out/gnss/lamp_track_adjusted.csv", csv);
  StageLog cal;
  cal.stage = "calibrate";
  cal.counts["network"] = network_counts();
  nlohmann::json pm = ppk_error_model_json(model, 2400);
  pm["gauss_markov"]["independent_looks"] = {{"horizontal", 13.4}, {"vertical", 6.5}};
  pm["gauss_markov"]["sd_m"]["sigma"] = {{"horizontal", 0.001}, {"vertical", 0.0025}};
  pm["white_scale"]["sigma"] = {{"horizontal", 0.04}, {"vertical", 0.06}};
  cal.counts["network"]["ppk_error_model"] = pm;
  update_run_log(fx.cfg, cal);
  run_report_stage(fx.cfg);
  const std::string sec = section();
  ASSERT_FALSE(sec.empty());
  EXPECT_NE(sec.find("<td class=\"num\">0.500 &#177; 0.040</td><td class=\"num\">0.800 &#177; 0.060</td><td "
                     "class=\"txt\">estimated &#177; 1&#963;</td>"),
            std::string::npos)
      << sec;
  EXPECT_NE(sec.find("<td class=\"num\">0.80 &#177; 0.10</td><td class=\"num\">1.40 &#177; 0.25</td>"),
            std::string::npos);
  EXPECT_NE(sec.find("<td class=\"num\">20.0</td><td class=\"num\">30.0</td><td class=\"txt\">fixed in the "
                     "config</td>"),
            std::string::npos);
  EXPECT_NE(sec.find("<td class=\"num\">13.4</td><td class=\"num\">6.5</td><td class=\"txt\">2400 chained"),
            std::string::npos);
  EXPECT_NE(sec.find("<p class=\"warn\">Fewer than 10 independent looks"), std::string::npos);
  EXPECT_EQ(sec.find("white (every fix independent)"), std::string::npos);
  // The lamp track's median .pos sd is 1 cm (E, N) and 2 cm (U): σ_w = s·sd.
  const double sw[2] = {0.5 * 0.01, 0.8 * 0.02};
  for (int v = 0; v < 2; ++v) {
    const std::string svg = svg_by_id(sec, v ? "ppk-acf-v" : "ppk-acf-h");
    ASSERT_FALSE(svg.empty()) << v;
    const AxisMap X = axis_from_ticks(svg, false), Y = axis_from_ticks(svg, true);
    std::vector<std::vector<double>> series(v ? 1 : 2);
    for (std::size_t k = 0; k < t.size(); ++k)
      for (std::size_t s = 0; s < series.size(); ++s)
        series[s].push_back(k == 700 ? std::nan("")
                                     : std::stod(fixed("%.4f", d[k][v ? 2 : static_cast<int>(s)])));
    const AutocorrelationLags lags = autocorrelation_lags(model, t);
    EXPECT_DOUBLE_EQ(lags.max_lag_s, 90);  // 3 × the longer τ
    const std::vector<AutocorrelationBin> bins =
        empirical_autocorrelation(t, series, lags.bin_s, lags.max_lag_s);
    std::vector<std::pair<double, double>> dots;
    const std::regex dot(R"re(<circle class="acf" cx="([^"]+)" cy="([^"]+)")re");
    for (std::sregex_iterator it(svg.begin(), svg.end(), dot), end; it != end; ++it)
      dots.emplace_back(X.value(std::stod((*it)[1])), Y.value(std::stod((*it)[2])));
    // Bins of fewer than max(30, a tenth of the fullest bin's) pairs are not drawn.
    long most = 0;
    for (const AutocorrelationBin& b : bins) most = std::max(most, b.pairs);
    std::vector<AutocorrelationBin> shown;
    for (const AutocorrelationBin& b : bins)
      if (b.pairs >= std::max(30L, most / 10)) shown.push_back(b);
    ASSERT_EQ(shown.size(), bins.size()) << v;  // 240 s flights: every lag up to 90 s has pairs
    ASSERT_EQ(dots.size(), shown.size()) << v;
    for (std::size_t b = 0; b < bins.size(); ++b) {
      EXPECT_NEAR(dots[b].first, bins[b].lag_s, 0.011 * X.per_unit()) << v << " bin " << b;
      EXPECT_NEAR(dots[b].second, bins[b].rho, 0.011 * Y.per_unit()) << v << " bin " << b;
    }
    // Correlated data: the first bin lies well above zero.
    EXPECT_GT(bins.front().rho, 0.5) << v;
    std::smatch m;
    ASSERT_TRUE(
        std::regex_search(svg, m, std::regex(R"re(<polyline class="model" points="([^,]+),([^ ]+) )re")));
    const double sg = v ? model.gm_sd_v_m : model.gm_sd_h_m;
    EXPECT_NEAR(X.value(std::stod(m[1])), 0, 0.011 * X.per_unit());
    EXPECT_NEAR(Y.value(std::stod(m[2])), sg * sg / (sw[v] * sw[v] + sg * sg), 0.011 * Y.per_unit()) << v;
  }
}

// What the float epochs add: network.json written by the calibrate stage's own writer, read back by
// the report, shown per camera and parameter with the ratio; a malformed object names its field.
TEST(Report, NetworkSectionShowsWhatTheFloatEpochsAdd) {
  const fs::path dir = test::scratch_dir("report_float_epochs");
  const Fixture fx = build_output(dir, true, /*with_network=*/true);
  NetworkResult r;
  r.cameras.resize(2);
  r.cameras[0].calibration.camera_id = "cam1";
  r.cameras[1].calibration.camera_id = "cam2";
  for (BundleResult& c : r.cameras) c.calibration.parameters = {CameraParameter::f, CameraParameter::k1};
  r.float_epochs.epochs = 9;
  r.float_epochs.sigma_with = {Eigen::Vector2d(0.6, 2e-6), Eigen::Vector2d(0.7, 3e-6)};
  r.float_epochs.sigma_without = {Eigen::Vector2d(0.8, 2.5e-6), Eigen::VectorXd()};
  const fs::path network = dir / "out/network.json";
  write_network_json(network.string(), network_json(r, {}));
  run_report_stage(fx.cfg);
  const std::string html = test::read_text(dir / "out/report.html");
  const std::size_t at = html.find("What the 9 float epochs add");
  ASSERT_NE(at, std::string::npos);
  const std::string table = html.substr(at, html.find("</table>", at) - at);
  EXPECT_NE(table.find("<td class=\"txt\">cam1</td><td class=\"txt\">f</td><td class=\"num\">0.6</td><td "
                       "class=\"num\">0.8</td><td class=\"num\">1.333</td><td class=\"txt\">mm</td>"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("<td class=\"txt\">cam2</td><td class=\"txt\">k1</td><td class=\"num\">3e-06</td><td "
                       "class=\"num\">undetermined</td>"),
            std::string::npos)
      << table;

  nlohmann::json j = read_json(network);
  j["float_epochs"]["cameras"][0]["sigma_without"] = {0.8};
  test::write_text(network, j.dump());
  try {
    run_report_stage(fx.cfg);
    FAIL() << "one σ for two parameters was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.exit_code(), 3);
    EXPECT_EQ(e.file(), network.string());
    EXPECT_EQ(e.field(), "float_epochs.cameras[0].sigma_without");
  }
}

// The datum floor (network.json datum_floor) beside the flight volume's predicted intersection σ:
// Σ_cal is linear in the calibrations' covariance, so a floor of a quarter of the joint covariance
// halves every σ of the slice (2.00× its floor: the images limit it) and one of 1/1.21 of it gives
// 1.10× (the datum limits it); a malformed floor names its field.
TEST(Report, VerdictSetsTheIntersectionSigmaBesideTheDatumFloor) {
  const fs::path dir = test::scratch_dir("report_datum_floor");
  Fixture fx = build_output(dir, true, /*with_network=*/true);
  // Two network calibrations: cam1 of the fixture and cam2 8 m east of it, aimed at the same point.
  CalibrationResult c1 = fx.cal;
  c1.method = "network";
  CalibrationResult c2 = c1;
  c2.camera_id = "cam2";
  c2.camera = test::range_camera_at("cam2", {8.0, 0.0, 1.5}, {0.5, 64.0, 7.5});
  c2.covariance = Eigen::Matrix2d(Eigen::Vector2d(0.02 * 0.02, 3e-6 * 3e-6).asDiagonal());
  write_calibration_json((dir / "out/cam1/calibration.json").string(), c1);
  write_calibration_json((dir / "out/cam2/calibration.json").string(), c2);
  NetworkResult r;
  r.cameras.resize(2);
  r.cameras[0].calibration = c1;
  r.cameras[1].calibration = c2;
  Eigen::MatrixXd joint = Eigen::MatrixXd::Zero(4, 4);
  joint.topLeftCorner(2, 2) = c1.covariance;
  joint.bottomRightCorner(2, 2) = c2.covariance;
  joint(0, 2) = joint(2, 0) = 0.5 * 0.0123 * 0.02;  // f of the two cameras correlated
  r.joint_covariance = joint;
  r.joint_offset = {0, 2};
  r.datum_floor_image_factor = kDatumFloorImageFactor;
  const fs::path network = dir / "out/network.json";
  auto verdict_with_floor = [&](double share) {
    r.datum_floor_covariance = joint * share;
    write_network_json(network.string(), network_json(r, {}));
    run_report_stage(fx.cfg);
    const std::string html = test::read_text(dir / "out/report.html");
    return html.substr(0, html.find("</section>"));
  };
  const std::regex median_re(R"re(over the flight volume at U = [^:]+: [^(]+\(median ([0-9.]+) cm\))re");
  const std::regex floor_re(
      R"re(divided by 100 \(what the PPK fixes and control poles alone allow\): median ([0-9.]+) cm; the calibration is ([0-9.]+)&#215; its floor)re");
  std::smatch m, f;

  const std::string images = verdict_with_floor(0.25);
  ASSERT_TRUE(std::regex_search(images, m, median_re)) << images;
  ASSERT_TRUE(std::regex_search(images, f, floor_re)) << images;
  EXPECT_NEAR(std::stod(f[1]), std::stod(m[1]) / 2, 0.006);
  EXPECT_EQ(f[2], "2.00");
  EXPECT_NE(images.find("The images still limit it"), std::string::npos);
  // summary.json carries the same numbers unrounded.
  const nlohmann::json pred = read_json(dir / "out/summary.json")["prediction"];
  EXPECT_NEAR(pred["median_sigma_m"].get<double>() * 100, std::stod(m[1]), 0.005);
  EXPECT_NEAR(pred["datum_floor_median_sigma_m"].get<double>(), pred["median_sigma_m"].get<double>() / 2,
              1e-12);
  EXPECT_NEAR(pred["over_datum_floor"].get<double>(), 2.0, 1e-9);
  EXPECT_NEAR(pred["slice_up_m"].get<double>(), 4.0, 1e-12);  // the check poles' height
  EXPECT_GE(pred["max_sigma_m"].get<double>(), pred["median_sigma_m"].get<double>());

  const std::string datum = verdict_with_floor(1 / 1.21);
  ASSERT_TRUE(std::regex_search(datum, f, floor_re)) << datum;
  EXPECT_EQ(f[2], "1.10");
  EXPECT_NE(datum.find("The datum limits it, not the images"), std::string::npos);

  // A floor of zero (images alone would fix everything) gives no ratio, not an infinite one.
  EXPECT_EQ(verdict_with_floor(0.0).find("datum floor"), std::string::npos);
  EXPECT_TRUE(read_json(dir / "out/summary.json")["prediction"]["over_datum_floor"].is_null());

  // Without a floor in network.json (a run before it, or a bundle run) the sentence is not there.
  r.datum_floor_covariance.resize(0, 0);
  write_network_json(network.string(), network_json(r, {}));
  run_report_stage(fx.cfg);
  EXPECT_EQ(test::read_text(dir / "out/report.html").find("datum floor"), std::string::npos);
  EXPECT_TRUE(read_json(dir / "out/summary.json")["prediction"]["over_datum_floor"].is_null());
  EXPECT_FALSE(read_json(dir / "out/summary.json")["prediction"]["median_sigma_m"].is_null());

  nlohmann::json j = network_json(r, {});
  j["datum_floor"] = {{"image_factor", "100"}, {"joint_covariance", nlohmann::json::array()}};
  test::write_text(network, j.dump());
  try {
    run_report_stage(fx.cfg);
    FAIL() << "a datum floor with a text image_factor was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.exit_code(), 3);
    EXPECT_EQ(e.file(), network.string());
    EXPECT_EQ(e.field(), "datum_floor.image_factor");
  }
  j["datum_floor"] = {{"image_factor", 100}, {"joint_covariance", {{1, 2}, {3, 4}, {5, 6}, {7, 8}}}};
  test::write_text(network, j.dump());
  try {
    run_report_stage(fx.cfg);
    FAIL() << "a datum floor with two columns for four parameters was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.exit_code(), 3);
    EXPECT_EQ(e.field(), "datum_floor.joint_covariance");
  }
}

TEST(Report, VerdictHoldsTheCheckPolesToTheConfiguredBar) {
  // The poles' mean ΔR is 1.69 cm: over the default 1 cm bar, within a configured 2 cm.
  double mean = 0;
  for (const Pole& p : kPoles) mean += pole_dr(p) / 3;
  ASSERT_GT(mean, 0.010);
  ASSERT_LT(mean, 0.020);
  const fs::path dir = test::scratch_dir("report_bar");
  Fixture fx = build_output(dir);
  run_report_stage(fx.cfg);
  std::string html = test::read_text(dir / "out/report.html");
  EXPECT_NE(html.find("bar: mean &#916;R &#8804; 1.0 cm"), std::string::npos);
  EXPECT_NE(html.find("docs/accuracy_analysis.md): NOT met."), std::string::npos);
  fx.cfg.intersect.bar_mean_dR_m = 0.020;
  run_report_stage(fx.cfg);
  html = test::read_text(dir / "out/report.html");
  EXPECT_NE(html.find("bar: mean &#916;R &#8804; 2.0 cm"), std::string::npos);
  EXPECT_NE(html.find("docs/accuracy_analysis.md): met."), std::string::npos);
}

// ---- plots -----------------------------------------------------------------------------------

TEST(SvgPlot, NiceFloorGivesRoundNumbers) {
  EXPECT_DOUBLE_EQ(nice_floor(0.73), 0.5);
  EXPECT_DOUBLE_EQ(nice_floor(1.0), 1.0);
  EXPECT_DOUBLE_EQ(nice_floor(3.9), 2.0);
  EXPECT_DOUBLE_EQ(nice_floor(47), 20);
  EXPECT_DOUBLE_EQ(nice_floor(0.061), 0.05);
  EXPECT_EQ(nice_floor(0), 0);
  EXPECT_EQ(nice_floor(-1), 0);
}

TEST(SvgPlot, ResidualVectorsAreScaledWithAMatchingScaleBar) {
  // 1000 px wide image drawn 640 wide from (52, 40): the largest residual (0.8 px) spans 64 drawing
  // units; the scale bar is 0.5 px of residual, i.e. 40 units.
  const PlotFrame frame{1000, 500};
  const std::string s =
      svg_residual_vectors(frame, {{99.5, 49.5}, {499.5, 249.5}}, {{0.8, 0.0}, {0.0, -0.4}}, "r");
  // First foot at (52 + 100·0.64, 40 + 50·0.64) = (116, 72).
  EXPECT_NE(s.find("x1=\"116.00\" y1=\"72.00\" x2=\"180.00\" y2=\"72.00\""), std::string::npos) << s;
  EXPECT_NE(s.find("x1=\"372.00\" y1=\"200.00\" x2=\"372.00\" y2=\"168.00\""), std::string::npos) << s;
  const std::size_t bar = s.find("class=\"scalebar\" x1=\"52.00\"");
  ASSERT_NE(bar, std::string::npos);
  EXPECT_NE(s.find("x2=\"92.00\"", bar), std::string::npos);
  // A vector that would leave the frame is cut at its edge (the frame ends at x = 52 + 640).
  const std::string cut = svg_residual_vectors(frame, {{990, 250}}, {{0.8, 0.0}}, "c");
  EXPECT_NE(cut.find("x2=\"692.00\""), std::string::npos) << cut;
  EXPECT_NE(cut.find("class=\"cut\""), std::string::npos);
  EXPECT_NE(s.find(">0.5 px residual"), std::string::npos);
}

TEST(SvgPlot, LampTrackDrawsOnePolylinePerSegmentAtImageScale) {
  // 1280 px drawn 640 wide: pixel (u, v) → (52 + (u + 0.5)/2, 40 + (v + 0.5)/2).
  const PlotFrame frame{1280, 800};
  const std::vector<Eigen::Vector2d> obs = {{-0.5, -0.5}, {99.5, 199.5}, {1279.5, 799.5}, {639.5, 399.5}};
  const std::vector<Eigen::Vector2d> proj = {{-0.5, -0.5}, {101.5, 199.5}, {1279.5, 799.5}, {639.5, 399.5}};
  const std::string s = svg_lamp_track(frame, obs, proj, {true, false, true, true}, {2}, "t");
  EXPECT_NE(s.find("points=\"52.00,40.00 102.00,140.00\""), std::string::npos) << s;
  EXPECT_NE(s.find("points=\"692.00,440.00 372.00,240.00\""), std::string::npos) << s;
  EXPECT_EQ(count(s, "<polyline"), 2u);
  EXPECT_NE(s.find("<circle class=\"rejected\" cx=\"102.00\" cy=\"140.00\""), std::string::npos);
  EXPECT_EQ(count(s, "<circle class=\"obs\""), 3u);
  EXPECT_NE(s.find("<path class=\"proj\" d=\"M100.00 137.00L106.00 143.00M100.00 143.00L106.00 137.00\""),
            std::string::npos);
  EXPECT_NE(s.find("id=\"t\""), std::string::npos);
}

TEST(SvgPlot, HistogramCountsEveryValueOnce) {
  // Max 0.95 → bin 0.05, 20 bins; counts 3 in [0, 0.05), 1 in [0.1, 0.15), 2 in [0.95, 1.0).
  const std::string s = svg_histogram({0.0, 0.01, 0.049, 0.12, 0.95, 0.95}, "r", "h");
  EXPECT_EQ(count(s, "<rect class=\"bar\""), 20u);
  EXPECT_NE(s.find("<title>[0, 0.05): 3</title>"), std::string::npos) << s;
  EXPECT_NE(s.find("<title>[0.1, 0.15): 1</title>"), std::string::npos);
  EXPECT_NE(s.find("<title>[0.95, 1): 2</title>"), std::string::npos);
  EXPECT_NE(s.find("(6 values; bin 0.05)"), std::string::npos);
}

// ---- headless browser (issue acceptance) -----------------------------------------------------

TEST(Report, HeadlessChromiumRendersThePage) {
  const std::string chromium = "/usr/bin/chromium";
  ASSERT_TRUE(fs::exists(chromium))
      << "chromium is not installed: install it (apt-get install -y --no-install-recommends chromium, "
         "or run `bash setup.sh test`, which installs it) — the report's browser check needs it";
  const fs::path dir = test::scratch_dir("report_chromium");
  const Fixture fx = build_output(dir);
  run_report_stage(fx.cfg);
  const fs::path html = dir / "out/report.html", png = dir / "shot.png", dom = dir / "dom.html";
  const std::string flags =
      " --headless --no-sandbox --disable-gpu --disable-dev-shm-usage --user-data-dir='" +
      (dir / "profile").string() + "' ";
  const std::string shot = "timeout 60 " + chromium + flags + "--screenshot='" + png.string() +
                           "' --window-size=1280,2000 'file://" + html.string() + "' >/dev/null 2>&1";
  ASSERT_EQ(std::system(shot.c_str()), 0) << shot;
  ASSERT_TRUE(fs::exists(png));
  const cv::Mat img = cv::imread(png.string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(img.empty()) << "screenshot does not decode";
  EXPECT_EQ(img.cols, 1280);
  // A blank page is uniformly white: here text, tables and plots darken a good share of it.
  const int non_white = cv::countNonZero(img < 240);
  EXPECT_GT(non_white, 20000) << "screenshot looks blank";
  cv::Scalar mean, sd;
  cv::meanStdDev(img, mean, sd);
  EXPECT_GT(sd[0], 10.0);

  const std::string dump = "timeout 60 " + chromium + flags + "--dump-dom 'file://" + html.string() + "' >'" +
                           dom.string() + "' 2>/dev/null";
  ASSERT_EQ(std::system(dump.c_str()), 0) << dump;
  const std::string d = test::read_text(dom);
  EXPECT_NE(d.find("id=\"cam-cam1-track\""), std::string::npos);
  EXPECT_NE(d.find("class=\"track\""), std::string::npos);
  EXPECT_NE(d.find("class=\"proj\""), std::string::npos);
  EXPECT_NE(d.find("class=\"resid\""), std::string::npos);
  EXPECT_NE(d.find("class=\"bar\""), std::string::npos);
  EXPECT_EQ(count(d, "<svg"), 14u);
}

}  // namespace
}  // namespace rangecal
