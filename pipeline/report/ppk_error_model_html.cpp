#include "pipeline/report/ppk_error_model_html.hpp"

#include <algorithm>
#include <cmath>

#include "config/number_format.hpp"
#include "pipeline/report/correction_autocorrelation.hpp"
#include "pipeline/report/report_plots.hpp"

namespace rangecal {
namespace {

/// The fewest pairs a bin of the chart needs (and a tenth of the fullest bin's).
constexpr long kMinPairs = 30;

std::string td(const std::string& html, const char* cls = "num") {
  return std::string("<td class=\"") + cls + "\">" + html + "</td>";
}
std::string th(const std::string& html) {
  return "<th>" + html + "</th>";
}

// A value with its σ when estimated: "v ± σ", else "v" (fixed in the config).
std::string with_sigma(const char* f, double value, double sigma, double unit = 1) {
  std::string s = format_number(f, value * unit);
  if (std::isfinite(sigma)) s += " &#177; " + format_number(f, sigma * unit);
  return s;
}
std::string source(double sigma_h, double sigma_v) {
  return std::isfinite(sigma_h) || std::isfinite(sigma_v) ? "estimated &#177; 1&#963;"
                                                          : "fixed in the config";
}
// σ_g's source: estimated, or held at the .pos sd because the record is shorter than 4τ̂
// (optim/network/ppk_error_estimation.hpp), or fixed in the config.
std::string gm_sd_source(const PpkErrorModelRecord& r) {
  if (!r.estimated || !(r.gm_sd_held_h || r.gm_sd_held_v))
    return source(r.sigma.gm_sd_h_m, r.sigma.gm_sd_v_m);
  const std::string which = r.gm_sd_held_h && r.gm_sd_held_v ? "both"
                            : r.gm_sd_held_h                 ? "horizontal"
                                                             : "vertical";
  return which + " held at the .pos sd: the record (" + format_number("%.0f", r.record_s) +
         " s) is shorter than 4&#964;&#770;, which cannot tell &#963;<sub>g</sub> from &#964;";
}

// The model's table: white scale, and for a correlated model the GM sd and τ, each h and v.
std::string model_table(const PpkErrorModelRecord& r) {
  const PpkErrorModel &m = r.model, &s = r.sigma;
  std::string t = "<table class=\"ppk-model\">\n<tr>" + th("Part") + th("Horizontal (E, N)") +
                  th("Vertical (U)") + th("Source") + "</tr>\n";
  t += "<tr>" + th("white scale s (&#215; .pos sd)") +
       td(with_sigma("%.3f", m.white_scale_h, s.white_scale_h)) +
       td(with_sigma("%.3f", m.white_scale_v, s.white_scale_v)) +
       td(source(s.white_scale_h, s.white_scale_v), "txt") + "</tr>\n";
  if (!m.correlated())
    return t + "<tr>" + th("Gauss&#8211;Markov part") + td("none", "txt") + td("none", "txt") +
           td(r.white_kept ? "white: the likelihood-ratio test found no slow part"
                           : "white (every fix independent)",
              "txt") +
           "</tr>\n</table>\n";
  t += "<tr>" + th("Gauss&#8211;Markov &#963;<sub>g</sub> /cm") +
       td(with_sigma("%.2f", m.gm_sd_h_m, s.gm_sd_h_m, 100)) +
       td(with_sigma("%.2f", m.gm_sd_v_m, s.gm_sd_v_m, 100)) + td(gm_sd_source(r), "txt") + "</tr>\n";
  t += "<tr>" + th("Gauss&#8211;Markov &#964; /s") + td(with_sigma("%.1f", m.tau_h_s, s.tau_h_s)) +
       td(with_sigma("%.1f", m.tau_v_s, s.tau_v_s)) + td(source(r.sigma.tau_h_s, r.sigma.tau_v_s), "txt") +
       "</tr>\n";
  t += "<tr>" + th("independent looks") + td(format_number("%.1f", r.looks_h)) +
       td(format_number("%.1f", r.looks_v)) + td(std::to_string(r.states) + " chained epochs", "txt") +
       "</tr>\n";
  return t + "</table>\n";
}

// The median of the PPK fixes' own sd over E and N pooled (h) or U (v), m; NaN without a track.
double median_pos_sd(const ReportData& d, bool vertical) {
  std::vector<double> sd;
  if (d.lamp_track)
    for (const LampEpoch& e : d.lamp_track->epochs)
      for (int a : vertical ? std::vector<int>{2} : std::vector<int>{0, 1}) sd.push_back(e.sd_enu[a]);
  if (sd.empty()) return std::nan("");
  std::nth_element(sd.begin(), sd.begin() + static_cast<std::ptrdiff_t>(sd.size() / 2), sd.end());
  return sd[sd.size() / 2];
}

// One axis's chart: the kept epochs' corrections (E and N pooled for h) against the model's ρ.
std::string autocorrelation_figure(const ReportData& d, const PpkErrorModel& m, bool vertical) {
  const std::vector<LampTrackAdjustedRow>& rows = *d.network_track;
  std::vector<double> t;
  std::vector<std::vector<double>> series(vertical ? 1 : 2);
  for (const LampTrackAdjustedRow& r : rows) {
    t.push_back(seconds_between(rows.front().utc, r.utc));
    for (std::size_t k = 0; k < series.size(); ++k)  // a flagged fix's correction is its blunder
      series[k].push_back(r.flagged ? std::nan("") : r.correction[vertical ? 2 : static_cast<int>(k)]);
  }
  const AutocorrelationLags lags = autocorrelation_lags(m, t);
  const std::vector<AutocorrelationBin> bins =
      empirical_autocorrelation(t, series, lags.bin_s, lags.max_lag_s);
  // A bin of few pairs (lags as long as a whole flight) is one or two products, not an estimate.
  long most = 0;
  for (const AutocorrelationBin& b : bins) most = std::max(most, b.pairs);
  const long min_pairs = std::max(kMinPairs, most / 10);
  std::vector<double> lag, rho, model_lag, model_rho;
  for (const AutocorrelationBin& b : bins)
    if (b.pairs >= min_pairs) lag.push_back(b.lag_s), rho.push_back(b.rho);
  // The model over the lags shown (the whole range when no bin is).
  const double reach = lag.empty() ? lags.max_lag_s : std::min(lags.max_lag_s, lag.back() + lags.bin_s);
  const double sw = (vertical ? m.white_scale_v : m.white_scale_h) * median_pos_sd(d, vertical);
  const bool curve = std::isfinite(sw) || !m.correlated();
  for (int k = 0; curve && k <= 100; ++k) {
    model_lag.push_back(reach * k / 100);
    model_rho.push_back(model_autocorrelation(vertical ? m.gm_sd_v_m : m.gm_sd_h_m,
                                              vertical ? m.tau_v_s : m.tau_h_s, std::isfinite(sw) ? sw : 0,
                                              model_lag.back()));
  }
  const std::string axis = vertical ? "vertical (U)" : "horizontal (E, N pooled)";
  const std::string id = vertical ? "ppk-acf-v" : "ppk-acf-h";
  const std::string model_caption =
      curve
          ? "; red: the model's &#961;(lag) = &#963;<sub>g</sub>&#178; e<sup>&#8722;lag/&#964;</sup> / "
            "(&#963;<sub>w</sub>&#178; + &#963;<sub>g</sub>&#178;), &#963;<sub>w</sub> = s &#215; the median "
            ".pos sd (" +
                format_number("%.2f", std::isfinite(sw) ? sw * 100 : 0) + " cm)"
          : "; no model curve: gnss/lamp_track.csv (the .pos sd) is missing";
  return "<figure>" +
         svg_autocorrelation(lag, rho, model_lag, model_rho,
                             std::string(vertical ? "ρ of dU (1)" : "ρ of dE, dN (1)"), id,
                             "PPK corrections' autocorrelation, " + axis) +
         "<figcaption>Autocorrelation of the corrections, " + axis + ", in bins of " +
         format_number("%.2f", lags.bin_s) + " s up to " + format_number("%.0f", lags.max_lag_s) +
         " s (pairs within one series; flagged epochs left out; bins of fewer than " +
         std::to_string(min_pairs) + " pairs not shown)" + model_caption + "</figcaption></figure>\n";
}

// The looks and what would lower the error they leave.
std::string looks_paragraph(const PpkErrorModelRecord& r) {
  const std::string lower =
      "What would lower it: more control poles (each a survey independent of the PPK errors), camera "
      "stations surveyed (calibrate priors on the centre), and ascents spread in time (a gap of many "
      "&#964; between flights starts a new look; longer flights add about one look per 2&#964;).";
  if (!r.model.correlated())
    return "<p>Under a white model every fix is an independent look at the PPK error, so the datum error "
           "averages down with the number of fixes. If the corrections above stay well above zero over "
           "seconds, the fixes are not independent and the &#963; are optimistic: set gnss.error_model "
           "(docs/gnss.md \"PPK error model\"). " +
           lower + "</p>\n";
  const double looks = std::min(r.looks_h, r.looks_v);
  std::string s =
      "<p>The fixes the network used give " + format_number("%.1f", r.looks_h) + " horizontal and " +
      format_number("%.1f", r.looks_v) +
      " vertical independent looks at the slow (Gauss&#8211;Markov) PPK error "
      "(1<sup>T</sup>R<sup>&#8722;1</sup>1, "
      "docs/accuracy_analysis.md \"Correlated PPK errors\"): the datum the lamp track gives the "
      "cameras is known to about &#963;<sub>g</sub>/&#8730;looks, whatever the number of fixes. " +
      lower + "</p>\n";
  if (std::isfinite(looks) && looks < kFewPpkLooks)
    s += "<p class=\"warn\">Fewer than " + format_number("%.0f", kFewPpkLooks) +
         " independent looks: the datum rests on few samples of the PPK error, and the calibration's "
         "position and scale carry it.</p>\n";
  return s;
}

}  // namespace

std::string ppk_error_model_section(const ReportData& d) {
  if (!d.network_track) return "";
  std::string s =
      "<section id=\"ppk-error-model\">\n<h2>PPK error model</h2>\n<p>How the network weighed the PPK fixes "
      "(docs/gnss.md \"PPK error model\"): a white part, s &#215; each fix's .pos sd, and a slow "
      "first-order Gauss&#8211;Markov part with sd &#963;<sub>g</sub> and correlation time &#964;, "
      "horizontal and vertical.</p>\n";
  const std::optional<PpkErrorModelRecord>& r =
      d.network_statistics ? d.network_statistics->ppk_error_model : std::optional<PpkErrorModelRecord>();
  if (!r)
    return s +
           "<p class=\"missing\">run.json has no PPK error model "
           "(stages.calibrate.counts.network.ppk_error_model).</p>\n</section>\n";
  s += model_table(*r);
  s += "<p>A correction (adjusted &#8722; PPK fix) is, where the cameras place the lamp well, minus the "
       "fix's error: under the model its autocorrelation between two fixes is the Gauss&#8211;Markov "
       "part's share of the variance, decaying with the time between them, and zero for a white model. "
       "The empirical points come from the corrections with each series' mean removed, which pulls them "
       "down when there are few independent looks.</p>\n";
  if (!d.network_track->empty())
    s += autocorrelation_figure(d, r->model, false) + autocorrelation_figure(d, r->model, true);
  return s + looks_paragraph(*r) + "</section>\n";
}

}  // namespace rangecal
