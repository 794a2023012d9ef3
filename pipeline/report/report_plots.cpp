#include "pipeline/report/report_plots.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "config/number_format.hpp"
#include "pipeline/report/html_escape.hpp"
#include "pipeline/report/svg_chart.hpp"

namespace rangecal {
namespace {

const char* kCameraColours[] = {"#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#17becf"};
const char* camera_colour(std::size_t i) {
  return kCameraColours[i % (sizeof kCameraColours / sizeof *kCameraColours)];
}

std::string n2(double x) {
  return svg_num(x);
}

std::string text(double x, double y, const std::string& s, const char* extra = "") {
  return "<text x=\"" + n2(x) + "\" y=\"" + n2(y) + "\"" + extra + ">" + s + "</text>";
}

std::string cross(double x, double y, double a, const char* cls, const char* colour) {
  return std::string("<path class=\"") + cls + "\" d=\"M" + n2(x - a) + " " + n2(y - a) + "L" + n2(x + a) +
         " " + n2(y + a) + "M" + n2(x - a) + " " + n2(y + a) + "L" + n2(x + a) + " " + n2(y - a) +
         "\" stroke=\"" + colour + "\" stroke-width=\"1.2\"/>\n";
}

// Data range [lo, hi] of values, widened to `min_span` and padded by `pad` of the span each side.
Eigen::Vector2d padded_range(const std::vector<double>& v, double pad, double min_span) {
  double lo = INFINITY, hi = -INFINITY;
  for (double x : v)
    if (std::isfinite(x)) lo = std::min(lo, x), hi = std::max(hi, x);
  if (!(hi >= lo)) lo = 0, hi = 1;
  if (hi - lo < min_span) {
    const double c = (lo + hi) / 2;
    lo = c - min_span / 2;
    hi = c + min_span / 2;
  }
  const double p = pad * (hi - lo);
  return {lo - p, hi + p};
}

// Equal scales in x and y: the area (w × h drawing units) shows at least the ranges given, centred.
void equal_aspect(ChartAxes* a, Eigen::Vector2d xr, Eigen::Vector2d yr) {
  const double s = std::min(a->width / (xr[1] - xr[0]), a->height / (yr[1] - yr[0]));
  const double xc = (xr[0] + xr[1]) / 2, yc = (yr[0] + yr[1]) / 2;
  a->x0 = xc - a->width / s / 2;
  a->x1 = xc + a->width / s / 2;
  a->y0 = yc - a->height / s / 2;
  a->y1 = yc + a->height / s / 2;
}

// The horizontal unit vector of a direction (ENU), or E when it is vertical.
Eigen::Vector2d horizontal(const Eigen::Vector3d& d) {
  const Eigen::Vector2d h(d.x(), d.y());
  return h.norm() > 1e-9 ? Eigen::Vector2d(h.normalized()) : Eigen::Vector2d(1, 0);
}

// A magnification 1, 2 or 5 × 10^k that makes `size` drawing units at least `want` (≥ 1).
double magnification(double size, double want) {
  if (!(size > 0) || size >= want) return 1;
  const double g = want / size;
  const double p = std::pow(10.0, std::floor(std::log10(g))), m = g / p;
  return (m <= 1 ? 1 : m <= 2 ? 2 : m <= 5 ? 5 : 10) * p;
}

}  // namespace

namespace {

// The plan view's axes: equal scales over the cameras, their wedges, the track and the poles.
ChartAxes site_plan_axes(const SiteMap& m) {
  std::vector<double> es, ns;
  auto add = [&](const Eigen::Vector3d& p) { es.push_back(p.x()), ns.push_back(p.y()); };
  for (const SiteCamera& c : m.cameras) {
    add(c.center);
    for (const Eigen::Vector3d& r : {c.left_ray, c.right_ray}) {
      const Eigen::Vector2d h = horizontal(r) * c.wedge_m;
      add(c.center + Eigen::Vector3d(h.x(), h.y(), 0));
    }
  }
  for (const Eigen::Vector3d& p : m.track) add(p);
  for (const SitePole& p : m.poles) add(p.enu);
  ChartAxes a;
  a.left = 60;
  a.top = 14;
  a.width = 560;
  a.height = 440;
  equal_aspect(&a, padded_range(es, 0.12, 10), padded_range(ns, 0.12, 10));
  return a;
}

// Viewing wedges, the track coloured by time (0 … t_end s) and the rejected pairs: the layer under
// the markers.
std::string site_plan_wedges_and_track(const SiteMap& m, const ChartAxes& a, double t_end) {
  std::string s;
  for (std::size_t i = 0; i < m.cameras.size(); ++i) {
    const SiteCamera& c = m.cameras[i];
    const Eigen::Vector2d hl = horizontal(c.left_ray) * c.wedge_m, hr = horizontal(c.right_ray) * c.wedge_m;
    s += "<polygon class=\"wedge\" points=\"" + n2(a.X(c.center.x())) + "," + n2(a.Y(c.center.y())) + " " +
         n2(a.X(c.center.x() + hl.x())) + "," + n2(a.Y(c.center.y() + hl.y())) + " " +
         n2(a.X(c.center.x() + hr.x())) + "," + n2(a.Y(c.center.y() + hr.y())) + "\" fill=\"" +
         camera_colour(i) + "\" fill-opacity=\"0.12\" stroke=\"" + camera_colour(i) +
         "\" stroke-width=\"0.6\"/>\n";
  }
  for (std::size_t k = 0; k < m.track.size(); ++k)
    s += "<circle class=\"track\" cx=\"" + n2(a.X(m.track[k].x())) + "\" cy=\"" + n2(a.Y(m.track[k].y())) +
         "\" r=\"1.60\" fill=\"" + sequential_colour(k < m.track_t_s.size() ? m.track_t_s[k] / t_end : 0) +
         "\"/>\n";
  for (const Eigen::Vector3d& p : m.outliers) s += cross(a.X(p.x()), a.Y(p.y()), 3, "outlier", "#d62728");
  return s;
}

// How much the camera centres' 1σ ellipses are magnified: the largest spans 8 drawing units.
double site_plan_centre_gain(const SiteMap& m, double scale) {
  double max_sigma = 0;
  for (const SiteCamera& c : m.cameras)
    if (c.center_cov_m2.allFinite())
      max_sigma = std::max(
          max_sigma,
          std::sqrt(std::max(0.0, c.center_cov_m2.topLeftCorner<2, 2>().eigenvalues().real().maxCoeff())));
  return magnification(max_sigma * scale, 8);
}

// Camera centres with their 1σ ellipses (E, N block of the covariance) magnified `gain` times.
std::string site_plan_cameras(const SiteMap& m, const ChartAxes& a, double scale, double gain) {
  std::string s;
  for (std::size_t i = 0; i < m.cameras.size(); ++i) {
    const SiteCamera& c = m.cameras[i];
    const double x = a.X(c.center.x()), y = a.Y(c.center.y());
    if (c.center_cov_m2.allFinite()) {
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es2(c.center_cov_m2.topLeftCorner<2, 2>());
      const Eigen::Vector2d ev = es2.eigenvalues().cwiseMax(0).cwiseSqrt() * gain * scale;
      const Eigen::Vector2d major = es2.eigenvectors().col(1);
      const double angle = -std::atan2(major.y(), major.x()) * 57.29577951308232;  // drawing y is down
      s += "<ellipse class=\"center-sigma\" cx=\"" + n2(x) + "\" cy=\"" + n2(y) + "\" rx=\"" + n2(ev[1]) +
           "\" ry=\"" + n2(ev[0]) + "\" transform=\"rotate(" + n2(angle) + " " + n2(x) + " " + n2(y) +
           ")\" fill=\"none\" stroke=\"#000\" stroke-width=\"0.8\"/>\n";
    }
    s += "<circle class=\"camera\" cx=\"" + n2(x) + "\" cy=\"" + n2(y) + "\" r=\"3.00\" fill=\"" +
         camera_colour(i) + "\"/>\n";
    s += "<text class=\"camera-label\" x=\"" + n2(std::min(x + 6, a.right() - 40)) + "\" y=\"" +
         n2(std::max(y - 6, a.top + 12)) + "\" font-size=\"11\">" + html_escape(c.id) + "</text>\n";
  }
  return s;
}

// How much the check poles' errors and σ are magnified: the largest spans 30 drawing units.
double site_plan_pole_gain(const SiteMap& m, double scale) {
  double max_err = 0;
  for (const SitePole& p : m.poles)
    if (p.has_error)
      max_err = std::max({max_err, Eigen::Vector2d(p.d_enu.x(), p.d_enu.y()).norm(), p.sigma_m});
  return max_err > 0 ? std::max(1.0, nice_floor(30.0 / (max_err * scale))) : 1;
}

// Poles; check poles' errors and σ magnified `gain` times.
std::string site_plan_poles(const SiteMap& m, const ChartAxes& a, double scale, double gain) {
  std::string s;
  for (const SitePole& p : m.poles) {
    const double x = a.X(p.enu.x()), y = a.Y(p.enu.y());
    if (p.check) {
      if (p.has_error) {
        s += "<circle class=\"pole-sigma\" cx=\"" + n2(x) + "\" cy=\"" + n2(y) + "\" r=\"" +
             n2(p.sigma_m * gain * scale) +
             "\" fill=\"none\" stroke=\"#777\" stroke-dasharray=\"2,2\" stroke-width=\"0.8\"/>\n";
        s += "<line class=\"pole-error\" x1=\"" + n2(x) + "\" y1=\"" + n2(y) + "\" x2=\"" +
             n2(x + p.d_enu.x() * gain * scale) + "\" y2=\"" + n2(y - p.d_enu.y() * gain * scale) +
             "\" stroke=\"#d62728\" stroke-width=\"1.4\"/>\n";
      }
      s += "<rect class=\"check-pole\" x=\"" + n2(x - 2.5) + "\" y=\"" + n2(y - 2.5) +
           "\" width=\"5.00\" height=\"5.00\" fill=\"#000\"/>\n";
    } else {
      s += "<path class=\"control-pole\" d=\"M" + n2(x) + " " + n2(y - 3.5) + "L" + n2(x + 3.2) + " " +
           n2(y + 2.5) + "L" + n2(x - 3.2) + " " + n2(y + 2.5) + "Z\" fill=\"#ff7f0e\"/>\n";
    }
  }
  return s;
}

// Key: scale bar, markers, magnifications, time colours.
std::string site_plan_key(const ChartAxes& a, double scale, double gain_p, double gain_c, double t_end) {
  const double bar_m = nice_floor((a.x1 - a.x0) / 5), ky = a.bottom() + 48;
  std::string s = "<g class=\"key\" font-size=\"11\">\n<line x1=\"" + n2(a.left) + "\" y1=\"" + n2(ky) +
                  "\" x2=\"" + n2(a.left + bar_m * scale) + "\" y2=\"" + n2(ky) +
                  "\" stroke=\"#000\" stroke-width=\"2\"/>" +
                  text(a.left + bar_m * scale + 6, ky + 4, tick_label(bar_m) + " m") + "\n";
  const double kx = a.left + bar_m * scale + 60;
  s += "<rect x=\"" + n2(kx) + "\" y=\"" + n2(ky - 6) + "\" width=\"5\" height=\"5\"/>" +
       text(kx + 8, ky, "check pole") + "<path d=\"M" + n2(kx + 82) + " " + n2(ky - 7) + "L" + n2(kx + 85) +
       " " + n2(ky - 1) + "L" + n2(kx + 79) + " " + n2(ky - 1) + "Z\" fill=\"#ff7f0e\"/>" +
       text(kx + 90, ky, "control pole") + cross(kx + 176, ky - 4, 3, "key-outlier", "#d62728") +
       text(kx + 183, ky, "rejected lamp pair") + "\n";
  const double ky2 = ky + 16;
  s += text(a.left, ky2,
            "check-pole error (red) and predicted 1σ of ΔR (dashed circle) magnified " + tick_label(gain_p) +
                "x") +
       text(a.left, ky2 + 14, "camera centre 1σ ellipse magnified " + tick_label(gain_c) + "x") + "\n";
  const double ky3 = ky2 + 30;
  for (int k = 0; k < 10; ++k)
    s += "<rect x=\"" + n2(a.left + k * 12) + "\" y=\"" + n2(ky3 - 8) +
         "\" width=\"12\" height=\"9\" fill=\"" + sequential_colour((k + 0.5) / 10) + "\"/>";
  s += text(a.left + 126, ky3, "lamp track, time 0 … " + format_number("%.1f", t_end) + " s") + "\n</g>\n";
  return s;
}

}  // namespace

std::string svg_site_plan(const SiteMap& m, const std::string& id) {
  const ChartAxes a = site_plan_axes(m);
  const double scale = a.width / (a.x1 - a.x0);  // drawing units per metre
  const double t_end = m.track_t_s.empty() ? 1 : std::max(1e-9, m.track_t_s.back());
  const double gain_c = site_plan_centre_gain(m, scale), gain_p = site_plan_pole_gain(m, scale);
  std::string s = svg_open(a.right() + 16, a.bottom() + 104, id, "Site map, plan view");
  s += "<g class=\"data\">\n";
  // Viewing wedges, then the track, then the markers on top.
  s += site_plan_wedges_and_track(m, a, t_end);
  s += site_plan_cameras(m, a, scale, gain_c);
  s += site_plan_poles(m, a, scale, gain_p);
  s += "</g>\n";
  s += svg_axes(a, "E (m), east", "N (m), north");
  s += site_plan_key(a, scale, gain_p, gain_c, t_end);
  return s + "</svg>\n";
}

std::string svg_site_side(const SiteMap& m, const std::string& id) {
  // Distance along the cameras' mean horizontal viewing direction (mean centre → mean track point).
  Eigen::Vector3d cm = Eigen::Vector3d::Zero(), tm = Eigen::Vector3d::Zero();
  for (const SiteCamera& c : m.cameras) cm += c.center / std::max<std::size_t>(1, m.cameras.size());
  for (const Eigen::Vector3d& p : m.track) tm += p / static_cast<double>(m.track.size());
  const Eigen::Vector2d dir =
      horizontal(m.track.empty() ? Eigen::Vector3d::UnitY() : Eigen::Vector3d(tm - cm));
  auto dist = [&](const Eigen::Vector3d& p) {
    return Eigen::Vector2d(p.x() - cm.x(), p.y() - cm.y()).dot(dir);
  };
  std::vector<double> xs, ys;
  for (const SiteCamera& c : m.cameras) xs.push_back(dist(c.center)), ys.push_back(c.center.z());
  for (const Eigen::Vector3d& p : m.track) xs.push_back(dist(p)), ys.push_back(p.z());
  for (const SitePole& p : m.poles) xs.push_back(dist(p.enu)), ys.push_back(p.enu.z());
  ys.push_back(0);
  ChartAxes a;
  a.left = 60;
  a.top = 14;
  a.width = 380;
  a.height = 300;
  const Eigen::Vector2d xr = padded_range(xs, 0.06, 1), yr = padded_range(ys, 0.06, 1);
  a.x0 = xr[0], a.x1 = xr[1], a.y0 = yr[0], a.y1 = yr[1];
  std::string s = svg_open(a.right() + 16, a.bottom() + 60, id, "Site map, side view");
  s += "<g class=\"data\">\n";
  const double t_end = m.track_t_s.empty() ? 1 : std::max(1e-9, m.track_t_s.back());
  for (std::size_t k = 0; k < m.track.size(); ++k)
    s += "<circle class=\"track\" cx=\"" + n2(a.X(dist(m.track[k]))) + "\" cy=\"" + n2(a.Y(m.track[k].z())) +
         "\" r=\"1.60\" fill=\"" + sequential_colour(k < m.track_t_s.size() ? m.track_t_s[k] / t_end : 0) +
         "\"/>\n";
  for (const Eigen::Vector3d& p : m.outliers) s += cross(a.X(dist(p)), a.Y(p.z()), 3, "outlier", "#d62728");
  for (const SitePole& p : m.poles) {
    const double x = a.X(dist(p.enu)), y = a.Y(p.enu.z());
    if (p.check)
      s += "<rect class=\"check-pole\" x=\"" + n2(x - 2.5) + "\" y=\"" + n2(y - 2.5) +
           "\" width=\"5.00\" height=\"5.00\" fill=\"#000\"/>\n";
    else
      s += "<path class=\"control-pole\" d=\"M" + n2(x) + " " + n2(y - 3.5) + "L" + n2(x + 3.2) + " " +
           n2(y + 2.5) + "L" + n2(x - 3.2) + " " + n2(y + 2.5) + "Z\" fill=\"#ff7f0e\"/>\n";
  }
  for (std::size_t i = 0; i < m.cameras.size(); ++i)
    s += "<circle class=\"camera\" cx=\"" + n2(a.X(dist(m.cameras[i].center))) + "\" cy=\"" +
         n2(a.Y(m.cameras[i].center.z())) + "\" r=\"3.00\" fill=\"" + camera_colour(i) + "\"/>\n";
  s += "</g>\n";
  s += svg_axes(a, "distance along the cameras' mean viewing direction (m)", "height U (m)");
  s += "<g class=\"key\" font-size=\"11\">" +
       text(a.left, a.bottom() + 48, "cameras (dots), lamp track coloured by time, poles as in the plan") +
       "</g>\n</svg>\n";
  return s;
}

namespace {

// What band_scatter draws beyond the points: the band's multiple of σ, the plot's width, the
// markers of flagged points and a key under the axes.
struct BandScatterStyle {
  double band_k = 2;
  double width = 380;
  std::vector<bool> flagged;  ///< empty: none; true: a red × instead of the dot
  std::string key;            ///< empty: no key; else the key's text, after the three markers
};

// y against x over the band ±k·σ about zero (σ per point; a polygon through the points sorted by
// x), with the zero line. A point outside the band is larger than k of its own σ. `used` false
// draws a hollow red ring, style.flagged true a red × (either list may be empty).
std::string band_scatter(const std::vector<double>& x, const std::vector<double>& y,
                         const std::vector<double>& sigma, const std::vector<bool>& used,
                         const std::string& x_label, const std::string& y_label, const std::string& id,
                         const std::string& title, const BandScatterStyle& style) {
  ChartAxes a;
  a.left = 60;
  a.top = 12;
  a.width = style.width;
  a.height = 150;
  const Eigen::Vector2d xr = padded_range(x, 0.02, 1e-6);
  const double k = style.band_k;
  double ymax = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    if (std::isfinite(y[i])) ymax = std::max(ymax, std::abs(y[i]));
    if (i < sigma.size() && std::isfinite(sigma[i])) ymax = std::max(ymax, k * sigma[i]);
  }
  ymax = ymax > 0 ? ymax * 1.1 : 1;
  a.x0 = xr[0], a.x1 = xr[1], a.y0 = -ymax, a.y1 = ymax;
  std::string s = svg_open(a.right() + 14, a.bottom() + (style.key.empty() ? 40 : 58), id, title);
  s += "<g class=\"data\">\n";
  // The ±kσ band through the points sorted by x, one polygon per run of points: a gap over 5× the
  // median step (the UAV flying back down between ascents) is left open, not bridged by a band no
  // point supports; a point alone gets a band half a median step to each side.
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < x.size() && i < sigma.size(); ++i)
    if (std::isfinite(x[i]) && std::isfinite(sigma[i])) order.push_back(i);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t p, std::size_t q) { return x[p] < x[q]; });
  std::vector<double> steps;
  for (std::size_t j = 1; j < order.size(); ++j) steps.push_back(x[order[j]] - x[order[j - 1]]);
  double median_step = 0;
  if (!steps.empty()) {
    std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2),
                     steps.end());
    median_step = steps[steps.size() / 2];
  }
  const double gap = median_step > 0 ? 5 * median_step : INFINITY;
  auto vertex = [&](double xv, double yv) {
    return n2(a.X(std::clamp(xv, a.x0, a.x1))) + "," + n2(a.Y(yv)) + " ";
  };
  for (std::size_t b = 0, j = 1; j <= order.size(); ++j) {
    if (j < order.size() && x[order[j]] - x[order[j - 1]] <= gap) continue;
    const double h = j - b == 1 ? median_step / 2 : 0;  // half-width of a lone point's band
    std::string up, down;  // upper edge left to right, then lower edge right to left
    for (std::size_t q = b; q < j; ++q) {
      const std::size_t i = order[q];
      up += vertex(x[i] - h, k * sigma[i]) + (h > 0 ? vertex(x[i] + h, k * sigma[i]) : "");
    }
    for (std::size_t q = j; q-- > b;) {
      const std::size_t i = order[q];
      down += (h > 0 ? vertex(x[i] + h, -k * sigma[i]) : "") + vertex(x[i] - h, -k * sigma[i]);
    }
    down.pop_back();
    s += "<polygon class=\"band\" points=\"" + up + down + "\" fill=\"#d5e3f3\" stroke=\"none\"/>\n";
    b = j;
  }
  s += "<line class=\"zero\" x1=\"" + n2(a.left) + "\" y1=\"" + n2(a.Y(0)) + "\" x2=\"" + n2(a.right()) +
       "\" y2=\"" + n2(a.Y(0)) + "\" stroke=\"#999\" stroke-width=\"0.6\"/>\n";
  for (std::size_t i = 0; i < x.size() && i < y.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i])) continue;
    if (i < style.flagged.size() && style.flagged[i]) {
      s += cross(a.X(x[i]), a.Y(y[i]), 3, "flagged", "#d62728");
      continue;
    }
    const bool ok = used.empty() || used[i];
    s += "<circle class=\"" + std::string(ok ? "point" : "rejected-point") + "\" cx=\"" + n2(a.X(x[i])) +
         "\" cy=\"" + n2(a.Y(y[i])) + "\" r=\"1.80\" fill=\"" + (ok ? "#1f5fa8" : "none") + "\" stroke=\"" +
         (ok ? "none" : "#d62728") + "\"/>\n";
  }
  s += "</g>\n";
  s += svg_axes(a, x_label, y_label, 6, 4, 44);
  if (!style.key.empty()) {
    const double ky = a.bottom() + 48;
    s += "<g class=\"key\" font-size=\"11\"><circle cx=\"" + n2(a.left + 4) + "\" cy=\"" + n2(ky - 4) +
         "\" r=\"2.20\" fill=\"#1f5fa8\"/>" + text(a.left + 12, ky, "epoch") + "<rect x=\"" +
         n2(a.left + 60) + "\" y=\"" + n2(ky - 9) + "\" width=\"14\" height=\"10\" fill=\"#d5e3f3\"/>" +
         text(a.left + 78, ky, "±" + tick_label(k) + "σ") +
         cross(a.left + 124, ky - 4, 3, "key-flagged", "#d62728") +
         text(a.left + 132, ky, html_escape(style.key)) + "</g>\n";
  }
  s += "</svg>\n";
  return s;
}

}  // namespace

std::string svg_residual_scatter(const std::vector<double>& x, const std::vector<double>& y,
                                 const std::vector<double>& sigma, const std::vector<bool>& used,
                                 const std::string& x_label, const std::string& y_label,
                                 const std::string& id, const std::string& title) {
  return band_scatter(x, y, sigma, used, x_label, y_label, id, title, BandScatterStyle{});
}

std::string svg_correction_series(const std::vector<double>& t_s, const std::vector<double>& d_cm,
                                  const std::vector<double>& sigma_cm, const std::vector<bool>& flagged,
                                  const std::string& y_label, const std::string& id,
                                  const std::string& title) {
  BandScatterStyle style;
  style.band_k = 1;
  style.width = 700;
  style.flagged = flagged;
  style.key = "flagged PPK epoch (its fix dropped)";
  return band_scatter(t_s, d_cm, sigma_cm, {}, "time since the first epoch (s)", y_label, id, title, style);
}

std::string svg_autocorrelation(const std::vector<double>& lag_s, const std::vector<double>& rho,
                                const std::vector<double>& model_lag_s, const std::vector<double>& model_rho,
                                const std::string& y_label, const std::string& id, const std::string& title) {
  ChartAxes a;
  a.left = 60;
  a.top = 12;
  a.width = 420;
  a.height = 170;
  // ρ of a few pairs may leave [−1, 1]: the area takes in every point.
  double x1 = 0, y0 = -0.2, y1 = 1;
  for (double x : lag_s) x1 = std::max(x1, x);
  for (double x : model_lag_s) x1 = std::max(x1, x);
  for (double y : rho) y0 = std::min(y0, y), y1 = std::max(y1, y);
  a.x0 = 0, a.x1 = x1 > 0 ? x1 * 1.02 : 1, a.y0 = y0 - 0.05, a.y1 = y1 + 0.05;
  std::string s = svg_open(a.right() + 14, a.bottom() + 58, id, title);
  s += "<g class=\"data\">\n<line class=\"zero\" x1=\"" + n2(a.left) + "\" y1=\"" + n2(a.Y(0)) + "\" x2=\"" +
       n2(a.right()) + "\" y2=\"" + n2(a.Y(0)) + "\" stroke=\"#999\" stroke-width=\"0.6\"/>\n";
  std::string pts;
  for (std::size_t i = 0; i < model_lag_s.size() && i < model_rho.size(); ++i)
    pts += (pts.empty() ? "" : " ") + n2(a.X(model_lag_s[i])) + "," + n2(a.Y(model_rho[i]));
  if (!pts.empty())
    s += "<polyline class=\"model\" points=\"" + pts +
         "\" fill=\"none\" stroke=\"#d62728\" stroke-width=\"1.4\"/>\n";
  for (std::size_t i = 0; i < lag_s.size() && i < rho.size(); ++i)
    s += "<circle class=\"acf\" cx=\"" + n2(a.X(lag_s[i])) + "\" cy=\"" + n2(a.Y(rho[i])) +
         "\" r=\"2.20\" fill=\"#1f5fa8\"/>\n";
  s += "</g>\n";
  s += svg_axes(a, "time lag (s)", y_label, 6, 5, 44);
  const double ky = a.bottom() + 48;
  s += "<g class=\"key\" font-size=\"11\"><circle cx=\"" + n2(a.left + 4) + "\" cy=\"" + n2(ky - 4) +
       "\" r=\"2.20\" fill=\"#1f5fa8\"/>" + text(a.left + 12, ky, "corrections (empirical)") + "<line x1=\"" +
       n2(a.left + 160) + "\" y1=\"" + n2(ky - 4) + "\" x2=\"" + n2(a.left + 180) + "\" y2=\"" + n2(ky - 4) +
       "\" stroke=\"#d62728\" stroke-width=\"1.4\"/>" + text(a.left + 186, ky, "error model") + "</g>\n";
  return s + "</svg>\n";
}

namespace {

/// Axes over a camera image, 520 drawing units wide: pixel edges −0.5 … W − 0.5, v down.
ChartAxes image_frame_axes(const PlotFrame& frame) {
  ChartAxes a;
  a.left = 56;
  a.top = 40;
  a.width = 520;
  a.height = 520.0 * std::max(1, frame.height_px) / std::max(1, frame.width_px);
  a.x0 = -0.5, a.x1 = frame.width_px - 0.5, a.y0 = -0.5, a.y1 = frame.height_px - 0.5;
  a.y_down = true;
  return a;
}

}  // namespace

std::string svg_image_map(const PlotFrame& frame, const std::vector<double>& u_px,
                          const std::vector<double>& v_px, const Eigen::MatrixXd& values,
                          const std::string& value_label, const std::string& id, const std::string& title,
                          const std::vector<Eigen::Vector2d>& marks) {
  const ChartAxes a = image_frame_axes(frame);
  double vmax = 0;
  for (Eigen::Index k = 0; k < values.size(); ++k)
    if (std::isfinite(values(k))) vmax = std::max(vmax, values(k));
  // The colour scale ends at a round value at or above the largest, so the bar's ticks reach it.
  const std::vector<double> t = nice_ticks(0, vmax > 0 ? vmax : 1, 4);
  double top_v = vmax > 0 ? vmax : 1;
  if (t.size() >= 2 && t.back() < top_v) top_v = t.back() + (t[1] - t[0]);
  std::string s = svg_open(a.right() + 100, a.bottom() + 14, id, title);
  s += "<g class=\"data\">\n" + svg_cells(a, u_px, v_px, values, top_v) +
       svg_contours(a, u_px, v_px, values, contour_levels(values, 5));
  for (const Eigen::Vector2d& p : marks) s += cross(a.X(p.x()), a.Y(p.y()), 3, "mark", "#ff2d2d");
  s += "</g>\n";
  s += svg_axes(a, "u (px), right", "v (px), down", 8, 5);
  s += svg_colour_bar(a.right() + 14, a.top, 14, a.height, top_v, value_label);
  return s + "</svg>\n";
}

std::string svg_image_vectors(const PlotFrame& frame, const std::vector<Eigen::Vector2d>& at,
                              const std::vector<Eigen::Vector2d>& vec, const std::string& what,
                              const std::string& id, const std::string& title) {
  const ChartAxes a = image_frame_axes(frame);
  const double scale = a.width / std::max(1, frame.width_px);  // drawing units per px
  double vmax = 0;
  for (const Eigen::Vector2d& v : vec) vmax = std::max(vmax, v.norm());
  const double gain = vmax > 0 ? a.width / 12 / vmax : 1;  // drawing units per px of displacement
  std::string s = svg_open(a.right() + 16, a.bottom() + 34, id, title);
  s += "<g class=\"data\">\n";
  for (std::size_t i = 0; i < at.size() && i < vec.size(); ++i) {
    Eigen::Vector2d p(a.X(at[i].x()), a.Y(at[i].y())), q = p + gain * vec[i];
    bool cut = false;
    if (!clip_segment(a.left, a.top, a.right(), a.bottom(), &p, &q, &cut)) continue;
    s += "<line class=\"vector\" x1=\"" + n2(p.x()) + "\" y1=\"" + n2(p.y()) + "\" x2=\"" + n2(q.x()) +
         "\" y2=\"" + n2(q.y()) + "\" stroke=\"#6a3d9a\" stroke-width=\"1\"/>\n<circle class=\"foot\" cx=\"" +
         n2(p.x()) + "\" cy=\"" + n2(p.y()) + "\" r=\"1.20\" fill=\"#333\"/>\n";
  }
  s += "</g>\n";
  s += svg_axes(a, "u (px), right", "v (px), down", 8, 5);
  const double bar = vmax > 0 ? nice_floor(vmax) : 1, ky = a.bottom() + 22;
  s += "<g class=\"key\" font-size=\"11\"><line x1=\"" + n2(a.left) + "\" y1=\"" + n2(ky) + "\" x2=\"" +
       n2(a.left + gain * bar) + "\" y2=\"" + n2(ky) + "\" stroke=\"#000\" stroke-width=\"2\"/>" +
       text(a.left + gain * bar + 6, ky + 4,
            tick_label(bar) + " px " + html_escape(what) + " (magnified " + tick_label(gain / scale) +
                "x; largest " + format_number("%.3g", vmax) + " px)") +
       "</g>\n</svg>\n";
  return s;
}

std::string svg_correlation_grid(const std::vector<std::string>& names, const Eigen::MatrixXd& rho,
                                 const std::string& id) {
  const int n = static_cast<int>(names.size());
  const double c = n > 0 ? std::min(34.0, 440.0 / n) : 34;
  ChartAxes a;
  a.left = 96;
  a.top = 10;
  a.width = a.height = std::max(1, n) * c;
  a.x0 = 0, a.x1 = std::max(1, n), a.y0 = 0, a.y1 = std::max(1, n);
  a.y_down = true;
  std::string s = svg_open(a.right() + 140, a.bottom() + 96, id, "Correlation of the estimated parameters");
  s += "<rect class=\"area\" x=\"" + n2(a.left) + "\" y=\"" + n2(a.top) + "\" width=\"" + n2(a.width) +
       "\" height=\"" + n2(a.height) +
       "\" fill=\"none\" stroke=\"#333\"/>\n<g class=\"data\" font-size=\"9\">\n";
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double r = rho(i, j);
      const double x = a.left + j * c, y = a.top + i * c;
      s += "<rect class=\"corr\" x=\"" + n2(x) + "\" y=\"" + n2(y) + "\" width=\"" + n2(c) + "\" height=\"" +
           n2(c) + "\" fill=\"" + diverging_colour(r) + "\" data-row=\"" + html_escape(names[i]) +
           "\" data-col=\"" + html_escape(names[j]) + "\" data-rho=\"" + format_number("%.4f", r) +
           "\"><title>ρ(" + html_escape(names[i]) + ", " + html_escape(names[j]) +
           ") = " + format_number("%.4f", r) + "</title></rect>\n";
      if (c >= 24)
        s += "<text x=\"" + n2(x + c / 2) + "\" y=\"" + n2(y + c / 2 + 3) +
             "\" text-anchor=\"middle\" fill=\"" + (std::abs(r) > 0.6 ? "#fff" : "#000") + "\">" +
             format_number("%.2f", r) + "</text>\n";
    }
  s += "</g>\n<g class=\"ticks\" font-size=\"10\">\n";
  for (int i = 0; i < n; ++i) {
    s += text(a.left - 5, a.top + i * c + c / 2 + 3.5, html_escape(names[i]), " text-anchor=\"end\"") + "\n";
    const double x = a.left + i * c + c / 2, y = a.bottom() + 6;
    s += "<text x=\"" + n2(x) + "\" y=\"" + n2(y) + "\" transform=\"rotate(60 " + n2(x) + " " + n2(y) +
         ")\">" + html_escape(names[i]) + "</text>\n";
  }
  s += "</g>\n";
  s += "<text class=\"xlabel\" x=\"" + n2(a.left + a.width / 2) + "\" y=\"" + n2(a.bottom() + 88) +
       "\" font-size=\"11\" text-anchor=\"middle\">parameter (unit as in the table above)</text>\n";
  const double yx = 14, yy = a.top + a.height / 2;
  s += "<text class=\"ylabel\" x=\"" + n2(yx) + "\" y=\"" + n2(yy) + "\" transform=\"rotate(-90 " + n2(yx) +
       " " + n2(yy) +
       ")\" font-size=\"11\" text-anchor=\"middle\">parameter (unit as in the table above)</text>\n";
  // Key: the diverging scale.
  s += "<g class=\"key\" font-size=\"10\">";
  for (int k = 0; k <= 10; ++k)
    s += "<rect x=\"" + n2(a.right() + 20) + "\" y=\"" + n2(a.top + k * 12) +
         "\" width=\"14\" height=\"12\" fill=\"" + diverging_colour(1 - k * 0.2) + "\"/>";
  s += text(a.right() + 38, a.top + 9, "ρ = +1 (1)") + text(a.right() + 38, a.top + 69, "0") +
       text(a.right() + 38, a.top + 129, "−1") + "</g>\n</svg>\n";
  return s;
}

std::string svg_pole_bars(const std::vector<std::string>& ids, const std::vector<Eigen::Vector3d>& d_cm,
                          const std::vector<Eigen::Vector3d>& sigma_cm, const std::string& id) {
  const std::size_t n = ids.size();
  ChartAxes a;
  a.left = 60;
  a.top = 12;
  a.width = std::max(200.0, std::min(760.0, 54.0 * static_cast<double>(n)));
  a.height = 200;
  double ymax = 0;
  for (std::size_t k = 0; k < n; ++k)
    for (int i = 0; i < 3; ++i) {
      if (std::isfinite(d_cm[k][i])) ymax = std::max(ymax, std::abs(d_cm[k][i]));
      if (k < sigma_cm.size() && std::isfinite(sigma_cm[k][i])) ymax = std::max(ymax, sigma_cm[k][i]);
    }
  ymax = ymax > 0 ? ymax * 1.15 : 1;
  a.x0 = 0, a.x1 = static_cast<double>(std::max<std::size_t>(1, n)), a.y0 = -ymax, a.y1 = ymax;
  static const char* colours[3] = {"#1f77b4", "#2ca02c", "#d62728"};
  std::string s = svg_open(a.right() + 16, a.bottom() + 58, id, "Check-pole errors with predicted 1σ");
  s += "<g class=\"data\">\n<line class=\"zero\" x1=\"" + n2(a.left) + "\" y1=\"" + n2(a.Y(0)) + "\" x2=\"" +
       n2(a.right()) + "\" y2=\"" + n2(a.Y(0)) + "\" stroke=\"#999\" stroke-width=\"0.6\"/>\n";
  const double gw = a.width / static_cast<double>(std::max<std::size_t>(1, n)), bw = gw / 4.5;
  for (std::size_t k = 0; k < n; ++k)
    for (int i = 0; i < 3; ++i) {
      const double x = a.left + k * gw + gw * 0.12 + i * (bw + 1);
      if (k < sigma_cm.size() && std::isfinite(sigma_cm[k][i]))
        s += "<rect class=\"sigma\" x=\"" + n2(x - 1) + "\" y=\"" + n2(a.Y(sigma_cm[k][i])) + "\" width=\"" +
             n2(bw + 2) + "\" height=\"" + n2(a.Y(-sigma_cm[k][i]) - a.Y(sigma_cm[k][i])) +
             "\" fill=\"#e3e3e3\"/>\n";
      if (!std::isfinite(d_cm[k][i])) continue;
      const double y0 = a.Y(0), y1 = a.Y(d_cm[k][i]);
      s += "<rect class=\"error\" x=\"" + n2(x) + "\" y=\"" + n2(std::min(y0, y1)) + "\" width=\"" + n2(bw) +
           "\" height=\"" + n2(std::abs(y1 - y0)) + "\" fill=\"" + colours[i] + "\" data-value-cm=\"" +
           format_number("%.4f", d_cm[k][i]) + "\"><title>" + html_escape(ids[k]) + " Δ" + "ENU"[i] + " " +
           format_number("%.2f", d_cm[k][i]) + " cm</title></rect>\n";
    }
  s += "</g>\n";
  s += svg_axes(a, "check pole (id)", "intersected − surveyed (cm)", 0, 5);
  s += "<g class=\"ticks\" font-size=\"10\">";
  for (std::size_t k = 0; k < n; ++k)
    s += text(a.left + (k + 0.5) * gw, a.bottom() + 14, html_escape(ids[k]), " text-anchor=\"middle\"");
  s += "</g>\n<g class=\"key\" font-size=\"11\">";
  const double ky = a.bottom() + 50;
  for (int i = 0; i < 3; ++i)
    s += "<rect x=\"" + n2(a.left + i * 60) + "\" y=\"" + n2(ky - 9) +
         "\" width=\"10\" height=\"10\" fill=\"" + colours[i] + "\"/>" +
         text(a.left + i * 60 + 14, ky, std::string("Δ") + "ENU"[i]);
  s += "<rect x=\"" + n2(a.left + 180) + "\" y=\"" + n2(ky - 9) +
       "\" width=\"10\" height=\"10\" fill=\"#e3e3e3\"/>" + text(a.left + 194, ky, "predicted ±1σ per axis") +
       "</g>\n</svg>\n";
  return s;
}

std::string svg_slice_map(const IntersectionSigmaSlice& sl, const std::vector<Eigen::Vector2d>& poles_en,
                          const std::string& id) {
  ChartAxes a;
  a.left = 60;
  a.top = 14;
  a.width = 440;
  a.height = 360;
  const double de = sl.e_m.size() > 1 ? sl.e_m[1] - sl.e_m[0] : 1,
               dn = sl.n_m.size() > 1 ? sl.n_m[1] - sl.n_m[0] : 1;
  const Eigen::Vector2d er(sl.e_m.front() - de / 2, sl.e_m.back() + de / 2),
      nr(sl.n_m.front() - dn / 2, sl.n_m.back() + dn / 2);
  // Equal scales: shrink the area to the slice's shape.
  const double s_m = std::min(a.width / (er[1] - er[0]), a.height / (nr[1] - nr[0]));
  a.width = (er[1] - er[0]) * s_m;
  a.height = (nr[1] - nr[0]) * s_m;
  a.x0 = er[0], a.x1 = er[1], a.y0 = nr[0], a.y1 = nr[1];
  const Eigen::MatrixXd cm = sl.sigma_m * 100.0;
  double vmax = 0;
  for (Eigen::Index k = 0; k < cm.size(); ++k)
    if (std::isfinite(cm(k))) vmax = std::max(vmax, cm(k));
  const std::vector<double> t = nice_ticks(0, vmax > 0 ? vmax : 1, 4);
  double top_v = vmax > 0 ? vmax : 1;
  if (t.size() >= 2 && t.back() < top_v) top_v = t.back() + (t[1] - t[0]);
  std::string s = svg_open(std::max(a.right() + 100, 600.0), a.bottom() + 56, id,
                           "Predicted intersection σ over a horizontal slice");
  s += "<g class=\"data\">\n" + svg_cells(a, sl.e_m, sl.n_m, cm, top_v) +
       svg_contours(a, sl.e_m, sl.n_m, cm, contour_levels(cm, 6));
  for (const Eigen::Vector2d& p : poles_en)
    if (p.x() >= a.x0 && p.x() <= a.x1 && p.y() >= a.y0 && p.y() <= a.y1)
      s += "<rect class=\"check-pole\" x=\"" + n2(a.X(p.x()) - 2.5) + "\" y=\"" + n2(a.Y(p.y()) - 2.5) +
           "\" width=\"5.00\" height=\"5.00\" fill=\"#fff\" stroke=\"#000\"/>\n";
  s += "</g>\n";
  s += svg_axes(a, "E (m), east", "N (m), north");
  s += svg_colour_bar(a.right() + 14, a.top, 14, a.height, top_v, "σ (cm), calibration only");
  s += "<g class=\"key\" font-size=\"11\">" +
       text(a.left, a.bottom() + 46,
            "at U = " + format_number("%.2f", sl.up_m) +
                " m; blank: seen by fewer than two cameras; squares: check poles") +
       "</g>\n</svg>\n";
  return s;
}

std::string svg_funnel(const std::vector<FunnelRow>& rows, const std::string& id) {
  static const char* drop_colours[] = {"#d62728", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"};
  ChartAxes a;
  a.left = 200;
  a.top = 10;
  a.width = 420;
  a.height = 20.0 * static_cast<double>(std::max<std::size_t>(1, rows.size()));
  a.x0 = 0, a.x1 = 100, a.y0 = 0, a.y1 = 1;
  std::string s = svg_open(a.right() + 120, a.bottom() + 40, id, "Data funnel");
  s += "<g class=\"data\">\n";
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const FunnelRow& f = rows[r];
    const double y = a.top + 20.0 * r + 3, h = 14, in = std::max<long long>(1, f.in);
    double x = a.left;
    const double wk = a.width * static_cast<double>(f.kept) / in;
    s += "<rect class=\"kept\" x=\"" + n2(x) + "\" y=\"" + n2(y) + "\" width=\"" + n2(wk) + "\" height=\"" +
         n2(h) + "\" fill=\"#4caf50\"><title>kept " + std::to_string(f.kept) + "</title></rect>\n";
    x += wk;
    for (std::size_t k = 0; k < f.dropped.size(); ++k) {
      const double w = std::min(a.right() - x, a.width * static_cast<double>(f.dropped[k].count) / in);
      if (!(w > 0)) continue;
      s += "<rect class=\"dropped\" x=\"" + n2(x) + "\" y=\"" + n2(y) + "\" width=\"" + n2(w) +
           "\" height=\"" + n2(h) + "\" fill=\"" + drop_colours[k % 6] + "\"><title>" +
           html_escape(f.dropped[k].reason) + ": " + std::to_string(f.dropped[k].count) + "</title></rect>\n";
      x += w;
    }
  }
  s += "</g>\n";
  s += svg_axes(a, "share of the stage's input (%)", "stage, camera (unit)", 5, 0, 190);
  s += "<g class=\"ticks\" font-size=\"10\">";
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const FunnelRow& f = rows[r];
    const double y = a.top + 20.0 * r + 14;
    s += text(a.left - 6, y,
              html_escape(f.stage + (f.camera.empty() ? "" : " " + f.camera) + " (" + f.unit + ")"),
              " text-anchor=\"end\"");
    s += text(a.right() + 6, y, std::to_string(f.kept) + " / " + std::to_string(f.in) + " kept");
  }
  s += "</g>\n</svg>\n";
  return s;
}

}  // namespace rangecal
