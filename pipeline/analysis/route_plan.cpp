#include "pipeline/analysis/route_plan.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "pipeline/analysis/monte_carlo.hpp"
#include "pipeline/report/html_escape.hpp"
#include "pipeline/simulate/mission_simulator.hpp"
#include "vision/triangulation/triangulation.hpp"

namespace rangecal {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Frames of one camera with their epochs: what the align stage keeps (docs/alignment.md: for every
/// lamp-track epoch the nearest frame, kept within max_frame_offset_s), lamp in view.
std::vector<BundleObservation> observations_of(const SimMission& m, const SimCamera& cam,
                                               const PlanOptions& o) {
  std::vector<BundleObservation> out;
  std::set<std::size_t> used;
  const auto& frames = cam.frames;
  const std::int64_t max_ns = static_cast<std::int64_t>(std::llround(o.max_frame_offset_s * 1e9));
  for (const SimEpoch& e : m.epochs) {
    if (e.quality != 1) continue;  // the simulated mission config accepts fix epochs only
    const std::size_t best = nearest_in_time(frames, e.utc, [](const SimFrame& f) { return f.stamp_utc; });
    if (best == frames.size() || std::llabs(frames[best].stamp_utc.ns - e.utc.ns) > max_ns ||
        !frames[best].in_view || used.count(best))
      continue;
    used.insert(best);
    BundleObservation ob;
    ob.world = frames[best].lamp_enu;
    ob.pixel = frames[best].lamp_px;
    ob.world_cov = e.sd_enu.cwiseProduct(e.sd_enu).asDiagonal();
    ob.pixel_sigma_px = o.pixel_sigma_px;
    ob.velocity = frames[best].lamp_velocity_enu;
    out.push_back(ob);
  }
  return out;
}

/// The control poles the mission would calibrate with (mission_calibrate.use_control_poles): each
/// pole top inside the image, surveyed with the scenario's survey σ and picked with its pick σ.
std::vector<BundleObservation> control_pole_observations(const Scenario& s, const Camera& cam) {
  std::vector<BundleObservation> out;
  const auto use = s.mission_calibrate.find("use_control_poles");
  if (use == s.mission_calibrate.end() || !use->is_boolean() || !use->get<bool>()) return out;
  for (const ScenarioPole& pole : s.poles) {
    if (pole.role != "control") continue;
    BundleObservation ob;
    if (!project(cam, pole.enu_m, &ob.pixel) || !inside_image(cam.intr, ob.pixel)) continue;
    ob.world = pole.enu_m;
    ob.world_cov = Eigen::Matrix3d::Identity() * s.survey_noise_m * s.survey_noise_m;
    ob.pixel_sigma_px = s.pick_noise_px;
    out.push_back(ob);
  }
  return out;
}

/// Lamp points, then control poles when the mission uses them.
std::vector<BundleObservation> all_observations(const SimMission& m, const SimCamera& cam,
                                                const PlanOptions& o, std::size_t* n_lamp) {
  std::vector<BundleObservation> obs = observations_of(m, cam, o);
  *n_lamp = obs.size();
  for (const BundleObservation& p : control_pole_observations(m.scenario, cam.spec.camera)) obs.push_back(p);
  return obs;
}

}  // namespace

std::vector<std::vector<std::string>> default_plan_free_sets() {
  std::vector<std::string> with_pp = default_free_parameters();
  with_pp.push_back(parameter_name(CameraParameter::u0));
  with_pp.push_back(parameter_name(CameraParameter::v0));
  return {default_free_parameters(), with_pp};
}

std::vector<BundleObservation> planned_observations(const Scenario& s, std::size_t camera_index,
                                                    const PlanOptions& options) {
  const SimMission m = simulate_mission(s);
  if (camera_index >= m.cameras.size())
    throw_config_error(s.file, "cameras", "no camera " + std::to_string(camera_index));
  std::size_t n_lamp = 0;
  return all_observations(m, m.cameras[camera_index], options, &n_lamp);
}

CameraBound cramer_rao_bound(const Camera& truth, const std::vector<BundleObservation>& obs,
                             const std::vector<std::string>& free, const PlanOptions& o) {
  CameraBound b;
  b.camera_id = truth.id;
  b.n_points = static_cast<int>(obs.size());
  b.free_parameters = expand_free_parameters(free);
  const int n = static_cast<int>(b.free_parameters.size());
  const auto it =
      std::find(b.free_parameters.begin(), b.free_parameters.end(), CameraParameter::clock_offset);
  const int clock = it == b.free_parameters.end() ? -1 : static_cast<int>(it - b.free_parameters.begin());
  Eigen::MatrixXd F = Eigen::MatrixXd::Zero(n, n);
  double max_speed = 0;  // m/s, for the clock offset's rule
  for (const BundleObservation& ob : obs) {
    max_speed = std::max(max_speed, ob.velocity.norm());
    Eigen::Matrix<double, 2, 3> Jx;
    Eigen::MatrixXd J = pixel_jacobian_wrt_parameters(truth, b.free_parameters, ob.world, &Jx);
    // The clock offset δ moves the seen point by −v·δ (optim/bundle/bundle_adjustment.hpp).
    if (clock >= 0) J.col(clock) = -Jx * ob.velocity;
    const double sp = ob.pixel_sigma_px > 0 ? ob.pixel_sigma_px : o.pixel_sigma_px;
    // Effective pixel covariance: centroid noise + PPK noise seen through the camera (as the bundle).
    const Eigen::Matrix2d C = sp * sp * Eigen::Matrix2d::Identity() + Jx * ob.world_cov * Jx.transpose();
    F += J.transpose() * C.inverse() * J;
  }
  // Column scaling makes the rank test independent of the parameters' units.
  const Eigen::VectorXd d = F.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd Fs = d.asDiagonal() * F * d.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Fs);
  const Eigen::VectorXd ev = es.eigenvalues();
  b.singular = n == 0 || !(ev.minCoeff() > o.rank_tolerance * ev.maxCoeff());
  if (!b.singular) {
    const Eigen::MatrixXd Fs_inv =
        es.eigenvectors() * ev.cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
    b.covariance = d.asDiagonal() * Fs_inv * d.asDiagonal();
  }
  for (int i = 0; i < n; ++i) {
    ParameterBound p;
    p.parameter = b.free_parameters[i];
    p.value = parameter_value(truth, p.parameter, truth);
    if (b.singular) {
      p.sigma = kInf;
      p.max_abs_correlation = kNaN;
      p.poorly_determined = true;
    } else {
      p.sigma = std::sqrt(b.covariance(i, i));
      for (int j = 0; j < n; ++j) {
        if (j == i) continue;
        const double r = std::abs(b.covariance(i, j) / std::sqrt(b.covariance(i, i) * b.covariance(j, j)));
        if (r > p.max_abs_correlation)
          p.max_abs_correlation = r, p.correlated_with = parameter_name(b.free_parameters[j]);
      }
      p.sigma_inflation = std::sqrt(F(i, i) * b.covariance(i, i));
      const bool principal_point = p.parameter == CameraParameter::u0 || p.parameter == CameraParameter::v0;
      p.poorly_determined =
          p.max_abs_correlation > o.correlation_limit ||
          (principal_point && p.sigma > o.principal_point_limit_px) ||
          (p.parameter == CameraParameter::clock_offset && p.sigma * max_speed > o.clock_offset_limit_m);
    }
    b.parameters.push_back(p);
  }
  return b;
}

RoutePlanAnalysis analyse_route_plan(const Scenario& s, const std::string& name, const PlanOptions& o) {
  const SimMission m = simulate_mission(s);
  std::vector<std::vector<BundleObservation>> obs;
  for (const SimCamera& c : m.cameras) {
    std::size_t n_lamp = 0;
    obs.push_back(all_observations(m, c, o, &n_lamp));
    if (n_lamp < 6)
      throw_calibration_error(s.file + " camera " + c.spec.id,
                              "the routes give only " + std::to_string(n_lamp) +
                                  " lamp points in view; the camera cannot be calibrated from them");
  }
  RoutePlanAnalysis a;
  a.name = name;
  for (const std::vector<std::string>& free : o.free_sets) {
    FreeSetPlan fp;
    fp.free = free;
    for (std::size_t c = 0; c < m.cameras.size(); ++c) {
      Camera truth = m.cameras[c].spec.camera;
      truth.id = m.cameras[c].spec.id;
      fp.cameras.push_back(cramer_rao_bound(truth, obs[c], free, o));
    }
    for (const ScenarioPole& pole : s.poles) {
      PoleBound pb;
      pb.id = pole.id;
      pb.role = pole.role;
      std::vector<TriangulationView> views;
      bool all_bounded = true;
      for (std::size_t c = 0; c < m.cameras.size(); ++c) {
        TriangulationView v;
        v.camera = m.cameras[c].spec.camera;
        v.camera.id = m.cameras[c].spec.id;
        if (!project(v.camera, pole.enu_m, &v.uv_px) || !inside_image(v.camera.intr, v.uv_px)) continue;
        all_bounded = all_bounded && !fp.cameras[c].singular;
        v.calibration.parameters = fp.cameras[c].free_parameters;
        v.calibration.covariance = fp.cameras[c].covariance;
        v.pick_sigma_px = s.pick_noise_px;
        views.push_back(v);
      }
      pb.n_cameras = static_cast<int>(views.size());
      if (views.size() >= 2 && all_bounded) {
        try {
          pb.sigma_m = triangulate_point(views, "pole " + pole.id).sigma_m;
        } catch (const Error&) {
          // Parallel rays or a pole behind a camera: no prediction, shown as "-".
        }
      }
      fp.poles.push_back(pb);
    }
    a.free_sets.push_back(fp);
  }
  return a;
}

namespace {

/// One table of the plan output: title, column names, rows of cells, notes below it.
struct PlanTable {
  std::string title;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> notes;
};

std::string unit_of(CameraParameter p) {
  const std::string unit = parameter_unit(p);
  return unit.empty() ? "" : " " + unit;
}

const CameraBound* camera_bound(const RoutePlanAnalysis& a, std::size_t k, std::size_t c) {
  return k < a.free_sets.size() && c < a.free_sets[k].cameras.size() ? &a.free_sets[k].cameras[c] : nullptr;
}

/// The tables of format_plan_table / format_plan_html: per free set, one per camera, then the poles.
std::vector<PlanTable> plan_tables(const std::vector<RoutePlanAnalysis>& cands) {
  std::vector<PlanTable> out;
  if (cands.empty()) return out;
  auto cell = [](double sigma, bool flagged) {
    if (std::isnan(sigma)) return std::string("-");
    if (std::isinf(sigma)) return std::string("undetermined");
    return format_number("%.4g", sigma) + (flagged ? " !" : "");
  };
  for (std::size_t k = 0; k < cands.front().free_sets.size(); ++k) {
    const FreeSetPlan& base = cands.front().free_sets[k];
    std::string free;
    for (const auto& f : base.free) free += (free.empty() ? "" : ",") + f;
    for (std::size_t c = 0; c < base.cameras.size(); ++c) {
      PlanTable t;
      t.title = "Cramér–Rao 1σ, camera " + base.cameras[c].camera_id + ", free " + free +
                " (! = poorly determined: |ρ| > 0.99, principal point σ > 1 px, clock offset σ moving the "
                "lamp > 2 cm, or singular)";
      t.header.push_back("parameter");
      std::vector<std::string> points{"points"};
      for (const auto& cand : cands) {
        t.header.push_back(cand.name);
        const CameraBound* b = camera_bound(cand, k, c);
        points.push_back(b ? std::to_string(b->n_points) : "-");
      }
      t.rows.push_back(points);
      for (const ParameterBound& bp : base.cameras[c].parameters) {
        std::vector<std::string> row{parameter_name(bp.parameter) + unit_of(bp.parameter)};
        for (const auto& cand : cands) {
          std::string v = "-";
          if (const CameraBound* b = camera_bound(cand, k, c))
            for (const ParameterBound& p : b->parameters)
              if (p.parameter == bp.parameter) v = cell(p.sigma, p.poorly_determined);
          row.push_back(v);
        }
        t.rows.push_back(row);
      }
      for (const auto& cand : cands) {
        const CameraBound* b = camera_bound(cand, k, c);
        if (!b) continue;
        for (const ParameterBound& p : b->parameters) {
          const std::string name = parameter_name(p.parameter);
          const bool pp = p.parameter == CameraParameter::u0 || p.parameter == CameraParameter::v0;
          if (std::isinf(p.sigma))
            t.notes.push_back(cand.name + ": " + name + " undetermined (singular information matrix)");
          else if (p.poorly_determined)
            t.notes.push_back(cand.name + ": " + name + " poorly determined (" +
                              (pp ? "σ " + format_number("%.2f", p.sigma) + " px; " : "") +
                              (p.parameter == CameraParameter::clock_offset
                                   ? "σ " + format_number("%.2f", p.sigma * 1e3) + " ms; "
                                   : "") +
                              "|ρ| " + format_number("%.4f", p.max_abs_correlation) + " with " +
                              p.correlated_with + "; σ inflated " + format_number("%.1f", p.sigma_inflation) +
                              "× by the other free parameters)");
        }
      }
      out.push_back(t);
    }
    PlanTable t;
    t.title = "Predicted intersection 1σ at the poles (m; pick σ of the scenario), free " + free;
    t.header.push_back("pole");
    for (const auto& cand : cands) t.header.push_back(cand.name);
    for (const PoleBound& pb : base.poles) {
      std::vector<std::string> row{pb.id + " " + pb.role};
      for (const auto& cand : cands) {
        std::string v = "-";
        if (k < cand.free_sets.size())
          for (const PoleBound& q : cand.free_sets[k].poles)
            if (q.id == pb.id && std::isfinite(q.sigma_m)) v = format_number("%.4f", q.sigma_m);
        row.push_back(v);
      }
      t.rows.push_back(row);
    }
    out.push_back(t);
  }
  return out;
}

}  // namespace

std::string format_plan_table(const std::vector<RoutePlanAnalysis>& cands) {
  std::string s;
  char line[256];
  // Columns as wide as the longest candidate name (at least 16), so names are never cut.
  int width = 16;
  for (const RoutePlanAnalysis& c : cands) width = std::max(width, static_cast<int>(c.name.size()));
  for (const PlanTable& t : plan_tables(cands)) {
    s += t.title + "\n";
    auto add_row = [&](const std::vector<std::string>& row) {
      std::snprintf(line, sizeof line, "  %-14s", row[0].c_str());
      s += line;
      for (std::size_t i = 1; i < row.size(); ++i) {
        std::snprintf(line, sizeof line, " %*s", width, row[i].substr(0, 64).c_str());
        s += line;
      }
      s += "\n";
    };
    add_row(t.header);
    for (const auto& row : t.rows) add_row(row);
    for (const std::string& n : t.notes) s += "  " + n + "\n";
    s += "\n";
  }
  return s;
}

std::string format_plan_html(const std::vector<RoutePlanAnalysis>& cands) {
  std::string s =
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>rangecal plan</title>\n"
      "<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse;margin:0.5em 0 1.5em}"
      "td,th{border:1px solid #bbb;padding:0.2em 0.6em;text-align:right}td:first-child,th:first-child"
      "{text-align:left}th{background:#eee}.flag{background:#fde2e2}p.note{margin:0.1em 0;color:#a00}"
      "</style></head><body>\n<h1>rangecal plan: predicted calibration accuracy</h1>\n";
  for (const PlanTable& t : plan_tables(cands)) {
    s += "<h2>" + html_escape(t.title) + "</h2>\n<table>\n<tr>";
    for (const std::string& h : t.header) s += "<th>" + html_escape(h) + "</th>";
    s += "</tr>\n";
    for (const auto& row : t.rows) {
      s += "<tr>";
      for (const std::string& c : row) {
        const bool flagged = c.size() > 2 && c.compare(c.size() - 2, 2, " !") == 0;
        s += std::string(flagged ? "<td class=\"flag\">" : "<td>") + html_escape(c) + "</td>";
      }
      s += "</tr>\n";
    }
    s += "</table>\n";
    for (const std::string& n : t.notes) s += "<p class=\"note\">" + html_escape(n) + "</p>\n";
  }
  return s + "</body></html>\n";
}

}  // namespace rangecal
