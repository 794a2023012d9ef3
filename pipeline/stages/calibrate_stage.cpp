#include "pipeline/stages/calibrate_stage.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>

#include "config/atomic_file.hpp"
#include "config/error.hpp"
#include "gnss/formats/pole_survey_csv.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "vision/camera/opencv_camera_export.hpp"

namespace rangecal {

CalibrationProblem make_calibration_problem(const MissionConfig& cfg, const CameraConfig& cam,
                                            const std::vector<Correspondence>& pairs) {
  CalibrationProblem p;
  p.camera_id = cam.id;
  p.sensor.width_px = cam.sensor.width_px;
  p.sensor.height_px = cam.sensor.height_px;
  p.sensor.dx_mm = cam.sensor.pixel_size_um[0] * 1e-3;
  p.sensor.dy_mm = cam.sensor.pixel_size_um[1] * 1e-3;
  p.nominal_focal_mm = cam.nominal_focal_mm;
  p.priors = cam.priors;
  p.free = cfg.calibrate.free;
  p.pixel_sigma_px = kDefaultPixelSigmaPx;
  p.seed = cfg.calibrate.seed;
  for (const Correspondence& c : pairs) {
    BundleObservation o;
    o.world = c.enu;
    o.pixel = c.uv;
    const Eigen::Vector3d sd = c.sd_enu ? *c.sd_enu : Eigen::Vector3d::Constant(kDefaultWorldSigmaM);
    o.world_cov = sd.cwiseProduct(sd).asDiagonal();
    if (c.vel_enu) o.velocity = *c.vel_enu;
    p.observations.push_back(o);
  }
  if (cfg.calibrate.use_control_poles && !cfg.poles_file.empty() && !cam.pole_observations.empty()) {
    const auto poles = read_pole_survey(cfg.poles_file, cfg.origin);
    std::map<std::string, const SurveyedPole*> by_id;
    for (const auto& pole : poles) by_id[pole.id] = &pole;
    for (const PolePick& pick : read_pole_picks(cam.pole_observations)) {
      const auto it = by_id.find(pick.id);
      if (it == by_id.end())
        throw_input_error(cam.pole_observations, pick.line, "id",
                          "pole '" + pick.id + "' is not in the survey " + cfg.poles_file);
      if (it->second->role != PoleRole::control) continue;  // check poles never calibrate
      BundleObservation o;
      o.world = it->second->enu;
      o.pixel = pick.uv;
      o.world_cov = Eigen::Matrix3d::Identity() * kControlPoleSigmaM * kControlPoleSigmaM;
      o.pixel_sigma_px = kPolePickSigmaPx;
      p.observations.push_back(o);
      p.control_pole_ids.push_back(pick.id);
    }
  }
  return p;
}

std::string format_methods_csv(const std::vector<CalibrationResult>& results) {
  std::string s =
      "method,u0_px,v0_px,f_mm,sx,k1_per_mm2,r11,r12,r13,r21,r22,r23,r31,r32,r33,Tx_m,Ty_m,Tz_m,"
      "sigma_f_mm,rms_px,n_used,n_rejected\n";
  char buf[128];
  for (const auto& r : results) {
    const Camera& c = r.camera;
    s += r.method;
    auto add = [&](const char* fmt, double v) {
      std::snprintf(buf, sizeof buf, fmt, v);
      s += ",";
      s += buf;
    };
    add("%.4f", c.intr.u0_px);
    add("%.4f", c.intr.v0_px);
    add("%.5f", c.intr.f_mm);
    add("%.6f", c.intr.sx);
    add("%.6e", c.intr.dist.k1);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) add("%.6f", c.pose.R(i, j));
    for (int i = 0; i < 3; ++i) add("%.4f", c.pose.T[i]);
    const double sf = r.sigma("f");
    if (std::isfinite(sf))
      add("%.5f", sf);
    else
      s += ",";
    add("%.4f", r.reprojection.rms_px);
    s += "," + std::to_string(r.reprojection.n_used) + "," + std::to_string(r.reprojection.n_rejected) + "\n";
  }
  return s;
}

StageLog run_calibrate_stage(const MissionConfig& cfg) {
  const auto t0 = std::chrono::steady_clock::now();
  StageLog log;
  log.stage = "calibrate";
  int calibrated = 0;
  std::string last_failure;
  for (const CameraConfig& cam : cfg.cameras) {
    const std::string corr_path = camera_output(cfg, cam.id, kCorrespondencesCsv);
    if (!std::filesystem::exists(corr_path))
      throw_input_error(corr_path, 0, "",
                        "missing; run the detect stage first (rangecal detect CONFIG), or "
                        "write the point pairs there yourself (SPEC §5 format)");
    std::vector<Correspondence> pairs = read_correspondences_csv(corr_path);
    const CalibrationProblem problem = make_calibration_problem(cfg, cam, pairs);
    nlohmann::json counts;
    counts["pairs"] = pairs.size();
    counts["control_poles"] = problem.observations.size() - pairs.size();
    CalibrationResult main;
    try {
      main = calibrate_camera(cfg.calibrate.method, problem);
    } catch (const Error& e) {
      // One camera that cannot be calibrated must not stop the others (issue 5): warn and go on.
      if (e.kind() != ErrorKind::calibration) throw;
      log.warnings.push_back(cam.id + ": calibration failed: " + e.what());
      last_failure = cam.id + ": " + e.what();
      counts["failed"] = e.what();
      log.counts[cam.id] = counts;
      continue;
    }
    ++calibrated;
    if (pairs.empty())
      log.warnings.push_back(cam.id + ": no lamp pairs; calibrated from its " +
                             std::to_string(problem.observations.size()) +
                             " control poles alone (seed 002's baseline setting, far fewer points)");
    write_calibration_json(camera_output(cfg, cam.id, kCalibrationJson), main);
    const OpenCvCamera ocv = fit_opencv_camera(main.camera);
    write_opencv_camera_yml(camera_output(cfg, cam.id, kCameraOpencvYml), ocv);
    if (ocv.fit_max_px > 0.01)
      log.warnings.push_back(cam.id + ": OpenCV model reproduces rangecal only to " +
                             std::to_string(ocv.fit_max_px) + " px");

    // Residual and use of every lamp pair (control poles follow them in the problem).
    const auto res = reprojection_residuals(main.camera, problem.observations, main.clock_offset_s);
    std::vector<bool> rejected(problem.observations.size(), false);
    for (std::size_t i : main.rejected)
      if (i < rejected.size()) rejected[i] = true;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      pairs[i].residual_px = res[i].norm();
      pairs[i].used = !rejected[i];
    }
    write_correspondences_csv(corr_path, pairs);

    std::vector<CalibrationResult> all{main};
    nlohmann::json times;
    times[main.method] = std::round(main.wall_time_s * 1e4) / 1e4;
    for (const std::string& m : cfg.calibrate.compare) {
      if (m == cfg.calibrate.method) continue;
      try {
        all.push_back(calibrate_camera(m, problem));
        times[m] = std::round(all.back().wall_time_s * 1e4) / 1e4;
        // Each compared method's full result, so any method's cameras can be used downstream
        // (e.g. the demo's intersection with Tsai beside the bundle, seed 002 Table 4).
        write_calibration_json(camera_output(cfg, cam.id, compare_calibration_json(m)), all.back());
      } catch (const Error& e) {
        if (e.kind() != ErrorKind::calibration) throw;
        log.warnings.push_back(cam.id + ": compare method " + m + " failed: " + e.what());
      }
    }
    if (!cfg.calibrate.compare.empty())
      write_file_atomic(camera_output(cfg, cam.id, kMethodsCsv), format_methods_csv(all));
    counts["method"] = main.method;
    counts["rms_px"] = main.reprojection.rms_px;
    counts["n_used"] = main.reprojection.n_used;
    counts["n_rejected"] = main.reprojection.n_rejected;
    counts["opencv_fit_max_px"] = ocv.fit_max_px;
    counts["method_time_s"] = times;
    log.counts[cam.id] = counts;
    for (const auto& w : main.warnings) log.warnings.push_back(cam.id + ": " + w);
  }
  if (calibrated == 0)
    throw_calibration_error("calibrate", cfg.cameras.empty() ? "no cameras in the config"
                                                             : "no camera could be "
                                                               "calibrated (" +
                                                                   last_failure + ")");
  log.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return log;
}

}  // namespace rangecal
