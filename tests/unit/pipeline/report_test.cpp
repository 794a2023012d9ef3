// The report stage (docs/outputs.md): an output folder built from synthetic data with the project's
// own writers → summary.json numbers equal the inputs', report.html has the tables and one <svg>
// per plot, reruns are byte-identical, a camera without calibration is reported (not an error), a
// malformed input names file and line, and a headless browser renders the page (issue acceptance).
#include "pipeline/stages/report_stage.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "config/error.hpp"
#include "gnss/formats/lamp_track_csv.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/io/methods_csv.hpp"
#include "pipeline/io/residuals_csv.hpp"
#include "pipeline/report/report_html.hpp"
#include "pipeline/report/svg_plot.hpp"
#include "pipeline/stages/calibrate_stage.hpp"
#include "support/paths.hpp"
#include "support/synthetic_camera.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;

std::size_t count(const std::string& hay, const std::string& needle) {
  std::size_t n = 0;
  for (std::size_t p = hay.find(needle); p != std::string::npos; p = hay.find(needle, p + needle.size())) ++n;
  return n;
}

std::string fixed(const char* f, double x) {
  char b[64];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

// The check poles written to intersection.csv (metres): dE, dN, dU and sigma; dR follows.
struct Pole {
  const char* id;
  double dE, dN, dU, sigma;
};
const Pole kPoles[] = {{"A1", 0.0120, -0.0050, 0.0031, 0.0110},
                       {"A2", -0.0042, 0.0211, -0.0008, 0.0120},
                       {"A3", 0.0007, 0.0033, 0.0152, 0.0105}};

double pole_dr(const Pole& p) {
  return std::sqrt(p.dE * p.dE + p.dN * p.dN + p.dU * p.dU);
}

struct Fixture {
  MissionConfig cfg;
  CalibrationResult cal;          // cam1's calibration.json
  std::size_t cam1_pairs = 0;     // lamp pairs in cam1/correspondences.csv
  std::size_t cam1_rejected = 0;  // of them marked used = 0
  std::size_t cam1_segments = 0;  // ascents (and the pole tops), each a separate time block
};

// A mission output folder: lamp track, cam1 calibrated (pairs, calibration.json, methods.csv),
// cam2 whose calibration failed (pairs only, failure in run.json), intersection.csv, run.json.
Fixture build_output(const fs::path& dir, bool with_intersection = true) {
  Fixture fx;
  fx.cfg.mission = "Range 3 <night> & \"dawn\" flights";
  fx.cfg.output_dir = (dir / "out").string();
  fx.cfg.config_path = (dir / "mission.json").string();
  for (const char* id : {"cam1", "cam2"}) {
    CameraConfig c;
    c.id = id;
    c.sensor.width_px = 1280;
    c.sensor.height_px = 800;
    c.sensor.pixel_size_um[0] = c.sensor.pixel_size_um[1] = 20;
    c.nominal_focal_mm = 135;
    fx.cfg.cameras.push_back(c);
  }
  const std::string out = fx.cfg.output_dir;

  LampTrack track;
  for (int i = 0; i < 5; ++i) {
    LampEpoch e;
    e.utc = UtcTime{1'700'000'000'000'000'000 + i * 200'000'000LL};
    e.enu = Eigen::Vector3d(0.5, 64.0, 2.0 + i);
    e.sd_enu = Eigen::Vector3d(0.01, 0.01, 0.02);
    e.quality = 1;
    track.epochs.push_back(e);
  }
  write_lamp_track_csv(out + "/gnss/lamp_track.csv", track);

  // cam1: the seed 002 range camera; pixels with 0.2 px noise, two pairs marked as rejected.
  const Camera truth = test::range_camera(-3.4e-4, 1.0, 0.6, -0.3);
  const auto obs = test::observe(truth, test::range_world_points(truth), 0.2, 0.0, 7);
  // Frames 10 ms apart along an ascent (or the pole tops); 60 s between them, as when the UAV flies
  // down out of view and climbs the next route, so Fig. 6 draws one polyline per segment.
  std::vector<Correspondence> pairs;
  std::int64_t t = 1'700'000'000'000'000'000;
  fx.cam1_segments = obs.empty() ? 0 : 1;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const bool new_segment = i > 0 && std::abs(obs[i].world.x() - obs[i - 1].world.x()) > 0.5;
    fx.cam1_segments += new_segment;
    t += i == 0 ? 0 : new_segment ? 60'000'000'000LL : 10'000'000LL;
    Correspondence c;
    c.utc = UtcTime{t};
    c.enu = obs[i].world;
    c.uv = obs[i].pixel;
    c.used = !(i == 3 || i == 17);
    Eigen::Vector2d p;
    project(truth, c.enu, &p);
    c.residual_px = (c.uv - p).norm();
    pairs.push_back(c);
  }
  fx.cam1_pairs = pairs.size();
  fx.cam1_rejected = 2;
  write_correspondences_csv(out + "/cam1/correspondences.csv", pairs);
  // The calibrate stage's residuals.csv says which pairs the calibration used.
  std::vector<ResidualRow> residuals;
  for (const Correspondence& c : pairs) {
    ResidualRow row;
    row.utc = c.utc;
    row.enu = c.enu;
    row.uv = c.uv;
    row.used = *c.used;
    residuals.push_back(row);
  }
  write_residuals_csv(out + "/cam1/residuals.csv", residuals);
  write_correspondences_csv(out + "/cam2/correspondences.csv", pairs);

  CalibrationResult& r = fx.cal;
  r.camera_id = "cam1";
  r.method = "bundle";
  r.camera = truth;
  r.camera.id = "cam1";
  r.parameters = test::parameters({"f", "k1"});
  r.covariance = Eigen::Matrix2d(Eigen::Vector2d(0.0123 * 0.0123, 2.5e-6 * 2.5e-6).asDiagonal());
  r.reprojection.rms_px = 0.2137;
  r.reprojection.mean_px = 0.1876;
  r.reprojection.max_px = 0.6543;
  r.reprojection.n_used = static_cast<int>(pairs.size() - 2);
  r.reprojection.n_rejected = 2;
  r.warnings = {"f and Tz correlated <0.995>"};
  write_calibration_json(out + "/cam1/calibration.json", r);
  CalibrationResult tsai = r;
  tsai.method = "tsai";
  tsai.camera.intr.f_mm = 132.43;
  tsai.covariance.resize(0, 0);
  tsai.parameters.clear();
  tsai.reprojection.rms_px = 0.99;
  test::write_text(out + "/cam1/methods.csv", format_methods_csv({method_row(r), method_row(tsai)}));

  if (with_intersection) {
    std::string csv = "id,E,N,U,E_survey,N_survey,U_survey,dE,dN,dU,dR,sigma_m\n";
    for (const Pole& p : kPoles)
      csv += std::string(p.id) + ",1.0000,62.0000,4.0000,1.0000,62.0000,4.0000," + fixed("%.4f", p.dE) + "," +
             fixed("%.4f", p.dN) + "," + fixed("%.4f", p.dU) + "," + fixed("%.6f", pole_dr(p)) + "," +
             fixed("%.4f", p.sigma) + "\n";
    test::write_text(out + "/intersection.csv", csv);
  }

  StageLog cal_log;
  cal_log.stage = "calibrate";
  cal_log.counts["cam2"] = {{"failed", "points on one line <degenerate>"}};
  cal_log.warnings = {"cam2: calibration failed: points on one line <degenerate>"};
  update_run_log(fx.cfg, cal_log);
  return fx;
}

nlohmann::json read_json(const fs::path& p) {
  return nlohmann::json::parse(test::read_text(p));
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
  EXPECT_NE(s.find("<path class=\"proj\" d=\"M100.00 137.00L106.00 143.00M100.00 143.00L106.00 137.00\""), std::string::npos);
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
