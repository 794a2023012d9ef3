// The report's trajectory section (pipeline/report/trajectory_html.hpp) and what it stands on:
// trajectory.csv read back as written (pipeline/io/trajectory_csv.hpp), its summary
// (pipeline/report/trajectory_summary.hpp: stretches split at gaps and at a change of cameras) and the
// 1σ ellipses, checked against the closed-form eigen-decomposition of a 2×2 covariance written here.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>

#include "config/error.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/io/trajectory_csv.hpp"
#include "pipeline/report/trajectory_json.hpp"
#include "pipeline/report/trajectory_summary.hpp"
#include "pipeline/stages/report_stage.hpp"
#include "support/paths.hpp"
#include "support/report_output.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;

constexpr std::int64_t kStartNs = 1'700'000'000'000'000'000;

/// A helix flown 0–10 s by cam1 + cam2 + cam3, 10–14 s by cam1 + cam3, a gap, then 20–24 s by all
/// three again; 0.2-s steps. Each instant's covariance a tilted ellipse growing with time.
Trajectory helix() {
  Trajectory t;
  for (int k = 0; k <= 120; ++k) {
    const double s = 0.2 * k;
    if (s > 14.01 && s < 19.99) continue;
    TrajectoryPoint p;
    p.t.ns = kStartNs + static_cast<std::int64_t>(k) * 200'000'000;
    p.cameras = s < 9.99 || s > 19.99 ? std::vector<std::string>{"cam1", "cam2", "cam3"}
                                      : std::vector<std::string>{"cam1", "cam3"};
    if (s > 20.5 && s < 21.5) p.extrapolated = {"cam2"};
    p.fix.point = Eigen::Vector3d(20 * std::cos(0.3 * s), 15 * std::sin(0.3 * s), 30 + 0.5 * s);
    const double a = 0.01 + 0.002 * s, b = 0.004, c = 0.003 * a;  // σ_E, σ_N (m), cov_EN (m²)
    p.fix.cov_m2 << a * a, c, 0.00001, c, b * b, 0, 0.00001, 0, 0.0001;
    p.fix.cov_pick_m2 = 0.5 * p.fix.cov_m2, p.fix.cov_timing_m2 = 0.3 * p.fix.cov_m2,
    p.fix.cov_calibration_m2 = 0.2 * p.fix.cov_m2;
    p.fix.sigma_m = std::sqrt(p.fix.cov_m2.trace());
    p.fix.rms_px = 0.4;
    p.inflated = k % 50 == 7;
    p.dof = 2 * static_cast<int>(p.cameras.size()) - 3;
    t.points.push_back(p);
  }
  return t;
}

LocalEnu site() {
  return LocalEnu(GeodeticOrigin{47.37, 8.55, 500});
}

TEST(TrajectoryCsv, ReadsBackWhatItWrote) {
  const Trajectory t = helix();
  const std::vector<TrajectoryRow> rows =
      parse_trajectory_csv(format_trajectory_csv(t, site()), "trajectory.csv");
  ASSERT_EQ(rows.size(), t.points.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const TrajectoryPoint& p = t.points[k];
    EXPECT_EQ(rows[k].utc.ns, p.t.ns);
    EXPECT_LT((rows[k].enu - p.fix.point).cwiseAbs().maxCoeff(), 0.6e-4);  // 4 decimals
    EXPECT_NEAR(rows[k].cov_m2(0, 1), p.fix.cov_m2(0, 1), 0.6e-8);
    EXPECT_NEAR(std::sqrt(rows[k].cov_m2(0, 0)), std::sqrt(p.fix.cov_m2(0, 0)), 0.6e-4);
    EXPECT_NEAR(rows[k].sigma_m, p.fix.sigma_m, 0.6e-4);
    EXPECT_NEAR(rows[k].sigma_labels_m, std::sqrt(p.fix.cov_pick_m2.trace()), 0.6e-4);
    EXPECT_EQ(rows[k].cameras, p.cameras);
    EXPECT_EQ(rows[k].extrapolated, p.extrapolated);
    EXPECT_EQ(rows[k].inflated, p.inflated);
  }
}

TEST(TrajectoryCsv, ABadCellNamesItsLineAndColumn) {
  std::string text = format_trajectory_csv(helix(), site());
  const std::size_t line3 = text.find('\n', text.find('\n', text.find('\n') + 1) + 1) + 1;
  // Line 4 (the third instant): its sigma_m made negative.
  std::vector<std::string> cells;
  const std::size_t end = text.find('\n', line3);
  std::string row = text.substr(line3, end - line3);
  for (std::size_t a = 0, b; a <= row.size(); a = b + 1) {
    b = row.find(',', a);
    if (b == std::string::npos) b = row.size();
    cells.push_back(row.substr(a, b - a));
  }
  cells[13] = "-0.01";  // sigma_m
  row.clear();
  for (std::size_t i = 0; i < cells.size(); ++i) row += (i ? "," : "") + cells[i];
  text.replace(line3, end - line3, row);
  try {
    parse_trajectory_csv(text, "out/trajectory.csv");
    FAIL() << "a negative σ was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.exit_code(), 3);
    EXPECT_EQ(e.line(), 4);
    EXPECT_EQ(e.field(), "sigma_m");
  }
}

// Rows out of time order, and a camera cell with an empty id, are refused naming line and column.
TEST(TrajectoryCsv, OutOfOrderTimesAndBadCameraCellsAreNamed) {
  const std::string text = format_trajectory_csv(helix(), site());
  const std::size_t l2 = text.find('\n') + 1, l3 = text.find('\n', l2) + 1, l4 = text.find('\n', l3) + 1;
  const std::string swapped = text.substr(0, l2) + text.substr(l3, l4 - l3) + text.substr(l2, l3 - l2);
  const auto refused = [](const std::string& csv, long line, const std::string& field) {
    try {
      parse_trajectory_csv(csv, "out/trajectory.csv");
      ADD_FAILURE() << "accepted; expected an error at line " << line << " field " << field;
    } catch (const Error& e) {
      EXPECT_EQ(e.exit_code(), 3);
      EXPECT_EQ(e.line(), line);
      EXPECT_EQ(e.field(), field);
    }
  };
  refused(swapped, 3, "utc");
  std::string bad_cameras = text;
  bad_cameras.replace(bad_cameras.find("cam1+cam2+cam3"), 14, "cam1++cam3");
  refused(bad_cameras, 2, "cameras");
}

TEST(TrajectorySummary, StretchesSplitAtGapsAndCameraChanges) {
  const std::vector<TrajectoryRow> rows =
      parse_trajectory_csv(format_trajectory_csv(helix(), site()), "t.csv");
  const TrajectorySummary s = summarise_trajectory(rows);
  EXPECT_EQ(s.instants, 92);  // 0–14 s and 20–24 s at 0.2 s: 71 + 21
  EXPECT_NEAR(s.span_s, 24, 1e-9);
  EXPECT_NEAR(s.step_s, 0.2, 1e-9);
  ASSERT_EQ(s.stretches.size(), 3u);
  EXPECT_NEAR(s.stretches[0].start_s, 0, 1e-9);
  EXPECT_NEAR(s.stretches[0].end_s, 9.8, 1e-9);
  EXPECT_EQ(s.stretches[0].instants, 50);
  EXPECT_EQ(s.stretches[1].cameras, (std::vector<std::string>{"cam1", "cam3"}));
  EXPECT_NEAR(s.stretches[1].end_s, 14, 1e-9);
  EXPECT_NEAR(s.stretches[2].start_s, 20, 1e-9);
  EXPECT_EQ(s.stretches[2].instants, 21);
  ASSERT_EQ(s.cameras.size(), 3u);
  EXPECT_EQ(s.cameras[0].instants, 92);
  EXPECT_EQ(s.cameras[1].id, "cam2");
  EXPECT_EQ(s.cameras[1].instants, 71);
  EXPECT_EQ(s.cameras[1].extrapolated, 5);  // 20.6 … 21.4 s
  EXPECT_EQ(s.extrapolated, 5);
  EXPECT_EQ(s.inflated, 3);  // 1.4, 11.4 and 21.4 s
}

// trajectory.json: the summary with UTC bounds, each camera's inputs beside its share.
TEST(TrajectoryJson, StatesTheStretchesInUtcAndEachCamerasShare) {
  const std::vector<TrajectoryRow> rows =
      parse_trajectory_csv(format_trajectory_csv(helix(), site()), "t.csv");
  TrajectoryJsonContext c;
  c.origin = {47.37, 8.55, 500};
  c.rate_hz = 5;
  c.extrapolation_sigma_px_per_px = 0.05;
  c.instants_tried = 121;
  c.single_camera = 0;
  c.cameras = {{"cam1", {{"label_sigma_px", 0.5}}},
               {"cam2", {{"label_sigma_px", 0.7}}},
               {"cam4", {{"label_sigma_px", 1.0}}}};
  const nlohmann::json j = trajectory_json(rows, c);
  EXPECT_EQ(j["instants_file"], "trajectory.csv");
  EXPECT_EQ(j["instants"]["tried"], 121);
  EXPECT_EQ(j["instants"]["triangulated"], 92);
  EXPECT_EQ(j["instants"]["extrapolated"], 5);
  EXPECT_EQ(j["first_utc"], format_iso8601_utc(UtcTime{kStartNs}, 3));
  EXPECT_EQ(j["last_utc"], format_iso8601_utc(UtcTime{kStartNs + 24'000'000'000}, 3));
  ASSERT_EQ(j["stretches"].size(), 3u);
  // The second stretch: cam1 + cam3 from 10.0 to 14.0 s; the third from 20 s.
  EXPECT_EQ(j["stretches"][1]["first_utc"], format_iso8601_utc(UtcTime{kStartNs + 10'000'000'000}, 3));
  EXPECT_EQ(j["stretches"][1]["last_utc"], format_iso8601_utc(UtcTime{kStartNs + 14'000'000'000}, 3));
  EXPECT_EQ(j["stretches"][1]["cameras"], (std::vector<std::string>{"cam1", "cam3"}));
  EXPECT_EQ(j["stretches"][2]["first_utc"], format_iso8601_utc(UtcTime{kStartNs + 20'000'000'000}, 3));
  // σ median over the 92 instants, computed here from the helix's own covariance: σ_E = 0.01 +
  // 0.002·s, σ_N 0.004, σ_U 0.01, so √trace rises with s and the median (nearest rank,
  // ⌈0.5·92⌉ = 46th) is that of the 46th time; the CSV holds σ to 0.1 mm.
  std::vector<double> times;
  for (int k = 0; k <= 120; ++k)
    if (!(0.2 * k > 14.01 && 0.2 * k < 19.99)) times.push_back(0.2 * k);
  const double s46 = times[45], a = 0.01 + 0.002 * s46;
  EXPECT_NEAR(j["sigma_m"]["median"].get<double>(), std::sqrt(a * a + 0.004 * 0.004 + 0.0001), 6e-5);
  // Each camera of the context with its inputs and share; one without instants says 0.
  ASSERT_EQ(j["cameras"].size(), 3u);
  EXPECT_EQ(j["cameras"][1]["id"], "cam2");
  EXPECT_EQ(j["cameras"][1]["label_sigma_px"], 0.7);
  EXPECT_EQ(j["cameras"][1]["instants"], 71);
  EXPECT_EQ(j["cameras"][1]["extrapolated"], 5);
  EXPECT_EQ(j["cameras"][2]["id"], "cam4");
  EXPECT_EQ(j["cameras"][2]["instants"], 0);
  EXPECT_EQ(j["frame"]["origin"]["lat_deg"], 47.37);
}

TEST(TrajectorySummary, EllipseIsTheClosedFormEigenDecomposition) {
  for (const Eigen::Vector3d& abc : {Eigen::Vector3d(4e-4, 1e-4, 1.5e-4), Eigen::Vector3d(1e-4, 4e-4, -1e-4),
                                     Eigen::Vector3d(2e-4, 2e-4, 0)}) {
    const double a = abc[0], c = abc[1], b = abc[2];
    Eigen::Matrix2d cov;
    cov << a, b, b, c;
    const double mean = (a + c) / 2, r = std::sqrt((a - c) * (a - c) / 4 + b * b);
    const SigmaEllipse e = sigma_ellipse(cov);
    EXPECT_NEAR(e.major_m, std::sqrt(mean + r), 1e-12);
    EXPECT_NEAR(e.minor_m, std::sqrt(mean - r), 1e-12);
    if (r > 0) {
      EXPECT_NEAR(e.angle_deg, 0.5 * std::atan2(2 * b, a - c) * 180 / M_PI, 1e-9);
    }
  }
}

// The svg with id `id` in `page`.
std::string svg_with_id(const std::string& page, const std::string& id) {
  const std::size_t a = page.find("id=\"" + id + "\"");
  if (a == std::string::npos) return "";
  return page.substr(a, page.find("</svg>", a) - a);
}

TEST(TrajectoryReport, TheSectionStatesTheCsvAndDrawsItsEllipsesToScale) {
  const fs::path dir = test::scratch_dir("report_trajectory");
  const test::ReportOutput fx = test::write_report_output(dir);
  const Trajectory t = helix();
  write_trajectory_csv((dir / "out" / kTrajectoryCsv).string(), t, site());
  run_report_stage(fx.cfg);
  const std::string html = test::read_text(dir / "out/report.html");
  ASSERT_NE(html.find("<section id=\"trajectory\">"), std::string::npos);
  EXPECT_NE(html.find("92 over 24.0 s (step 0.2 s)"), std::string::npos);
  const std::string stretches = html.substr(html.find("trajectory-stretches"));
  EXPECT_NE(
      stretches.find("<td class=\"num\">20.00</td><td class=\"num\">24.00</td><td class=\"num\">21</td>"),
      std::string::npos);
  // The plan view: equal scales read from its tick labels; the first ellipse (the first instant) is
  // its E–N covariance's 1σ ellipse, magnified by the factor the key states.
  const std::string plan = svg_with_id(html, "trajectory-plan");
  ASSERT_FALSE(plan.empty());
  std::smatch m;
  ASSERT_TRUE(std::regex_search(plan, m, std::regex(R"re(magnified ([0-9.]+)&#215;)re")));
  const double gain = std::stod(m[1]);
  std::vector<std::pair<double, double>> x_ticks;
  const std::regex tick(R"re(<text x="([^"]+)" y="[^"]+" text-anchor="middle">([^<]+)</text>)re");
  for (std::sregex_iterator it(plan.begin(), plan.end(), tick), end; it != end; ++it)
    x_ticks.emplace_back(std::stod((*it)[2]), std::stod((*it)[1]));
  ASSERT_GE(x_ticks.size(), 2u);
  const double metres_per_unit =
      (x_ticks.back().first - x_ticks.front().first) / (x_ticks.back().second - x_ticks.front().second);
  ASSERT_TRUE(
      std::regex_search(plan, m, std::regex(R"re(<ellipse class="sigma" [^>]*rx="([^"]+)" ry="([^"]+)")re")));
  const Eigen::Matrix2d cov = t.points[0].fix.cov_m2.topLeftCorner<2, 2>();
  const double mean = cov.trace() / 2,
               r = std::sqrt((cov(0, 0) - cov(1, 1)) * (cov(0, 0) - cov(1, 1)) / 4 + cov(0, 1) * cov(0, 1));
  EXPECT_NEAR(std::stod(m[1]) * metres_per_unit / gain, std::sqrt(mean + r), 0.02 * std::sqrt(mean + r));
  EXPECT_NEAR(std::stod(m[2]) * metres_per_unit / gain, std::sqrt(mean - r), 0.02 * std::sqrt(mean + r));
  EXPECT_FALSE(svg_with_id(html, "trajectory-side").empty());
  EXPECT_FALSE(svg_with_id(html, "trajectory-sigma").empty());

  // Without trajectory.csv: no section.
  fs::remove(dir / "out" / kTrajectoryCsv);
  run_report_stage(fx.cfg);
  EXPECT_EQ(test::read_text(dir / "out/report.html").find("<section id=\"trajectory\">"), std::string::npos);
}

}  // namespace
}  // namespace rangecal
