#include "pipeline/steps/intersection.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "config/error.hpp"

namespace rangecal {

namespace {

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

/// One pole's picks: a view per camera that picked it, the cameras' ids and their index in the
/// camera list.
struct PoleViews {
  std::vector<TriangulationView> views;
  std::vector<std::string> cameras;
  std::vector<std::size_t> index;  ///< into `cameras`
};

/// Every camera's picks grouped by pole id; `order` gets the ids the survey does not know, in
/// order of first appearance (a warning each when there is a survey).
std::map<std::string, PoleViews> views_by_pole(const std::vector<IntersectCamera>& cameras,
                                               const std::vector<SurveyedPole>& survey,
                                               const std::map<std::string, const SurveyedPole*>& surveyed,
                                               double pick_sigma_px, std::vector<std::string>* order,
                                               std::vector<std::string>* warnings) {
  std::map<std::string, PoleViews> seen;
  for (std::size_t ci = 0; ci < cameras.size(); ++ci) {
    const IntersectCamera& cam = cameras[ci];
    for (const PolePick& pick : cam.picks) {
      if (!seen.count(pick.id) && !surveyed.count(pick.id)) {
        order->push_back(pick.id);
        if (!survey.empty())
          warnings->push_back("pole '" + pick.id + "' (picked in " + cam.id +
                              ") is not in the pole survey: triangulated, not compared");
      }
      PoleViews& s = seen[pick.id];
      TriangulationView v;
      v.camera = cam.camera;
      v.calibration = cam.calibration;
      v.uv_px = pick.uv;
      v.pick_sigma_px = pick_sigma_px;
      s.views.push_back(std::move(v));
      s.cameras.push_back(cam.id);
      s.index.push_back(ci);
    }
  }
  return seen;
}

/// The cross-covariance blocks between one pole's views, taken from the cameras' joint ones.
CrossCovariances views_cross_covariances(const PoleViews& s, const CrossCovariances& cross,
                                         std::size_t n_cameras) {
  CrossCovariances views_cross(s.views.size(), std::vector<Eigen::MatrixXd>(s.views.size()));
  for (std::size_t a = 0; a < s.views.size(); ++a)
    for (std::size_t b = 0; b < s.views.size(); ++b)
      if (a != b && cross[s.index[a]].size() == n_cameras) {
        // A block that does not fit the two calibrations (e.g. one without a usable
        // covariance) is left out: those cameras are taken as independent.
        const Eigen::MatrixXd& m = cross[s.index[a]][s.index[b]];
        if (m.rows() == static_cast<Eigen::Index>(s.views[a].calibration.parameters.size()) &&
            m.cols() == static_cast<Eigen::Index>(s.views[b].calibration.parameters.size()))
          views_cross[a][b] = m;
      }
  return views_cross;
}

/// Pole `id` triangulated from its views (joint: with the cameras' cross covariances), or nothing
/// with a warning when it cannot be: one pole that cannot be triangulated (parallel rays, behind a
/// camera) must not stop the others (docs/intersection.md "every pole seen by ≥ 2 calibrated cameras").
std::optional<PoleIntersection> triangulate_pole(const std::string& id, const PoleViews& s,
                                                 const CrossCovariances* cross, std::size_t n_cameras,
                                                 std::vector<std::string>* warnings) {
  PoleIntersection p;
  p.id = id;
  p.cameras = s.cameras;
  try {
    CrossCovariances views_cross;
    if (cross) views_cross = views_cross_covariances(s, *cross, n_cameras);
    const TriangulationResult t = triangulate_point(s.views, "pole " + id, cross ? &views_cross : nullptr);
    p.enu = t.point;
    p.rms_px = t.rms_px;
    p.max_ray_angle_deg = t.max_ray_angle_deg;
    p.cov_m2 = t.cov_m2;
    p.sigma_m = t.sigma_m;
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::calibration) throw;
    warnings->push_back("pole '" + id + "' (cameras " + join(s.cameras) +
                        "): triangulation failed: " + e.what());
    return std::nullopt;
  }
  return p;
}

}  // namespace

IntersectionResult intersect_poles(const std::vector<IntersectCamera>& cameras,
                                   const std::vector<SurveyedPole>& survey, double pick_sigma_px,
                                   const CrossCovariances* cross) {
  if (!(pick_sigma_px > 0)) throw_input_error("", 0, "pick_sigma_px", "must be a positive number of pixels");
  IntersectionResult out;

  // Pole order: survey order, then ids the survey does not know in order of first appearance, so
  // the output does not depend on how picks files are sorted.
  std::map<std::string, const SurveyedPole*> surveyed;
  std::vector<std::string> order;
  for (const SurveyedPole& p : survey) {
    surveyed[p.id] = &p;
    order.push_back(p.id);
  }
  const bool joint = cross && cross->size() == cameras.size();
  const std::map<std::string, PoleViews> seen =
      views_by_pole(cameras, survey, surveyed, pick_sigma_px, &order, &out.warnings);

  for (const std::string& id : order) {
    const auto sv = surveyed.find(id);
    const auto it = seen.find(id);
    if (it == seen.end()) {
      // A check pole nobody picked is a hole in the accuracy table worth telling; control poles
      // are often placed for calibration only.
      if (sv != surveyed.end() && sv->second->role == PoleRole::check)
        out.warnings.push_back("check pole '" + id + "' is picked in no camera");
      continue;
    }
    const PoleViews& s = it->second;
    if (s.views.size() < 2) {
      out.warnings.push_back("pole '" + id + "' is picked only in camera " + s.cameras.front() +
                             ": two cameras are needed to triangulate it");
      continue;
    }
    std::optional<PoleIntersection> p =
        triangulate_pole(id, s, joint ? cross : nullptr, cameras.size(), &out.warnings);
    if (!p) continue;
    if (sv != surveyed.end()) {
      p->surveyed = true;
      p->role = sv->second->role;
      p->survey_enu = sv->second->enu;
      p->d_enu = p->enu - p->survey_enu;  // measured − surveyed, as Table 4's Δ
      p->dR = p->d_enu.norm();
    }
    out.poles.push_back(std::move(*p));
  }
  out.check = intersection_means(out.poles, PoleRole::check);
  out.control = intersection_means(out.poles, PoleRole::control);
  return out;
}

IntersectionMeans intersection_means(const std::vector<PoleIntersection>& poles, PoleRole role) {
  IntersectionMeans m;
  Eigen::Vector3d sum_abs = Eigen::Vector3d::Zero();
  double sum_dR = 0, sum_dR2 = 0, sum_sigma = 0, max_dR = 0;
  for (const PoleIntersection& p : poles) {
    if (!p.surveyed || p.role != role) continue;
    ++m.n;
    sum_abs += p.d_enu.cwiseAbs();
    sum_dR += p.dR;
    sum_dR2 += p.dR * p.dR;
    sum_sigma += p.sigma_m;
    max_dR = std::max(max_dR, p.dR);
  }
  if (m.n == 0) return m;
  m.mean_abs_d = sum_abs / m.n;
  m.mean_dR = sum_dR / m.n;
  m.max_dR = max_dR;
  m.rms_dR = std::sqrt(sum_dR2 / m.n);
  m.mean_sigma_m = sum_sigma / m.n;
  return m;
}

std::vector<IntersectionRow> intersection_rows(const IntersectionResult& result) {
  std::vector<IntersectionRow> rows;
  for (const PoleIntersection& p : result.poles) {
    if (!p.surveyed || p.role != PoleRole::check) continue;  // control poles: see the header comment
    IntersectionRow r;
    r.id = p.id;
    r.enu = p.enu;
    r.survey_enu = p.survey_enu;
    r.d_enu = p.d_enu;
    r.dR = p.dR;
    r.sigma_m = p.sigma_m;
    rows.push_back(r);
  }
  return rows;
}

IntersectionMeans intersection_means(const std::vector<IntersectionRow>& rows) {
  std::vector<PoleIntersection> poles;
  for (const IntersectionRow& r : rows) {
    PoleIntersection p;
    p.id = r.id;
    p.surveyed = true;
    p.role = PoleRole::check;
    p.enu = r.enu;
    p.survey_enu = r.survey_enu;
    p.d_enu = r.d_enu;
    p.dR = r.dR;
    p.sigma_m = r.sigma_m;
    poles.push_back(p);
  }
  return intersection_means(poles, PoleRole::check);
}

}  // namespace rangecal
