// `rangecal project --calibration CAL.json --points PTS.csv [--geodetic]` (docs/cli.md): `id,E,N,U`
// (world ENU, metres) — or with --geodetic `id,lat,lon,h` (WGS84 degrees, ellipsoidal metres,
// converted about the site origin calibration.json names) — in, `id,u,v` (pixels, centre of the
// top-left pixel = (0, 0)) out on stdout.
#include <iostream>
#include <memory>
#include <string>

#include "config/csv_table.hpp"
#include "pipeline/cli/commands.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "vision/camera/point_projection.hpp"

namespace rangecal {

void add_project_command(CLI::App& app, const CliContext& /*ctx*/) {
  struct Args {
    std::string calibration, points;
    bool geodetic = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub =
      app.add_subcommand("project", "Project world points (id,E,N,U) to pixels (id,u,v) on stdout");
  sub->add_option("--calibration", args->calibration, "calibration.json written by rangecal")->required();
  sub->add_option("--points", args->points,
                  "CSV with columns id,E,N,U (local ENU metres), or id,lat,lon,h with --geodetic")
      ->required();
  sub->add_flag("--geodetic", args->geodetic,
                "points are id,lat,lon,h (WGS84 degrees, ellipsoidal height m), placed with the site "
                "origin recorded in calibration.json");
  sub->callback([args]() {
    const CalibrationResult cal = read_calibration_json(args->calibration);
    const std::string text = read_file_text(args->points);
    if (!args->geodetic) {
      std::cout << project_points_csv(cal.camera, text, args->points, args->calibration) << std::flush;
      return;
    }
    std::cout << project_geodetic_points_csv(cal.camera, require_site_origin(cal, args->calibration), text,
                                             args->points, args->calibration)
              << std::flush;
  });
}

}  // namespace rangecal
