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
#include "pipeline/analysis/network_plan.hpp"
#include "pipeline/analysis/plan_tables.hpp"
#include "pipeline/analysis/route_plan.hpp"
#include "pipeline/analysis/target_path_plan.hpp"
#include "pipeline/analysis/target_path_table.hpp"
#include "pipeline/cli/commands.hpp"
#include "pipeline/io/target_path_csv.hpp"
#include "pipeline/simulate/scenario.hpp"
#include "pipeline/steps/calibration_problem.hpp"

namespace rangecal {
namespace {

// The candidate's cameras calibrated together on its routes (the network's bound over `free`),
// then the path triangulated from them.
TargetPathCandidate plan_target_path_of(const Scenario& s, const std::string& name,
                                        const std::vector<TargetPathPoint>& path,
                                        const std::vector<std::string>& free, const PlanOptions& o,
                                        const TargetPathOptions& target) {
  TargetPathCandidate c;
  c.name = name;
  for (const ScenarioCamera& cam : s.cameras) c.cameras.push_back(cam.id);
  const PlannedNetwork n = planned_network(s, o);
  const Eigen::MatrixXd joint = network_cramer_rao_bound(n, free, o.pixel_sigma_px);
  c.calibration_known = joint.size() > 0;
  c.plan = plan_target_path(n.truth, expand_free_parameters(free), joint, path, target);
  return c;
}

}  // namespace

void add_plan_command(CLI::App& app, const CliContext& /*ctx*/) {
  struct Args {
    std::vector<std::string> scenarios;
    std::string free;  ///< empty: the first scenario's mission_calibrate.free, else f,k1,pose
    double pixel_sigma_px = kDefaultPixelSigmaPx;
    std::string html;
    std::string target_path;  ///< a planned target path (CSV t_s,E,N,U); empty: none
    std::string target_csv;
    TargetPathOptions target;
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
  sub->add_option(
      "--target-path", args->target_path,
      "A target's planned path (CSV t_s,E,N,U in the site ENU): predict the trajectory σ along it "
      "for each candidate's camera stations");
  sub->add_option("--target-label-sigma", args->target.label_sigma_px,
                  "The target's label σ, px (default 0.5)");
  sub->add_option("--target-timing-sigma", args->target.timing_sigma_s,
                  "A label's instant's σ, s (default 0.001)");
  sub->add_option("--target-rate", args->target.rate_hz, "Instants per second along the path (default 10)");
  sub->add_option("--target-csv", args->target_csv, "Also write the path's σ per instant as CSV here");
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
    // The target path is read, and its options checked, before any work.
    std::vector<TargetPathPoint> path;
    if (!args->target_path.empty()) {
      path = read_target_path_csv(args->target_path);
      check_target_path_options(args->target, path);
    } else if (!args->target_csv.empty()) {
      throw_config_error("", "--target-csv", "needs --target-path (the path whose σ it would hold)");
    }
    std::vector<RoutePlanAnalysis> cands;
    for (std::size_t i = 0; i < scenarios.size(); ++i)
      cands.push_back(
          analyse_route_plan(scenarios[i], std::filesystem::path(args->scenarios[i]).stem().string(), o));
    std::vector<TargetPathCandidate> targets;
    if (!path.empty())
      for (std::size_t i = 0; i < scenarios.size(); ++i)
        targets.push_back(plan_target_path_of(scenarios[i], cands[i].name, path, base, o, args->target));
    if (!args->html.empty()) write_file_atomic(args->html, format_plan_html(cands));
    if (!args->target_csv.empty()) write_file_atomic(args->target_csv, target_path_csv_text(targets));
    std::cout << format_plan_table(cands);
    if (!targets.empty())
      std::cout << format_target_path_table(targets, args->target_path, base, args->target);
  });
}

}  // namespace rangecal
