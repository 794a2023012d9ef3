// `rangecal plan SCENARIO.json [MORE.json ...] [--free LIST] [--pixel-sigma PX] [--html FILE]` (docs/cli.md,
// docs/accuracy_analysis.md): the Cramér–Rao bound of each calibration parameter, per camera and for the
// network, the calibration-only intersection σ through the flight volume for both methods and the
// predicted intersection 1σ at the poles from the scenario's camera stations and routes alone
// (pipeline/analysis/route_plan.hpp, plan_tables.hpp). Several scenarios are candidate route sets, compared
// side by side. The scenario format has no room for alternative routes (pipeline/simulate/scenario.cpp
// rejects unknown keys, and `simulate` must keep reading the same file), so each candidate is its own
// scenario file, named by its file stem.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "config/atomic_file.hpp"
#include "config/error.hpp"
#include "pipeline/analysis/plan_tables.hpp"
#include "pipeline/analysis/route_plan.hpp"
#include "pipeline/cli/commands.hpp"
#include "pipeline/simulate/scenario.hpp"
#include "pipeline/steps/calibration_problem.hpp"

namespace rangecal {

void add_plan_command(CLI::App& app, const CliContext& /*ctx*/) {
  struct Args {
    std::vector<std::string> scenarios;
    std::string free;  ///< empty: the first scenario's mission_calibrate.free, else f,k1,pose
    double pixel_sigma_px = kDefaultPixelSigmaPx;
    std::string html;
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand(
      "plan",
      "Predict calibration σ (Cramér–Rao, per camera and network), flight-volume and pole "
      "intersection 1σ from scenario files; several files are candidate route sets compared side by "
      "side");
  sub->add_option("SCENARIO", args->scenarios, "Scenario file(s) (JSON, docs/simulator.md)")->required();
  sub->add_option(
      "--free", args->free,
      "Free parameters (comma-separated; default: the first scenario's mission_calibrate.free, else "
      "f,k1,pose; also sx, k2, k3, p1, p2, a1, a2, rotation, center, clock_offset); the same set "
      "with u0,v0 is analysed too");
  sub->add_option("--pixel-sigma", args->pixel_sigma_px, "Lamp centroid σ, px (default 0.1)");
  sub->add_option("--html", args->html, "Also write the tables as a self-contained HTML page here");
  sub->callback([args]() {
    if (!(args->pixel_sigma_px > 0)) throw_config_error("", "--pixel-sigma", "must be positive");
    PlanOptions o;
    o.pixel_sigma_px = args->pixel_sigma_px;
    std::vector<Scenario> scenarios;
    for (const std::string& path : args->scenarios) scenarios.push_back(load_scenario(path));
    std::vector<std::string> base;
    if (args->free.empty()) {
      base = scenario_free_parameters(scenarios.front());
    } else {
      std::stringstream ss(args->free);
      for (std::string item; std::getline(ss, item, ',');)
        if (!item.empty()) base.push_back(item);
    }
    expand_free_parameters(base, "", "--free");  // names checked here, before any work
    if (base.empty()) throw_config_error("", "--free", "no parameters given");
    std::vector<std::string> with_pp = base;
    for (const CameraParameter p : {CameraParameter::u0, CameraParameter::v0})
      if (std::find(with_pp.begin(), with_pp.end(), parameter_name(p)) == with_pp.end())
        with_pp.push_back(parameter_name(p));
    o.free_sets = {base};
    if (with_pp != base) o.free_sets.push_back(with_pp);
    std::vector<RoutePlanAnalysis> cands;
    for (std::size_t i = 0; i < scenarios.size(); ++i)
      cands.push_back(
          analyse_route_plan(scenarios[i], std::filesystem::path(args->scenarios[i]).stem().string(), o));
    if (!args->html.empty()) write_file_atomic(args->html, format_plan_html(cands));
    std::cout << format_plan_table(cands);
  });
}

}  // namespace rangecal
