#include "pipeline/report/svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "config/number_format.hpp"
#include "pipeline/report/html_escape.hpp"

namespace rangecal {
namespace {

constexpr double kPlotWidth = 640;  // drawing width of image plots (SVG user units)
constexpr double kMargin = 36;      // room for axis labels

std::string f2(double x) {
  return format_number("%.2f", x);
}

// Short label of a round number (bin edges, scale bar): at most 3 significant digits.
std::string label(double x) {
  return format_number("%.3g", x);
}

// Pixel → drawing coordinates (pixel centres at +0.5 so the frame spans [−0.5, W−0.5]).
struct ImageMap {
  double scale = 1;
  double x(double u) const { return kMargin + (u + 0.5) * scale; }
  double y(double v) const { return kMargin + (v + 0.5) * scale; }
};

ImageMap image_map(const PlotFrame& f) {
  ImageMap m;
  m.scale = f.width_px > 0 ? kPlotWidth / f.width_px : 1.0;
  return m;
}

// Opens the svg with its frame rectangle and axis labels; returns the text so far.
std::string open_image_svg(const PlotFrame& f, const ImageMap& m, const std::string& id,
                           const std::string& title) {
  const double w = kPlotWidth + 2 * kMargin, h = std::max(1, f.height_px) * m.scale + 2 * kMargin;
  std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"" + html_escape(id) +
                  "\" class=\"plot\" width=\"" + f2(w) + "\" height=\"" + f2(h) + "\" viewBox=\"0 0 " +
                  f2(w) + " " + f2(h) + "\">\n";
  s += "<title>" + html_escape(title) + "</title>\n";
  s += "<rect class=\"frame\" x=\"" + f2(kMargin) + "\" y=\"" + f2(kMargin) + "\" width=\"" +
       f2(f.width_px * m.scale) + "\" height=\"" + f2(f.height_px * m.scale) +
       "\" fill=\"#fafafa\" stroke=\"#333\" stroke-width=\"1\"/>\n";
  s += "<text x=\"" + f2(kMargin) + "\" y=\"" + f2(kMargin - 8) + "\" font-size=\"11\">(0, 0)</text>\n";
  // Image size at the top right: the legend line below the frame needs the bottom.
  s += "<text x=\"" + f2(kMargin + f.width_px * m.scale) + "\" y=\"" + f2(kMargin - 8) +
       "\" font-size=\"11\" text-anchor=\"end\">" + std::to_string(f.width_px) + " x " +
       std::to_string(f.height_px) + " px, u right, v down</text>\n";
  return s;
}

}  // namespace

double nice_floor(double x) {
  if (!(x > 0) || !std::isfinite(x)) return 0;
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  const double m = x / p;  // in [1, 10) up to rounding
  const double n = m >= 5 ? 5 : m >= 2 ? 2 : m >= 1 ? 1 : 0.5;
  return n * p;
}

std::string svg_lamp_track(const PlotFrame& frame, const std::vector<Eigen::Vector2d>& observed,
                           const std::vector<Eigen::Vector2d>& reprojected, const std::vector<bool>& used,
                           const std::vector<std::size_t>& breaks, const std::string& id) {
  const ImageMap m = image_map(frame);
  std::string s = open_image_svg(frame, m, id, "Lamp track on the image (seed 002 Fig. 6)");
  std::size_t next_break = 0;
  for (std::size_t i = 0; i < observed.size(); ++i) {
    const bool starts = i == 0 || (next_break < breaks.size() && breaks[next_break] == i);
    if (starts && i > 0) {
      s += "\"/>\n";
      ++next_break;
    }
    if (starts)
      s += "<polyline class=\"track\" fill=\"none\" stroke=\"#7aa6d6\" stroke-width=\"0.8\" points=\"";
    else
      s += " ";
    s += f2(m.x(observed[i].x())) + "," + f2(m.y(observed[i].y()));
  }
  if (!observed.empty()) s += "\"/>\n";
  for (std::size_t i = 0; i < observed.size(); ++i) {
    const bool ok = used.empty() || used[i];
    s += "<circle class=\"" + std::string(ok ? "obs" : "rejected") + "\" cx=\"" + f2(m.x(observed[i].x())) +
         "\" cy=\"" + f2(m.y(observed[i].y())) + "\" r=\"2.00\" fill=\"" + (ok ? "none" : "#d62728") +
         "\" stroke=\"" + (ok ? "#1f5fa8" : "#d62728") + "\" stroke-width=\"0.8\"/>\n";
  }
  for (const Eigen::Vector2d& p : reprojected) {
    const double x = m.x(p.x()), y = m.y(p.y()), a = 2.5;
    s += "<path class=\"proj\" d=\"M" + f2(x - a) + " " + f2(y) + "H" + f2(x + a) + "M" + f2(x) + " " +
         f2(y - a) + "V" + f2(y + a) + "\" stroke=\"#e07b00\" stroke-width=\"0.8\"/>\n";
  }
  const double ly = kMargin + frame.height_px * m.scale + 14;
  s += "<text x=\"" + f2(kMargin) + "\" y=\"" + f2(ly) +
       "\" font-size=\"11\">o observed lamp pixel, + reprojected world point" +
       (reprojected.empty() ? std::string(" (none: not calibrated)") : std::string()) +
       ", red: rejected</text>\n";
  s += "</svg>\n";
  return s;
}

std::string svg_residual_vectors(const PlotFrame& frame, const std::vector<Eigen::Vector2d>& at,
                                 const std::vector<Eigen::Vector2d>& residual, const std::string& id) {
  const ImageMap m = image_map(frame);
  std::string s = open_image_svg(frame, m, id, "Reprojection residual vectors");
  double max_r = 0;
  for (const Eigen::Vector2d& r : residual) max_r = std::max(max_r, r.norm());
  // Drawing units per pixel of residual: the largest residual spans a tenth of the plot width.
  const double gain = max_r > 0 ? 0.1 * kPlotWidth / max_r : 1.0;
  const std::size_t n = std::min(at.size(), residual.size());
  for (std::size_t i = 0; i < n; ++i) {
    const double x = m.x(at[i].x()), y = m.y(at[i].y());
    s += "<line class=\"resid\" x1=\"" + f2(x) + "\" y1=\"" + f2(y) + "\" x2=\"" +
         f2(x + gain * residual[i].x()) + "\" y2=\"" + f2(y + gain * residual[i].y()) +
         "\" stroke=\"#c0392b\" stroke-width=\"1\"/>\n";
    s += "<circle class=\"foot\" cx=\"" + f2(x) + "\" cy=\"" + f2(y) + "\" r=\"1.20\" fill=\"#333\"/>\n";
  }
  // Scale bar: a round residual length, drawn at the bottom left below the frame.
  const double bar_px = max_r > 0 ? nice_floor(max_r) : 1.0;
  const double by = kMargin + frame.height_px * m.scale + 16, bx = kMargin;
  s += "<line class=\"scalebar\" x1=\"" + f2(bx) + "\" y1=\"" + f2(by) + "\" x2=\"" + f2(bx + gain * bar_px) +
       "\" y2=\"" + f2(by) + "\" stroke=\"#000\" stroke-width=\"2\"/>\n";
  s += "<text x=\"" + f2(bx + gain * bar_px + 6) + "\" y=\"" + f2(by + 4) + "\" font-size=\"11\">" +
       label(bar_px) + " px residual (vectors magnified " + label(gain / m.scale) + "x)</text>\n";
  s += "</svg>\n";
  return s;
}

std::string svg_histogram(const std::vector<double>& values, const std::string& x_label,
                          const std::string& id) {
  const double W = 480, H = 240, left = 44, right = 16, top = 16, bottom = 40;
  double max_v = 0;
  for (double v : values)
    if (std::isfinite(v)) max_v = std::max(max_v, v);
  // About ten round-width bins from 0 (at least one).
  const double bin = max_v > 0 ? nice_floor(max_v / 10.0) : 1.0;
  // Bin index of v; the tolerance puts a value on a bin edge (0.95 with bin 0.05, whose quotient is
  // 18.999…) into the bin it starts, as its label says.
  auto bin_of = [bin](double v) { return static_cast<std::size_t>(std::floor(v / bin + 1e-9)); };
  const std::size_t nbins = bin_of(max_v) + 1;
  std::vector<int> counts(nbins, 0);
  for (double v : values) {
    if (!std::isfinite(v) || v < 0) continue;
    const std::size_t k = std::min(nbins - 1, bin_of(v));
    ++counts[k];
  }
  const int max_c = std::max(1, *std::max_element(counts.begin(), counts.end()));
  const double pw = W - left - right, ph = H - top - bottom, bw = pw / static_cast<double>(nbins);
  std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"" + html_escape(id) +
                  "\" class=\"plot\" width=\"" + f2(W) + "\" height=\"" + f2(H) + "\" viewBox=\"0 0 " +
                  f2(W) + " " + f2(H) + "\">\n";
  s += "<title>Histogram: " + html_escape(x_label) + "</title>\n";
  for (std::size_t k = 0; k < nbins; ++k) {
    const double h = ph * counts[k] / max_c;
    s += "<rect class=\"bar\" x=\"" + f2(left + k * bw + 0.5) + "\" y=\"" + f2(top + ph - h) + "\" width=\"" +
         f2(std::max(0.5, bw - 1.0)) + "\" height=\"" + f2(h) + "\" fill=\"#5b8fc7\"><title>[" +
         label(k * bin) + ", " + label((k + 1) * bin) + "): " + std::to_string(counts[k]) +
         "</title></rect>\n";
  }
  s += "<line class=\"axis\" x1=\"" + f2(left) + "\" y1=\"" + f2(top + ph) + "\" x2=\"" + f2(left + pw) +
       "\" y2=\"" + f2(top + ph) + "\" stroke=\"#000\"/>\n";
  s += "<line class=\"axis\" x1=\"" + f2(left) + "\" y1=\"" + f2(top) + "\" x2=\"" + f2(left) + "\" y2=\"" +
       f2(top + ph) + "\" stroke=\"#000\"/>\n";
  // x ticks at every bin edge when few bins, else every other.
  const std::size_t step = nbins > 12 ? 2 : 1;
  for (std::size_t k = 0; k <= nbins; k += step)
    s += "<text x=\"" + f2(left + k * bw) + "\" y=\"" + f2(top + ph + 14) +
         "\" font-size=\"10\" text-anchor=\"middle\">" + label(k * bin) + "</text>\n";
  s += "<text x=\"" + f2(left - 4) + "\" y=\"" + f2(top + 4) + "\" font-size=\"10\" text-anchor=\"end\">" +
       std::to_string(max_c) + "</text>\n";
  s += "<text x=\"" + f2(left - 4) + "\" y=\"" + f2(top + ph) +
       "\" font-size=\"10\" text-anchor=\"end\">0</text>\n";
  s += "<text x=\"" + f2(left + pw / 2) + "\" y=\"" + f2(H - 6) +
       "\" font-size=\"11\" text-anchor=\"middle\">" + html_escape(x_label) + " (" +
       std::to_string(values.size()) + " values; bin " + label(bin) + ")</text>\n";
  s += "</svg>\n";
  return s;
}

}  // namespace rangecal
