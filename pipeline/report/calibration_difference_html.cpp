#include "pipeline/report/calibration_difference_html.hpp"

#include <cmath>

#include "config/number_format.hpp"
#include "pipeline/report/html_escape.hpp"
#include "pipeline/report/report_plots.hpp"

namespace rangecal {

std::string render_difference_html(const CalibrationDifference& d, const std::string& name_a,
                                   const std::string& name_b, int width_px, int height_px) {
  std::vector<double> u, v;
  for (int i = 0; i < d.nx; ++i) u.push_back(d.cells[static_cast<std::size_t>(i)].uv_px.x());
  for (int j = 0; j < d.ny; ++j) v.push_back(d.cells[static_cast<std::size_t>(j * d.nx)].uv_px.y());
  Eigen::MatrixXd norm(d.ny, d.nx);
  std::vector<Eigen::Vector2d> marks, at, vec;
  for (int j = 0; j < d.ny; ++j)
    for (int i = 0; i < d.nx; ++i) {
      const DifferenceCell& c = d.cells[static_cast<std::size_t>(j * d.nx + i)];
      norm(j, i) = c.diff_px.norm();
      if (c.exceeds) marks.push_back(c.uv_px);
      if (std::isfinite(c.diff_px.x())) at.push_back(c.uv_px), vec.push_back(c.diff_px);
    }
  const PlotFrame frame{width_px, height_px};
  std::string s =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>rangecal "
      "compare-calibrations</title>\n<style>body{font-family:sans-serif;margin:24px;color:#222}"
      "figure{display:inline-block;margin:8px 16px 8px 0;vertical-align:top}"
      "figcaption{font-size:12px;color:#555;max-width:640px}td,th{border:1px solid #bbb;padding:3px 8px}"
      "table{border-collapse:collapse}</style>\n</head>\n<body>\n<h1>Difference between two "
      "calibrations</h1>\n";
  s += "<table>\n<tr><th>A</th><td>" + html_escape(name_a) + "</td></tr>\n<tr><th>B</th><td>" +
       html_escape(name_b) + "</td></tr>\n<tr><th>depth</th><td>" + format_number("%.2f", d.depth_m) +
       " m</td></tr>\n<tr><th>max |&#916;|</th><td>" + format_number("%.4f", d.max_diff_px) +
       " px</td></tr>\n<tr><th>RMS |&#916;|</th><td>" + format_number("%.4f", d.rms_diff_px) +
       " px</td></tr>\n<tr><th>cells exceeding the combined &#963;</th><td>" +
       format_number("%.1f", 100 * d.fraction_exceeding) +
       " % (5 % expected from noise alone)</td></tr>\n</table>\n";
  s +=
      "<figure>" +
      svg_image_map(frame, u, v, norm, "|q_B − q_A| (px)", "difference-map", "Projection difference", marks) +
      "<figcaption>|q<sub>B</sub> &#8722; q<sub>A</sub>| (px) of a point " +
      format_number("%.1f", d.depth_m) +
      " m in front of camera A on the ray of each pixel; &#215;: exceeds the combined 1&#963; ellipse by "
      "more "
      "than &#8730;&#967;&#178;<sub>2</sub>(0.95) = 2.45</figcaption></figure>\n";
  s += "<figure>" +
       svg_image_vectors(frame, at, vec, "difference", "difference-vectors", "Difference vectors") +
       "<figcaption>q<sub>B</sub> &#8722; q<sub>A</sub> (px), magnified</figcaption></figure>\n";
  return s + "</body>\n</html>\n";
}

}  // namespace rangecal
