#include "pipeline/report/trajectory_html.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "config/number_format.hpp"
#include "pipeline/report/html_escape.hpp"
#include "pipeline/report/svg_chart.hpp"
#include "pipeline/report/svg_plot.hpp"
#include "pipeline/report/trajectory_summary.hpp"

namespace rangecal {
namespace {

/// Ellipses drawn on a view: at most this many, spread evenly over the instants.
constexpr std::size_t kMaxEllipses = 40;
/// The largest ellipse is magnified to about this many drawing units when it is smaller.
constexpr double kEllipseUnits = 14;

std::string trajectory_td(const std::string& html, const char* cls = "num") {
  return std::string("<td class=\"") + cls + "\">" + html + "</td>";
}
std::string trajectory_th(const std::string& html) {
  return "<th>" + html + "</th>";
}
std::string trajectory_cm(double m) {
  return format_number("%.1f", m * 100);
}
std::string joined(const std::vector<std::string>& ids) {
  std::string s;
  for (const std::string& id : ids) s += (s.empty() ? "" : " + ") + html_escape(id);
  return s;
}

/// One view of the track (first axis right, second up, equal scales) with 1σ ellipses of `cov`.
struct TrackView {
  std::vector<Eigen::Vector2d> xy;   ///< m
  std::vector<Eigen::Matrix2d> cov;  ///< m², per point
  std::vector<double> t_s;           ///< since the first instant, for the colour
  std::string x_label, y_label, id, title;
};

/// Axes of equal scale holding every point, padded.
ChartAxes view_axes(const TrackView& v) {
  ChartAxes a;
  a.left = 60, a.top = 12, a.width = 420, a.height = 300;
  Eigen::Vector2d lo = v.xy.front(), hi = v.xy.front();
  for (const Eigen::Vector2d& p : v.xy) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Eigen::Vector2d mid = (lo + hi) / 2;
  // Metres per drawing unit: the larger of the two axes' needs, so both scales are equal, with room
  // for the largest ellipse (kEllipseUnits) inside the area at every edge.
  const double inner_w = a.width - 2 * (kEllipseUnits + 4), inner_h = a.height - 2 * (kEllipseUnits + 4);
  const double per_unit = std::max({(hi.x() - lo.x()) / inner_w, (hi.y() - lo.y()) / inner_h, 1e-3});
  a.x0 = mid.x() - per_unit * a.width / 2, a.x1 = mid.x() + per_unit * a.width / 2;
  a.y0 = mid.y() - per_unit * a.height / 2, a.y1 = mid.y() + per_unit * a.height / 2;
  return a;
}

std::string svg_track_view(const TrackView& v) {
  const ChartAxes a = view_axes(v);
  const double scale = a.width / (a.x1 - a.x0);  // drawing units per metre
  const double t_end = std::max(1e-9, v.t_s.back());
  const std::size_t every = std::max<std::size_t>(1, (v.xy.size() + kMaxEllipses - 1) / kMaxEllipses);
  double largest = 0;
  for (std::size_t k = 0; k < v.xy.size(); k += every)
    largest = std::max(largest, sigma_ellipse(v.cov[k]).major_m);
  const double gain = largest * scale > 0 ? std::max(1.0, nice_floor(kEllipseUnits / (largest * scale))) : 1;
  std::string s = svg_open(a.right() + 16, a.bottom() + 76, v.id, v.title);
  s += "<g class=\"data\">\n";
  for (std::size_t k = 0; k < v.xy.size(); ++k)
    s += "<circle class=\"track\" cx=\"" + svg_num(a.X(v.xy[k].x())) + "\" cy=\"" +
         svg_num(a.Y(v.xy[k].y())) + "\" r=\"1.40\" fill=\"" + sequential_colour(v.t_s[k] / t_end) + "\"/>\n";
  for (std::size_t k = 0; k < v.xy.size(); k += every) {
    const SigmaEllipse e = sigma_ellipse(v.cov[k]);
    const double x = a.X(v.xy[k].x()), y = a.Y(v.xy[k].y());
    // Drawing y is down: the angle turns the other way.
    s += "<ellipse class=\"sigma\" cx=\"" + svg_num(x) + "\" cy=\"" + svg_num(y) + "\" rx=\"" +
         svg_num(e.major_m * gain * scale) + "\" ry=\"" + svg_num(e.minor_m * gain * scale) +
         "\" transform=\"rotate(" + svg_num(-e.angle_deg) + " " + svg_num(x) + " " + svg_num(y) +
         ")\" fill=\"none\" stroke=\"#000\" stroke-width=\"0.7\"/>\n";
  }
  s += "</g>\n";
  s += svg_axes(a, v.x_label, v.y_label);
  s += "<g class=\"key\" font-size=\"11\"><text x=\"" + svg_num(a.left) + "\" y=\"" +
       svg_num(a.bottom() + 50) + "\">1&#963; ellipses every " + std::to_string(every) +
       " instant(s), magnified " + tick_label(gain) + "&#215;; colour: time (dark first)</text></g>\n";
  return s + "</svg>\n";
}

/// σ (cm) and its parts against time; each line left open across a gap.
std::string svg_sigma_series(const std::vector<TrajectoryRow>& rows, const TrajectorySummary& sum) {
  ChartAxes a;
  a.left = 60, a.top = 12, a.width = 640, a.height = 200;
  std::vector<double> t;
  double top = 0;
  for (const TrajectoryRow& r : rows) {
    t.push_back(seconds_between(rows.front().utc, r.utc));
    top = std::max({top, r.sigma_m, r.sigma_labels_m, r.sigma_timing_m, r.sigma_calibration_m});
  }
  a.x0 = 0, a.x1 = std::max(t.back(), 1e-3), a.y0 = 0, a.y1 = std::max(top * 100 * 1.08, 0.1);
  const struct {
    double TrajectoryRow::*value;
    const char* name;
    const char* colour;
  } parts[] = {{&TrajectoryRow::sigma_m, "total", "#000000"},
               {&TrajectoryRow::sigma_labels_m, "labels", "#1f77b4"},
               {&TrajectoryRow::sigma_timing_m, "timing", "#2ca02c"},
               {&TrajectoryRow::sigma_calibration_m, "calibration", "#d62728"}};
  std::string s = svg_open(a.right() + 16, a.bottom() + 76, "trajectory-sigma", "Trajectory σ against time");
  s += "<g class=\"data\">\n";
  for (const auto& part : parts) {
    std::string pts;
    const auto flush = [&]() {
      if (!pts.empty())
        s += std::string("<polyline class=\"sigma-") + part.name + "\" points=\"" + pts +
             "\" fill=\"none\" stroke=\"" + part.colour + "\" stroke-width=\"1.2\"/>\n";
      pts.clear();
    };
    for (std::size_t k = 0; k < rows.size(); ++k) {
      if (k > 0 && t[k] - t[k - 1] > kTrajectoryGapSteps * sum.step_s) flush();
      pts += (pts.empty() ? "" : " ") + svg_num(a.X(t[k])) + "," + svg_num(a.Y(rows[k].*part.value * 100));
    }
    flush();
  }
  s += "</g>\n";
  s += svg_axes(a, "time since the first instant (s)", "1σ (cm)");
  s += "<g class=\"key\" font-size=\"11\">";
  double x = a.left;
  for (const auto& part : parts) {
    s += "<line x1=\"" + svg_num(x) + "\" y1=\"" + svg_num(a.bottom() + 46) + "\" x2=\"" + svg_num(x + 18) +
         "\" y2=\"" + svg_num(a.bottom() + 46) + "\" stroke=\"" + part.colour + "\" stroke-width=\"1.2\"/>" +
         "<text x=\"" + svg_num(x + 22) + "\" y=\"" + svg_num(a.bottom() + 50) + "\">" + part.name +
         "</text>";
    x += 110;
  }
  return s + "</g>\n</svg>\n";
}

std::string summary_table(const TrajectorySummary& s) {
  std::string h = "<table class=\"kv\">\n";
  const auto row = [&](const std::string& k, const std::string& v) {
    h += "<tr>" + trajectory_th(k) + trajectory_td(v) + "</tr>\n";
  };
  row("Instants", std::to_string(s.instants) + " over " + format_number("%.1f", s.span_s) + " s (step " +
                      format_number("%.3g", s.step_s) + " s)");
  row("1&#963; (&#8730;trace), median / 95 %",
      trajectory_cm(s.sigma_median_m) + " / " + trajectory_cm(s.sigma_p95_m) + " cm");
  row("its parts (median): labels, timing, calibration", trajectory_cm(s.labels_median_m) + ", " +
                                                             trajectory_cm(s.timing_median_m) + ", " +
                                                             trajectory_cm(s.calibration_median_m) + " cm");
  row("Views disagreeing beyond their &#963; (&#963; scaled up)", std::to_string(s.inflated));
  row("On an extrapolated lens model", std::to_string(s.extrapolated));
  return h + "</table>\n";
}

std::string camera_table(const TrajectorySummary& s) {
  std::string h = "<table class=\"trajectory-cameras\">\n<tr>" + trajectory_th("Camera") +
                  trajectory_th("Instants used") + trajectory_th("of them extrapolated") + "</tr>\n";
  for (const TrajectoryCameraUse& u : s.cameras)
    h += "<tr>" + trajectory_td(html_escape(u.id), "txt") + trajectory_td(std::to_string(u.instants)) +
         trajectory_td(std::to_string(u.extrapolated)) + "</tr>\n";
  return h + "</table>\n";
}

/// The stretches in time order, the first kMaxRows listed and the rest counted.
std::string stretch_table(const TrajectorySummary& s) {
  constexpr std::size_t kMaxRows = 30;
  std::string h = "<table class=\"trajectory-stretches\">\n<tr>" + trajectory_th("From /s") +
                  trajectory_th("To /s") + trajectory_th("Instants") + trajectory_th("Cameras") + "</tr>\n";
  for (std::size_t i = 0; i < s.stretches.size() && i < kMaxRows; ++i) {
    const TrajectoryStretch& r = s.stretches[i];
    h += "<tr>" + trajectory_td(format_number("%.2f", r.start_s)) +
         trajectory_td(format_number("%.2f", r.end_s)) + trajectory_td(std::to_string(r.instants)) +
         trajectory_td(joined(r.cameras), "txt") + "</tr>\n";
  }
  h += "</table>\n";
  if (s.stretches.size() > kMaxRows)
    h +=
        "<p>and " + std::to_string(s.stretches.size() - kMaxRows) + " more stretches (trajectory.csv).</p>\n";
  return h;
}

}  // namespace

std::string trajectory_section(const ReportData& d) {
  if (!d.trajectory) return "";
  std::string s = "<section id=\"trajectory\">\n<h2>Trajectory</h2>\n";
  const std::vector<TrajectoryRow>& rows = *d.trajectory;
  if (rows.empty())
    return s +
           "<p class=\"missing\">trajectory.csv holds no instant: no two cameras labelled the target at "
           "one instant.</p>\n</section>\n";
  const TrajectorySummary sum = summarise_trajectory(rows);
  s +=
      "<p>The target triangulated at each instant from the cameras' labels (docs/trajectory.md); the 1&#963; "
      "carry the labels, their timing and the calibrations' covariance. A stretch is a run of instants "
      "with one set of cameras and no gap (a step above " +
      format_number("%g", kTrajectoryGapSteps) + " median steps).</p>\n";
  s += summary_table(sum) + camera_table(sum) + stretch_table(sum);
  TrackView plan, side;
  // Side view: the horizontal direction along which the track spreads most, against U.
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const TrajectoryRow& r : rows) mean += r.enu.head<2>() / static_cast<double>(rows.size());
  Eigen::Matrix2d spread = Eigen::Matrix2d::Zero();
  for (const TrajectoryRow& r : rows)
    spread += (r.enu.head<2>() - mean) * (r.enu.head<2>() - mean).transpose();
  const Eigen::Vector2d along = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(spread).eigenvectors().col(1);
  Eigen::Matrix<double, 2, 3> J = Eigen::Matrix<double, 2, 3>::Zero();
  J(0, 0) = along.x(), J(0, 1) = along.y(), J(1, 2) = 1;
  for (const TrajectoryRow& r : rows) {
    const double t = seconds_between(rows.front().utc, r.utc);
    plan.xy.push_back(r.enu.head<2>()), plan.cov.push_back(r.cov_m2.topLeftCorner<2, 2>()),
        plan.t_s.push_back(t);
    side.xy.push_back(J * r.enu), side.cov.push_back(J * r.cov_m2 * J.transpose()), side.t_s.push_back(t);
  }
  plan.x_label = "E (m), east", plan.y_label = "N (m), north", plan.id = "trajectory-plan";
  plan.title = "Trajectory, plan view";
  side.x_label = "distance along the track's main horizontal direction (m)", side.y_label = "height U (m)";
  side.id = "trajectory-side", side.title = "Trajectory, side view";
  s += "<div class=\"plots\">\n" + svg_track_view(plan) + svg_track_view(side) + "</div>\n";
  s += svg_sigma_series(rows, sum);
  return s + "</section>\n";
}

}  // namespace rangecal
