#include "pipeline/analysis/plan_tables.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "config/number_format.hpp"
#include "pipeline/report/html_escape.hpp"

namespace rangecal {
namespace {

/// One table of the plan output: title, optional column groups (a label over `span` columns after
/// the first), column names, rows of cells, notes below it.
struct PlanTable {
  std::string title;
  std::vector<std::pair<std::string, int>> groups;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> notes;
};

std::string unit_of(CameraParameter p) {
  const std::string unit = parameter_unit(p);
  return unit.empty() ? "" : " " + unit;
}

const FreeSetPlan* free_set(const RoutePlanAnalysis& a, std::size_t k) {
  return k < a.free_sets.size() ? &a.free_sets[k] : nullptr;
}

const CameraBound* camera_bound(const std::vector<CameraBound>& cameras, std::size_t c) {
  return c < cameras.size() ? &cameras[c] : nullptr;
}

const ParameterBound* parameter_bound(const CameraBound* b, CameraParameter parameter) {
  if (b)
    for (const ParameterBound& p : b->parameters)
      if (p.parameter == parameter) return &p;
  return nullptr;
}

std::string sigma_cell(const ParameterBound* p) {
  if (!p || std::isnan(p->sigma)) return "-";
  if (std::isinf(p->sigma)) return "undetermined";
  return format_number("%.4g", p->sigma) + (p->poorly_determined ? " !" : "");
}

/// Why a flagged parameter is poorly determined (`who`: the candidate, and the method if not the
/// per-camera calibration).
std::string flag_note(const std::string& who, const ParameterBound& p) {
  const std::string name = parameter_name(p.parameter);
  if (std::isinf(p.sigma)) return who + ": " + name + " undetermined (singular information matrix)";
  const bool pp = p.parameter == CameraParameter::u0 || p.parameter == CameraParameter::v0;
  std::string s =
      who + ": " + name + " poorly determined (" +
      (pp ? "σ " + format_number("%.2f", p.sigma) + " px; " : "") +
      (p.parameter == CameraParameter::clock_offset ? "σ " + format_number("%.2f", p.sigma * 1e3) + " ms; "
                                                    : "") +
      "|ρ| " + format_number("%.4f", p.max_abs_correlation) + " with " + p.correlated_with;
  if (std::isfinite(p.sigma_inflation))
    s += "; σ inflated " + format_number("%.1f", p.sigma_inflation) + "× by the other free parameters";
  return s + ")";
}

/// Why a candidate has no network column of its own.
std::string network_note(const RoutePlanAnalysis& cand, const FreeSetPlan& fs) {
  if (fs.cameras.size() < 2) return cand.name + ": one camera — the network is the per-camera calibration";
  return cand.name +
         ": no lamp epoch seen by ≥ 2 cameras — `rangecal run` calibrates each camera alone; the network "
         "is the per-camera calibration";
}

std::string mm_cell(double m) {
  return std::isfinite(m) ? format_number("%.2f", m * 1e3) : "-";
}

std::string ratio_cell(double a, double b) {
  return std::isfinite(a) && std::isfinite(b) && b > 0 ? format_number("%.3f", a / b) : "-";
}

/// One camera's table for free set k: per candidate the per-camera σ, and — when `with_network` —
/// the network's σ and the ratio network / per-camera beside it.
PlanTable camera_table(const std::vector<RoutePlanAnalysis>& cands, std::size_t k, std::size_t c,
                       const std::string& free, bool with_network) {
  const CameraBound& base = cands.front().free_sets[k].cameras[c];
  PlanTable t;
  t.title = "Cramér–Rao 1σ, camera " + base.camera_id + ", free " + free +
            (with_network ? ": per-camera calibration and network, ratio = network / per-camera" : "") +
            " (! = poorly determined: |ρ| > 0.99, principal point σ > 1 px, clock offset σ moving the "
            "lamp > 2 cm, or singular)";
  t.header.push_back("parameter");
  std::vector<std::string> points{"points"};
  for (const RoutePlanAnalysis& cand : cands) {
    const FreeSetPlan* fs = free_set(cand, k);
    const CameraBound* b = fs ? camera_bound(fs->cameras, c) : nullptr;
    const std::string n = b ? std::to_string(b->n_points) : "-";
    if (!with_network) {
      t.header.push_back(cand.name);
      points.push_back(n);
      continue;
    }
    t.groups.emplace_back(cand.name, 3);
    for (const char* h : {"per-camera", "network", "ratio"}) t.header.push_back(h);
    const bool applies = fs && fs->network.applies();
    points.insert(points.end(), {n, applies ? n : "", ""});
  }
  t.rows.push_back(points);
  for (const ParameterBound& bp : base.parameters) {
    std::vector<std::string> row{parameter_name(bp.parameter) + unit_of(bp.parameter)};
    for (const RoutePlanAnalysis& cand : cands) {
      const FreeSetPlan* fs = free_set(cand, k);
      const ParameterBound* p = parameter_bound(fs ? camera_bound(fs->cameras, c) : nullptr, bp.parameter);
      row.push_back(sigma_cell(p));
      if (!with_network) continue;
      if (!fs || !fs->network.applies()) {
        row.insert(row.end(), {p ? "= per-camera" : "-", "-"});
        continue;
      }
      const ParameterBound* q = parameter_bound(camera_bound(fs->network.cameras, c), bp.parameter);
      row.push_back(sigma_cell(q));
      row.push_back(p && q ? ratio_cell(q->sigma, p->sigma) : "-");
    }
    t.rows.push_back(row);
  }
  for (const RoutePlanAnalysis& cand : cands) {
    const FreeSetPlan* fs = free_set(cand, k);
    const CameraBound* b = fs ? camera_bound(fs->cameras, c) : nullptr;
    if (!b) continue;
    for (const ParameterBound& p : b->parameters)
      if (p.poorly_determined) t.notes.push_back(flag_note(cand.name, p));
    if (!fs->network.applies()) continue;
    // The network's own flags, where the per-camera calibration has none (the rest read as above).
    if (const CameraBound* nb = camera_bound(fs->network.cameras, c))
      for (const ParameterBound& q : nb->parameters) {
        const ParameterBound* p = parameter_bound(b, q.parameter);
        if (q.poorly_determined && !(p && p->poorly_determined))
          t.notes.push_back(flag_note(cand.name + " network", q));
      }
  }
  if (c + 1 == cands.front().free_sets[k].cameras.size())
    for (const RoutePlanAnalysis& cand : cands)
      if (const FreeSetPlan* fs = free_set(cand, k); fs && !fs->network.applies())
        t.notes.push_back(network_note(cand, *fs));
  return t;
}

/// Free set k's calibration-only intersection σ through the flight volume, both methods.
PlanTable volume_table(const std::vector<RoutePlanAnalysis>& cands, std::size_t k, const std::string& free) {
  PlanTable t;
  t.title =
      "Calibration-only intersection 1σ through the flight volume, free " + free +
      " (mm: rms over points in the lamp-track box seen by ≥ 2 cameras of √trace Σ_cal, noise-free pixels; "
      "per-camera with the cross-covariance its cameras share through the PPK fixes)";
  t.header.push_back("method");
  for (const RoutePlanAnalysis& cand : cands) t.header.push_back(cand.name);
  std::vector<std::string> points{"points"}, per{"per-camera"}, net{"network"}, ratio{"network / per-camera"},
      datum{"network, images " + format_number("%.0f", kDatumFloorImageFactor) + "× sharper (datum floor)"},
      per_ind{"per-camera, cameras independent"}, net_ind{"network, cross blocks dropped"};
  bool any_floor = false;
  for (const RoutePlanAnalysis& cand : cands) {
    const FreeSetPlan* fs = free_set(cand, k);
    if (!fs || fs->volume.n_points == 0) {
      for (auto* row : {&points, &per, &net, &ratio, &datum, &per_ind, &net_ind}) row->push_back("-");
      if (fs && fs->cameras.size() < 2)
        t.notes.push_back(cand.name + ": one camera — nothing to intersect");
      else if (fs)
        t.notes.push_back(cand.name + ": no point of the lamp-track box lies in two images");
      continue;
    }
    const VolumeIntersection& v = fs->volume;
    const bool applies = fs->network.applies();
    points.push_back(std::to_string(v.n_points));
    per.push_back(mm_cell(v.per_camera_m));
    per_ind.push_back(mm_cell(v.per_camera_independent_m));
    net.push_back(applies ? mm_cell(v.network_m) : "= per-camera");
    ratio.push_back(applies ? ratio_cell(v.network_m, v.per_camera_m) : "-");
    datum.push_back(applies ? mm_cell(v.network_datum_floor_m) : "-");
    any_floor = any_floor || applies;
    net_ind.push_back(applies ? mm_cell(v.network_independent_m) : "-");
    if (!applies) t.notes.push_back(network_note(cand, *fs));
  }
  if (any_floor)
    t.notes.push_back(
        "datum floor: the network with every centroid and pick σ divided by " +
        format_number("%.0f", kDatumFloorImageFactor) +
        ", i.e. what the PPK fixes and the control survey alone allow; sharper images cannot go below it, "
        "more fix epochs or control surveyed better than the PPK average can");
  t.rows = {points, per, net, ratio, datum, per_ind, net_ind};
  return t;
}

/// What surveying would buy (SurveyBenefit, the first free set): per number of control poles, the
/// network's flight-volume σ with the stations free and surveyed, per candidate.
PlanTable survey_table(const std::vector<RoutePlanAnalysis>& cands, const std::string& free) {
  PlanTable t;
  t.title = "What surveying buys: network calibration-only intersection 1σ through the flight volume, free " +
            free +
            " (mm, as above), with the first N scenario poles as control (survey σ of the scenario) and the "
            "camera stations free or surveyed to " +
            format_number("%.0f", kSurveyedStationSigmaM * 1e3) + " mm";
  t.header.push_back("control poles");
  for (const RoutePlanAnalysis& cand : cands) {
    t.groups.emplace_back(cand.name, 2);
    t.header.insert(
        t.header.end(),
        {"stations free", "stations " + format_number("%.0f", kSurveyedStationSigmaM * 1e3) + " mm"});
  }
  std::vector<std::size_t> rows;
  for (const RoutePlanAnalysis& cand : cands)
    if (const FreeSetPlan* fs = free_set(cand, 0))
      for (const std::size_t k : fs->survey.control_poles)
        if (std::find(rows.begin(), rows.end(), k) == rows.end()) rows.push_back(k);
  std::sort(rows.begin(), rows.end());
  for (const std::size_t k : rows) {
    std::vector<std::string> row{std::to_string(k)};
    for (const RoutePlanAnalysis& cand : cands) {
      const FreeSetPlan* fs = free_set(cand, 0);
      const SurveyBenefit* b = fs ? &fs->survey : nullptr;
      std::size_t i = 0;
      while (b && i < b->control_poles.size() && b->control_poles[i] != k) ++i;
      const bool has = b && i < b->control_poles.size();
      row.push_back(has ? mm_cell(b->stations_free_m[i]) : "-");
      row.push_back(has ? mm_cell(b->stations_surveyed_m[i]) : "-");
    }
    t.rows.push_back(row);
  }
  t.notes.push_back(
      "control poles: those with role control first, then the others, in scenario order (fewer when the "
      "scenario "
      "has fewer); each adds datum information independent of the PPK errors, which the fixes cannot average "
      "away when they are correlated in time (docs/accuracy_analysis.md \"What surveying buys\")");
  return t;
}

/// Free set k's predicted intersection 1σ at the poles (the run's calibration method, pick σ included).
PlanTable pole_table(const std::vector<RoutePlanAnalysis>& cands, std::size_t k, const std::string& free) {
  PlanTable t;
  t.title =
      "Predicted intersection 1σ at the poles (m; the network's joint covariance where the cameras share "
      "epochs, else the per-camera calibrations with their shared-fix cross-covariances, as the run states "
      "them; pick σ of the scenario), free " +
      free;
  t.header.push_back("pole");
  for (const RoutePlanAnalysis& cand : cands) t.header.push_back(cand.name);
  for (const PoleBound& pb : cands.front().free_sets[k].poles) {
    std::vector<std::string> row{pb.id + " " + pb.role};
    for (const RoutePlanAnalysis& cand : cands) {
      std::string v = "-";
      if (const FreeSetPlan* fs = free_set(cand, k))
        for (const PoleBound& q : fs->poles)
          if (q.id == pb.id && std::isfinite(q.sigma_m)) v = format_number("%.4f", q.sigma_m);
      row.push_back(v);
    }
    t.rows.push_back(row);
  }
  return t;
}

/// The tables of format_plan_table / format_plan_html: per free set, one per camera, the flight
/// volume, then the poles.
std::vector<PlanTable> plan_tables(const std::vector<RoutePlanAnalysis>& cands) {
  std::vector<PlanTable> out;
  if (cands.empty()) return out;
  for (std::size_t k = 0; k < cands.front().free_sets.size(); ++k) {
    const FreeSetPlan& base = cands.front().free_sets[k];
    std::string free;
    for (const auto& f : base.free) free += (free.empty() ? "" : ",") + f;
    bool with_network = false;
    for (const RoutePlanAnalysis& cand : cands)
      if (const FreeSetPlan* fs = free_set(cand, k)) with_network = with_network || fs->network.applies();
    for (std::size_t c = 0; c < base.cameras.size(); ++c)
      out.push_back(camera_table(cands, k, c, free, with_network));
    out.push_back(volume_table(cands, k, free));
    if (k == 0 && !base.survey.control_poles.empty()) out.push_back(survey_table(cands, free));
    out.push_back(pole_table(cands, k, free));
  }
  return out;
}

/// Characters shown (UTF-8 code points: σ, –, ≥ are one column each, as in a terminal).
int display_width(const std::string& s) {
  int n = 0;
  for (const unsigned char ch : s) n += (ch & 0xC0) != 0x80;
  return n;
}

std::string pad_left(const std::string& s, int width) {
  return std::string(static_cast<std::size_t>(std::max(0, width - display_width(s))), ' ') + s;
}

std::string pad_right(const std::string& s, int width) {
  return s + std::string(static_cast<std::size_t>(std::max(0, width - display_width(s))), ' ');
}

}  // namespace

std::string format_plan_table(const std::vector<RoutePlanAnalysis>& cands) {
  std::string s;
  for (const PlanTable& t : plan_tables(cands)) {
    // Every column as wide as its widest cell (names are never cut), at least 14 for the labels
    // and 12 for the values, two spaces apart (a flagged σ and "= per-camera" stay apart); a group
    // label wider than its columns widens the last of them.
    const std::string sep = "  ";
    std::vector<int> width(t.header.size(), 12);
    width[0] = 14;
    for (std::size_t i = 0; i < t.header.size(); ++i) {
      width[i] = std::max(width[i], display_width(t.header[i]));
      for (const auto& row : t.rows)
        if (i < row.size()) width[i] = std::max(width[i], display_width(row[i]));
    }
    std::size_t col = 1;
    for (const auto& [label, span] : t.groups) {
      int w = (span - 1) * display_width(sep);
      for (int j = 0; j < span; ++j) w += width[col + static_cast<std::size_t>(j)];
      width[col + static_cast<std::size_t>(span) - 1] += std::max(0, display_width(label) - w);
      col += static_cast<std::size_t>(span);
    }
    s += t.title + "\n";
    if (!t.groups.empty()) {
      s += "  " + std::string(static_cast<std::size_t>(width[0]), ' ');
      col = 1;
      for (const auto& [label, span] : t.groups) {
        int w = (span - 1) * display_width(sep);
        for (int j = 0; j < span; ++j) w += width[col + static_cast<std::size_t>(j)];
        s += sep + pad_left(label, w);
        col += static_cast<std::size_t>(span);
      }
      s += "\n";
    }
    auto add_row = [&](const std::vector<std::string>& row) {
      s += "  " + pad_right(row[0], width[0]);
      for (std::size_t i = 1; i < row.size() && i < width.size(); ++i) s += sep + pad_left(row[i], width[i]);
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
      "{text-align:left}th{background:#eee}th.group{text-align:center}.flag{background:#fde2e2}"
      "p.note{margin:0.1em 0;color:#a00}</style></head><body>\n"
      "<h1>rangecal plan: predicted calibration accuracy</h1>\n";
  for (const PlanTable& t : plan_tables(cands)) {
    s += "<h2>" + html_escape(t.title) + "</h2>\n<table>\n";
    if (!t.groups.empty()) {
      s += "<tr><th></th>";
      for (const auto& [label, span] : t.groups)
        s += "<th class=\"group\" colspan=\"" + std::to_string(span) + "\">" + html_escape(label) + "</th>";
      s += "</tr>\n";
    }
    s += "<tr>";
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
