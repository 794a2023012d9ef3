// `rangecal compare-calibrations A.json B.json [--distance M] [--grid NX NY] [--html FILE]`: the
// projection difference between two calibrations of one camera over the image, judged against their
// combined σ (pipeline/report/calibration_difference.hpp); a table on stdout, the map in HTML.
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "config/atomic_file.hpp"
#include "config/error.hpp"
#include "pipeline/cli/commands.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/report/calibration_difference.hpp"
#include "pipeline/report/calibration_difference_html.hpp"

namespace rangecal {

void add_compare_command(CLI::App& app, const CliContext& /*ctx*/) {
  struct Args {
    std::string a, b, html;
    double distance_m = 0;
    std::vector<int> grid = {9, 5};
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand(
      "compare-calibrations",
      "Projection difference between two calibrations of one camera against their combined sigma");
  sub->add_option("A", args->a, "calibration.json (the reference: its rays place the points)")->required();
  sub->add_option("B", args->b, "calibration.json of the same camera")->required();
  sub->add_option("--distance", args->distance_m,
                  "depth (m) of the compared points in front of camera A (default: the site origin's depth)");
  sub->add_option("--grid", args->grid, "cells across and down the image (default 9 5)")->expected(2);
  sub->add_option("--html", args->html, "also write the map as a self-contained HTML page");
  sub->callback([args]() {
    const CalibrationResult a = read_calibration_json(args->a);
    const CalibrationResult b = read_calibration_json(args->b);
    double depth = args->distance_m;
    if (depth == 0) depth = site_origin_depth_m(a.camera);
    if (!(depth > 0) || !std::isfinite(depth))
      throw Error(
          ErrorKind::usage, "", 0, "--distance",
          "the site origin is behind camera A (or --distance is not positive); give --distance M > 0");
    if (args->grid.size() != 2 || args->grid[0] < 1 || args->grid[1] < 1 || args->grid[0] > 200 ||
        args->grid[1] > 200)
      throw Error(ErrorKind::usage, "", 0, "--grid", "two cell counts between 1 and 200");
    const CalibrationDifference d = compare_calibrations(a, b, depth, args->grid[0], args->grid[1], args->b);
    std::cout << "A: " << args->a << "\nB: " << args->b << "\n" << format_difference_table(d) << std::flush;
    if (!args->html.empty())
      write_file_atomic(args->html, render_difference_html(d, args->a, args->b, a.camera.intr.width_px,
                                                           a.camera.intr.height_px));
  });
}

}  // namespace rangecal
