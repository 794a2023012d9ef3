// `rangecal project --calibration CAL.json --points PTS.csv` (SPEC §6): `id,E,N,U` (world ENU,
// metres) in, `id,u,v` (pixels, centre of the top-left pixel = (0, 0)) out on stdout.
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
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub =
      app.add_subcommand("project", "Project world points (id,E,N,U) to pixels (id,u,v) on stdout");
  sub->add_option("--calibration", args->calibration, "calibration.json written by rangecal")->required();
  sub->add_option("--points", args->points, "CSV with columns id,E,N,U (local ENU metres)")->required();
  sub->callback([args]() {
    const CalibrationResult cal = read_calibration_json(args->calibration);
    std::cout << project_points_csv(cal.camera, read_file_text(args->points), args->points) << std::flush;
  });
}

}  // namespace rangecal
