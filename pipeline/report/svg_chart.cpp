#include "pipeline/report/svg_chart.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "config/number_format.hpp"
#include "pipeline/report/html_escape.hpp"

namespace rangecal {
namespace {

std::string hex_colour(double r, double g, double b) {
  auto c = [](double x) { return static_cast<int>(std::lround(std::clamp(x, 0.0, 1.0) * 255)); };
  return fmt::format("#{:02x}{:02x}{:02x}", c(r), c(g), c(b));
}

// Linear interpolation between colour stops (r, g, b in [0, 1]).
template <std::size_t N>
std::string interpolate(const std::array<std::array<double, 3>, N>& stops, double t) {
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * (N - 1);
  const std::size_t k = std::min<std::size_t>(N - 2, static_cast<std::size_t>(t));
  const double f = t - static_cast<double>(k);
  return hex_colour(stops[k][0] + f * (stops[k + 1][0] - stops[k][0]),
                    stops[k][1] + f * (stops[k + 1][1] - stops[k][1]),
                    stops[k][2] + f * (stops[k + 1][2] - stops[k][2]));
}

}  // namespace

std::vector<double> nice_ticks(double lo, double hi, int n) {
  std::vector<double> t;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi) || n < 1) return t;
  const double raw = (hi - lo) / n, p = std::pow(10.0, std::floor(std::log10(raw))), m = raw / p;
  const double step = (m <= 1 ? 1 : m <= 2 ? 2 : m <= 5 ? 5 : 10) * p;
  const double eps = 1e-9 * step;
  for (double k = std::ceil((lo - eps) / step); k * step <= hi + eps; k += 1) {
    const double v = k * step;
    t.push_back(std::abs(v) < eps ? 0.0 : v);
  }
  return t;
}

std::string svg_num(double x) {
  return format_number("%.2f", x);
}

std::string tick_label(double x) {
  return format_number("%.4g", x);
}

std::string svg_open(double width, double height, const std::string& id, const std::string& title) {
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"" + html_escape(id) + "\" class=\"plot\" width=\"" +
         svg_num(width) + "\" height=\"" + svg_num(height) + "\" viewBox=\"0 0 " + svg_num(width) + " " +
         svg_num(height) + "\">\n<title>" + html_escape(title) + "</title>\n";
}

std::string svg_axes(const ChartAxes& a, const std::string& x_label, const std::string& y_label,
                     int n_ticks_x, int n_ticks_y, double ylabel_offset) {
  std::string s =
      "<rect class=\"area\" x=\"" + svg_num(a.left) + "\" y=\"" + svg_num(a.top) + "\" width=\"" +
      svg_num(a.width) + "\" height=\"" + svg_num(a.height) +
      "\" fill=\"none\" stroke=\"#333\" stroke-width=\"1\"/>\n<g class=\"ticks\" font-size=\"10\">\n";
  const double xlo = std::min(a.x0, a.x1), xhi = std::max(a.x0, a.x1);
  const double ylo = std::min(a.y0, a.y1), yhi = std::max(a.y0, a.y1);
  const double ty = a.y_down ? a.top : a.bottom(), dir = a.y_down ? -1 : 1;
  for (double v : nice_ticks(xlo, xhi, n_ticks_x)) {
    const double x = a.X(v);
    s += "<line x1=\"" + svg_num(x) + "\" y1=\"" + svg_num(ty) + "\" x2=\"" + svg_num(x) + "\" y2=\"" +
         svg_num(ty + dir * 4) + "\" stroke=\"#333\"/><text x=\"" + svg_num(x) + "\" y=\"" +
         svg_num(ty + (a.y_down ? -7 : 14)) + "\" text-anchor=\"middle\">" + tick_label(v) + "</text>\n";
  }
  for (double v : nice_ticks(ylo, yhi, n_ticks_y)) {
    const double y = a.Y(v);
    s += "<line x1=\"" + svg_num(a.left) + "\" y1=\"" + svg_num(y) + "\" x2=\"" + svg_num(a.left - 4) +
         "\" y2=\"" + svg_num(y) + "\" stroke=\"#333\"/><text x=\"" + svg_num(a.left - 6) + "\" y=\"" +
         svg_num(y + 3.5) + "\" text-anchor=\"end\">" + tick_label(v) + "</text>\n";
  }
  s += "</g>\n";
  const double lx = a.left + a.width / 2, ly = a.y_down ? a.top - 21 : a.bottom() + 29;
  s += "<text class=\"xlabel\" x=\"" + svg_num(lx) + "\" y=\"" + svg_num(ly) +
       "\" font-size=\"11\" text-anchor=\"middle\">" + html_escape(x_label) + "</text>\n";
  const double yx = a.left - ylabel_offset, yy = a.top + a.height / 2;
  s += "<text class=\"ylabel\" x=\"" + svg_num(yx) + "\" y=\"" + svg_num(yy) + "\" transform=\"rotate(-90 " +
       svg_num(yx) + " " + svg_num(yy) + ")\" font-size=\"11\" text-anchor=\"middle\">" +
       html_escape(y_label) + "</text>\n";
  return s;
}

std::string sequential_colour(double t) {
  static const std::array<std::array<double, 3>, 5> kViridis = {{{0.267, 0.005, 0.329},
                                                                 {0.229, 0.322, 0.545},
                                                                 {0.128, 0.567, 0.551},
                                                                 {0.369, 0.789, 0.383},
                                                                 {0.993, 0.906, 0.144}}};
  return interpolate(kViridis, t);
}

std::string diverging_colour(double t) {
  static const std::array<std::array<double, 3>, 3> kBwr = {
      {{0.230, 0.299, 0.754}, {0.97, 0.97, 0.97}, {0.706, 0.016, 0.150}}};
  return interpolate(kBwr, (std::clamp(std::isfinite(t) ? t : 0.0, -1.0, 1.0) + 1) / 2);
}

std::string svg_cells(const ChartAxes& a, const std::vector<double>& xc, const std::vector<double>& yc,
                      const Eigen::MatrixXd& values, double vmax) {
  std::string s;
  const double dx = xc.size() > 1 ? xc[1] - xc[0] : (a.x1 - a.x0);
  const double dy = yc.size() > 1 ? yc[1] - yc[0] : (a.y1 - a.y0);
  for (Eigen::Index j = 0; j < values.rows(); ++j)
    for (Eigen::Index i = 0; i < values.cols(); ++i) {
      const double v = values(j, i);
      if (!std::isfinite(v)) continue;
      const double xa = a.X(xc[i] - dx / 2), xb = a.X(xc[i] + dx / 2);
      const double ya = a.Y(yc[j] - dy / 2), yb = a.Y(yc[j] + dy / 2);
      s += "<rect class=\"cell\" x=\"" + svg_num(std::min(xa, xb)) + "\" y=\"" + svg_num(std::min(ya, yb)) +
           "\" width=\"" + svg_num(std::abs(xb - xa)) + "\" height=\"" + svg_num(std::abs(yb - ya)) +
           "\" fill=\"" + sequential_colour(vmax > 0 ? v / vmax : 0) + "\" data-value=\"" +
           format_number("%.6g", v) + "\"/>\n";
    }
  return s;
}

std::vector<double> contour_levels(const Eigen::MatrixXd& values, int n) {
  double lo = INFINITY, hi = -INFINITY;
  for (Eigen::Index k = 0; k < values.size(); ++k)
    if (std::isfinite(values(k))) lo = std::min(lo, values(k)), hi = std::max(hi, values(k));
  std::vector<double> out;
  if (!(hi > lo)) return out;
  for (double v : nice_ticks(lo, hi, n))
    if (v > lo && v < hi) out.push_back(v);
  return out;
}

std::string svg_contours(const ChartAxes& a, const std::vector<double>& xc, const std::vector<double>& yc,
                         const Eigen::MatrixXd& values, const std::vector<double>& levels) {
  std::string s;
  for (double L : levels) {
    std::string d;
    std::vector<Eigen::Vector2d> mids;
    for (Eigen::Index j = 0; j + 1 < values.rows(); ++j)
      for (Eigen::Index i = 0; i + 1 < values.cols(); ++i) {
        const std::array<Eigen::Index, 4> ci = {i, i + 1, i + 1, i}, cj = {j, j, j + 1, j + 1};
        std::array<double, 4> v;
        bool ok = true;
        for (int k = 0; k < 4; ++k) ok &= std::isfinite(v[k] = values(cj[k], ci[k]));
        if (!ok) continue;
        std::vector<Eigen::Vector2d> pts;
        for (int k = 0; k < 4; ++k) {
          const int m = (k + 1) % 4;
          if ((v[k] >= L) == (v[m] >= L)) continue;
          const double t = (L - v[k]) / (v[m] - v[k]);
          pts.emplace_back(a.X(xc[ci[k]] + t * (xc[ci[m]] - xc[ci[k]])),
                           a.Y(yc[cj[k]] + t * (yc[cj[m]] - yc[cj[k]])));
        }
        for (std::size_t k = 0; k + 1 < pts.size(); k += 2) {
          d += "M" + svg_num(pts[k].x()) + " " + svg_num(pts[k].y()) + "L" + svg_num(pts[k + 1].x()) + " " +
               svg_num(pts[k + 1].y());
          mids.push_back((pts[k] + pts[k + 1]) / 2);
        }
      }
    if (d.empty()) continue;
    s += "<path class=\"contour\" d=\"" + d + "\" fill=\"none\" stroke=\"#fff\" stroke-width=\"0.9\"/>\n";
    // The label at the middle segment far enough from the edges to keep the text inside the area.
    for (std::size_t k = 0; k < mids.size(); ++k) {
      const Eigen::Vector2d& p = mids[(mids.size() / 2 + k) % mids.size()];
      if (p.x() < a.left + 24 || p.x() > a.right() - 24 || p.y() < a.top + 12 || p.y() > a.bottom() - 6)
        continue;
      s += "<text class=\"contour-label\" x=\"" + svg_num(p.x()) + "\" y=\"" + svg_num(p.y()) +
           "\" font-size=\"9\" text-anchor=\"middle\" fill=\"#fff\" stroke=\"#000\" stroke-width=\"0.25\">" +
           tick_label(L) + "</text>\n";
      break;
    }
  }
  return s;
}

std::string svg_colour_bar(double x, double y, double w, double h, double vmax, const std::string& label) {
  std::string s = "<g class=\"colourbar\" font-size=\"10\">\n";
  const int n = 24;
  for (int k = 0; k < n; ++k)
    s += "<rect x=\"" + svg_num(x) + "\" y=\"" + svg_num(y + h - (k + 1) * h / n) + "\" width=\"" +
         svg_num(w) + "\" height=\"" + svg_num(h / n + 0.3) + "\" fill=\"" +
         sequential_colour((k + 0.5) / n) + "\"/>\n";
  s += "<rect x=\"" + svg_num(x) + "\" y=\"" + svg_num(y) + "\" width=\"" + svg_num(w) + "\" height=\"" +
       svg_num(h) + "\" fill=\"none\" stroke=\"#333\"/>\n";
  for (double v : nice_ticks(0, vmax, 4)) {
    const double ty = y + h - v / vmax * h;
    s += "<text x=\"" + svg_num(x + w + 4) + "\" y=\"" + svg_num(ty + 3.5) + "\">" + tick_label(v) +
         "</text>\n";
  }
  const double lx = x + w + 44, ly = y + h / 2;
  s += "<text class=\"barlabel\" x=\"" + svg_num(lx) + "\" y=\"" + svg_num(ly) +
       "\" transform=\"rotate(-90 " + svg_num(lx) + " " + svg_num(ly) +
       ")\" text-anchor=\"middle\" font-size=\"11\">" + html_escape(label) + "</text>\n</g>\n";
  return s;
}

bool clip_segment(double x0, double y0, double x1, double y1, Eigen::Vector2d* p, Eigen::Vector2d* q,
                  bool* clipped) {
  const Eigen::Vector2d d = *q - *p;
  double t0 = 0, t1 = 1;
  const double pp[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double qq[4] = {p->x() - x0, x1 - p->x(), p->y() - y0, y1 - p->y()};
  for (int k = 0; k < 4; ++k) {
    if (pp[k] == 0) {
      if (qq[k] < 0) return false;
      continue;
    }
    const double r = qq[k] / pp[k];
    if (pp[k] < 0)
      t0 = std::max(t0, r);
    else
      t1 = std::min(t1, r);
    if (t0 > t1) return false;
  }
  *clipped = t1 < 1;
  const Eigen::Vector2d p0 = *p;
  *p = p0 + t0 * d;
  *q = p0 + t1 * d;
  return true;
}

}  // namespace rangecal
