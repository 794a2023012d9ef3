#include "support/report_output.hpp"

#include <cmath>
#include <cstdio>

#include "gnss/formats/lamp_track_csv.hpp"
#include "gnss/time/utc_time.hpp"
#include "pipeline/io/calibrate_record.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/io/methods_csv.hpp"
#include "pipeline/io/network_json.hpp"
#include "pipeline/io/residuals_csv.hpp"
#include "pipeline/io/run_log.hpp"
#include "support/paths.hpp"
#include "support/synthetic_camera.hpp"

namespace rangecal::test {

namespace fs = std::filesystem;

std::string fixed(const char* f, double x) {
  char b[64];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

double pole_dr(const Pole& p) {
  return std::sqrt(p.dE * p.dE + p.dN * p.dN + p.dU * p.dU);
}

std::string adjusted_utc(const AdjustedEpoch& e) {
  return format_iso8601_utc(UtcTime{kAdjustedStartNs + static_cast<std::int64_t>(std::llround(e.t_s * 1e9))});
}

nlohmann::json network_counts() {
  nlohmann::json outliers = nlohmann::json::array();
  for (const AdjustedEpoch& e : kAdjusted)
    if (e.flag) outliers.push_back(adjusted_utc(e));
  return {{"variance_factor", 1.0712},
          {"chi2", 1284.4},
          {"dof", 1199},
          {"epochs_seen_by_1", 3},
          {"epochs_seen_by_2", 70},
          {"epochs_seen_by_3_or_more", 1},
          {"float_epochs_used", 2},
          {"ppk_outliers", outliers},
          {"image_outliers", 4},
          {"cameras_alone", nlohmann::json::array()},
          {"rank_deficient", false},
          {"ppk_error_model", ppk_error_model_json(PpkErrorModel{}, 0)}};
}

ReportOutput write_report_output(const fs::path& dir, bool with_intersection, bool with_network) {
  ReportOutput fx;
  fx.cfg.mission = "Range 3 <night> & \"dawn\" flights";
  fx.cfg.output_dir = (dir / "out").string();
  fx.cfg.config_path = (dir / "mission.json").string();
  for (const char* id : {"cam1", "cam2"}) {
    CameraConfig c;
    c.id = id;
    c.sensor.width_px = 1280;
    c.sensor.height_px = 800;
    c.sensor.pixel_size_um[0] = c.sensor.pixel_size_um[1] = 20;
    c.nominal_focal_mm = 135;
    fx.cfg.cameras.push_back(c);
  }
  const std::string out = fx.cfg.output_dir;

  LampTrack track;
  for (int i = 0; i < 5; ++i) {
    LampEpoch e;
    e.utc = UtcTime{1'700'000'000'000'000'000 + i * 200'000'000LL};
    e.enu = Eigen::Vector3d(0.5, 64.0, 2.0 + i);
    e.sd_enu = Eigen::Vector3d(0.01, 0.01, 0.02);
    e.quality = 1;
    track.epochs.push_back(e);
  }
  write_lamp_track_csv(out + "/gnss/lamp_track.csv", track);

  // cam1: the seed 002 range camera; pixels with 0.2 px noise, two pairs marked as rejected.
  const Camera truth = range_camera(-3.4e-4, 1.0, 0.6, -0.3);
  const auto obs = observe(truth, range_world_points(truth), 0.2, 0.0, 7);
  // Frames 10 ms apart along an ascent (or the pole tops); 60 s between them, as when the UAV flies
  // down out of view and climbs the next route, so Fig. 6 draws one polyline per segment.
  std::vector<Correspondence> pairs;
  std::int64_t t = 1'700'000'000'000'000'000;
  fx.cam1_segments = obs.empty() ? 0 : 1;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const bool new_segment = i > 0 && std::abs(obs[i].world.x() - obs[i - 1].world.x()) > 0.5;
    fx.cam1_segments += new_segment;
    t += i == 0 ? 0 : new_segment ? 60'000'000'000LL : 10'000'000LL;
    Correspondence c;
    c.utc = UtcTime{t};
    c.enu = obs[i].world;
    c.uv = obs[i].pixel;
    c.used = !(i == 3 || i == 17);
    Eigen::Vector2d p;
    project(truth, c.enu, &p);
    c.residual_px = (c.uv - p).norm();
    pairs.push_back(c);
  }
  fx.cam1_pairs = pairs.size();
  fx.cam1_rejected = 2;
  write_correspondences_csv(out + "/cam1/correspondences.csv", pairs);
  // The calibrate stage's residuals.csv says which pairs the calibration used.
  std::vector<ResidualRow> residuals;
  for (const Correspondence& c : pairs) {
    ResidualRow row;
    row.utc = c.utc;
    row.enu = c.enu;
    row.uv = c.uv;
    row.used = *c.used;
    residuals.push_back(row);
  }
  write_residuals_csv(out + "/cam1/residuals.csv", residuals);
  write_correspondences_csv(out + "/cam2/correspondences.csv", pairs);

  CalibrationResult& r = fx.cal;
  r.camera_id = "cam1";
  r.method = "bundle";
  r.camera = truth;
  r.camera.id = "cam1";
  r.parameters = parameters({"f", "k1"});
  r.covariance = Eigen::Matrix2d(Eigen::Vector2d(0.0123 * 0.0123, 2.5e-6 * 2.5e-6).asDiagonal());
  r.reprojection.rms_px = 0.2137;
  r.reprojection.mean_px = 0.1876;
  r.reprojection.max_px = 0.6543;
  r.reprojection.n_used = static_cast<int>(pairs.size() - 2);
  r.reprojection.n_rejected = 2;
  r.warnings = {"f and Tz correlated <0.995>"};
  write_calibration_json(out + "/cam1/calibration.json", r);
  CalibrationResult tsai = r;
  tsai.method = "tsai";
  tsai.camera.intr.f_mm = 132.43;
  tsai.covariance.resize(0, 0);
  tsai.parameters.clear();
  tsai.reprojection.rms_px = 0.99;
  write_text(out + "/cam1/methods.csv", format_methods_csv({method_row(r), method_row(tsai)}));

  if (with_intersection) {
    std::string csv = "id,E,N,U,E_survey,N_survey,U_survey,dE,dN,dU,dR,sigma_m\n";
    for (const Pole& p : kPoles)
      csv += std::string(p.id) + ",1.0000,62.0000,4.0000,1.0000,62.0000,4.0000," + fixed("%.4f", p.dE) + "," +
             fixed("%.4f", p.dN) + "," + fixed("%.4f", p.dU) + "," + fixed("%.6f", pole_dr(p)) + "," +
             fixed("%.4f", p.sigma) + "\n";
    write_text(out + "/intersection.csv", csv);
  }

  StageLog cal_log;
  cal_log.stage = "calibrate";
  CalibrateRecord cal_record;
  cal_record.cameras["cam2"].failed = "points on one line <degenerate>";
  if (with_network) {
    std::string csv = "utc,E,N,U,sdE,sdN,sdU,dE,dN,dU,flag\n";
    for (const AdjustedEpoch& e : kAdjusted)
      csv += adjusted_utc(e) + ",0.5000,64.0000," + fixed("%.4f", 2.0 + e.t_s) + "," + fixed("%.4f", e.sdE) +
             "," + fixed("%.4f", e.sdN) + "," + fixed("%.4f", e.sdU) + "," + fixed("%.4f", e.dE) + "," +
             fixed("%.4f", e.dN) + "," + fixed("%.4f", e.dU) + "," + std::to_string(e.flag) + "\n";
    write_text(out + "/gnss/lamp_track_adjusted.csv", csv);
    cal_record.network = network_counts();
    cal_record.method_choice =
        MethodChoiceRecord{"network", 71, "default: 71 epochs seen by two or more cameras"};
  }
  cal_log.counts = calibrate_record_json(cal_record);
  cal_log.warnings = {"cam2: calibration failed: points on one line <degenerate>"};
  update_run_log(fx.cfg, cal_log);
  return fx;
}

nlohmann::json read_json(const fs::path& p) {
  return nlohmann::json::parse(read_text(p));
}

}  // namespace rangecal::test
