// `rangecal intersect` (docs/cli.md), both forms on one subcommand:
//   rangecal intersect CONFIG      the mission's intersect stage (pipeline/stages/intersect_stage.hpp)
//   rangecal intersect --calibration A.json --observations A.csv --calibration B.json
//                      --observations B.csv [...]
//                                  picks `id,u,v` per camera in (pairs matched in order), triangulated
//                                  `id,E,N,U,rms_px` out on stdout, no survey; with --geodetic
//                                  `id,lat,lon,h,rms_px` (WGS84 degrees, ellipsoidal metres) about
//                                  the site origin the calibrations record.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "gnss/geodesy/local_enu.hpp"
#include "pipeline/cli/commands.hpp"
#include "pipeline/cli/stage_command.hpp"
#include "pipeline/cli/stage_summary.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/stages/intersect_stage.hpp"
#include "pipeline/stages/mission_runner.hpp"
#include "pipeline/steps/intersection.hpp"
#include "vision/triangulation/calibration_covariance.hpp"

namespace rangecal {

namespace {

/// Default pick σ of the standalone form. With one σ for every camera it does not move the point
/// (equal weights); it only scales the predicted σ, which this form does not print.
constexpr double kStandalonePickSigmaPx = 0.5;

[[noreturn]] void usage_error(const std::string& field, const std::string& reason) {
  throw Error(ErrorKind::usage, "", 0, field, reason);
}

/// `id,E,N,U,rms_px`: metres and pixels with 4 decimals (0.1 mm; 1 px is ~1 cm at 64 m).
std::string format_points_csv(const IntersectionResult& r) {
  std::string s = "id,E,N,U,rms_px\n";
  for (const PoleIntersection& p : r.poles)
    s += p.id + fmt::format(",{:.4f},{:.4f},{:.4f},{:.4f}\n", p.enu.x(), p.enu.y(), p.enu.z(), p.rms_px);
  return s;
}

/// `id,lat,lon,h,rms_px`: WGS84 degrees with 9 decimals (0.1 mm), ellipsoidal height in metres and
/// pixels with 4, the ENU points converted about `origin` (gnss/geodesy/local_enu.hpp).
std::string format_geodetic_points_csv(const IntersectionResult& r, const GeodeticOrigin& origin) {
  const LocalEnu site(origin);
  std::string s = "id,lat,lon,h,rms_px\n";
  for (const PoleIntersection& p : r.poles) {
    const Eigen::Vector3d llh = site.to_geodetic(p.enu);
    s += p.id + fmt::format(",{:.9f},{:.9f},{:.4f},{:.4f}\n", llh[0], llh[1], llh[2], p.rms_px);
  }
  return s;
}

/// Two calibrations whose world frames are tangent at different site origins cannot be
/// triangulated together: their poses are in different ENU frames.
void check_same_world_frame(const std::vector<CalibrationResult>& cals,
                            const std::vector<std::string>& files) {
  for (std::size_t i = 0; i < cals.size(); ++i)
    for (std::size_t k = 0; k < i; ++k) {
      if (!cals[i].site_origin || !cals[k].site_origin) continue;
      const GeodeticOrigin &a = *cals[i].site_origin, &b = *cals[k].site_origin;
      if (std::abs(a.lat_deg - b.lat_deg) > 1e-9 || std::abs(a.lon_deg - b.lon_deg) > 1e-9 ||
          std::abs(a.h_m - b.h_m) > 1e-6)
        throw_input_error(files[i], 0, "world_frame",
                          "its site origin differs from that of " + files[k] +
                              ": the two cameras' poses are in different ENU frames and cannot be "
                              "triangulated together");
    }
}

void run_standalone(const std::vector<std::string>& calibrations,
                    const std::vector<std::string>& observations, bool geodetic, const CliContext& ctx) {
  if (calibrations.size() != observations.size())
    usage_error("--observations", "give one --observations per --calibration, in the same order (got " +
                                      std::to_string(calibrations.size()) + " --calibration and " +
                                      std::to_string(observations.size()) + " --observations)");
  if (calibrations.size() < 2)
    usage_error("--calibration",
                "triangulation needs at least two cameras (--calibration/--observations pairs)");
  std::vector<CalibrationResult> cals;
  for (const std::string& path : calibrations) {
    cals.push_back(read_calibration_json(path));
    if (geodetic) require_site_origin(cals.back(), path);
  }
  check_same_world_frame(cals, calibrations);
  std::vector<IntersectCamera> cameras;
  for (std::size_t i = 0; i < calibrations.size(); ++i) {
    const CalibrationResult& cal = cals[i];
    IntersectCamera c;
    // The file names the camera in warnings when two calibrations carry the same id.
    c.id = cal.camera_id.empty() ? calibrations[i] : cal.camera_id;
    for (const auto& prev : cameras)
      if (prev.id == c.id) c.id = calibrations[i];
    c.camera = cal.camera;
    c.calibration = camera_covariance(cal);
    c.picks = read_pole_picks(observations[i], {cal.camera.intr.width_px, cal.camera.intr.height_px});
    cameras.push_back(std::move(c));
  }
  const IntersectionResult r = intersect_poles(cameras, {}, kStandalonePickSigmaPx);
  if (!ctx.quiet)
    for (const std::string& w : r.warnings) std::cerr << "rangecal: warning: " << w << "\n";
  if (r.poles.empty()) {
    // Nothing at all to print is a failure, not an empty table: say why.
    bool shared = false;  // some id picked in two files (so a triangulation failed)?
    for (std::size_t i = 0; i < cameras.size() && !shared; ++i)
      for (std::size_t j = i + 1; j < cameras.size() && !shared; ++j)
        for (const PolePick& a : cameras[i].picks)
          for (const PolePick& b : cameras[j].picks) shared = shared || a.id == b.id;
    if (shared) throw_calibration_error("intersect", "no point could be triangulated (see the warnings)");
    throw_input_error(observations.front(), 0, "id",
                      "no point id is picked in two of the --observations files; nothing to triangulate");
  }
  std::cout << (geodetic ? format_geodetic_points_csv(r, *cals.front().site_origin) : format_points_csv(r))
            << std::flush;
}

}  // namespace

void add_intersect_command(CLI::App& app, const CliContext& ctx) {
  struct Args {
    std::string config;
    std::vector<std::string> calibrations, observations;
    bool geodetic = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand(
      "intersect",
      "Triangulate pole tops: `intersect CONFIG` runs the mission stage (writes intersection.csv); "
      "`intersect --calibration A.json --observations A.csv --calibration B.json --observations "
      "B.csv ...` prints id,E,N,U,rms_px (id,lat,lon,h,rms_px with --geodetic)");
  sub->add_option("CONFIG", args->config, "Mission config (JSON): run the intersect stage");
  // One value per occurrence, repeated: pairs are matched in the order given.
  sub->add_option("--calibration", args->calibrations, "calibration.json of one camera (repeat)")
      ->allow_extra_args(false);
  sub->add_option("--observations", args->observations, "id,u,v picks in that camera (repeat, same order)")
      ->allow_extra_args(false);
  sub->add_flag("--geodetic", args->geodetic,
                "with --calibration/--observations: print id,lat,lon,h,rms_px (WGS84 degrees, ellipsoidal "
                "height m) about the site origin recorded in the calibrations");
  sub->callback([&ctx, args] {
    const bool standalone = !args->calibrations.empty() || !args->observations.empty();
    if (!args->config.empty() && standalone)
      usage_error("CONFIG", "give either a mission CONFIG or --calibration/--observations pairs, not both");
    if (standalone) {
      run_standalone(args->calibrations, args->observations, args->geodetic, ctx);
      return;
    }
    if (args->geodetic)
      usage_error("--geodetic",
                  "applies to the --calibration/--observations form; the mission stage writes "
                  "intersection.csv in site ENU");
    if (args->config.empty())
      usage_error("CONFIG", "give a mission CONFIG or --calibration/--observations pairs");
    const MissionConfig cfg = load_mission_config(args->config);
    require_intersect_inputs(cfg);  // asked for this stage alone: nothing to do is an error
    const StageLog log = run_stage("intersect", cfg);
    if (!ctx.quiet) std::cout << stage_summary(log, ctx.verbose) << std::flush;
    require_complete_outcome(cfg);
  });
}

}  // namespace rangecal
