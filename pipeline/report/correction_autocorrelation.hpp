#pragma once
// The PPK corrections' autocorrelation against the error model's (docs/outputs.md "PPK error
// model"). A correction is adjusted − PPK fix (gnss/lamp_track_adjusted.csv): where the cameras place
// the lamp well it is minus the fix's error, e = w + g (gnss/track/ppk_error_model.hpp), so its
// autocorrelation at lag Δt > 0 should follow the model's
//   ρ(Δt) = σ_g²·exp(−Δt/τ) / (σ_w² + σ_g²),   σ_w = s·(the .pos sd),
// zero for a white model. Epochs are irregular and the flights are separated by gaps, so pairs are
// binned by their time lag and taken only up to a largest lag.
#include <vector>

#include "gnss/track/ppk_error_model.hpp"

namespace rangecal {

/// One lag bin of the empirical autocorrelation.
struct AutocorrelationBin {
  double lag_s = 0;  ///< mean lag of the pairs in the bin (s)
  double rho = 0;    ///< their mean product over the series' variance
  long pairs = 0;
};

/// The empirical autocorrelation of the series (each as long as `t_s`, ascending times; NaN values
/// skipped), pooled: each series has its mean removed, the variance is Σ(x − x̄)² / n over all series,
/// and bin k holds the pairs i < j of one series with t_j − t_i in [(k − ½)·bin_s, (k + ½)·bin_s),
/// k = 0 … ⌊max_lag_s / bin_s⌋ (bin 0 only lags below ½·bin_s, a pair never with itself). Bins
/// without pairs are left out; empty when the variance is zero.
std::vector<AutocorrelationBin> empirical_autocorrelation(const std::vector<double>& t_s,
                                                          const std::vector<std::vector<double>>& series,
                                                          double bin_s, double max_lag_s);

/// The model's ρ between two distinct fixes `lag_s` apart on one axis, σ_g²·exp(−|lag|/τ)/(σ_w² + σ_g²)
/// (at lag 0 its limit, the GM part's share of the variance: a fix with itself is 1); 0 for σ_g = 0
/// (white).
double model_autocorrelation(double gm_sd_m, double tau_s, double white_sd_m, double lag_s);

/// Largest lag and bin width shown: up to 3τ (the longer axis's) but at most 120 s for a correlated
/// model, 30 s for a white one; the bin a fortieth of that, but not below the median epoch spacing
/// of `t_s` (ascending).
struct AutocorrelationLags {
  double max_lag_s = 30, bin_s = 0.75;
};
AutocorrelationLags autocorrelation_lags(const PpkErrorModel& m, const std::vector<double>& t_s);

}  // namespace rangecal
