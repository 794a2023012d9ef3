#include "optim/bundle/bundle_diagnostics.hpp"

#include <algorithm>
#include <cmath>

#include "config/chi2_quantile.hpp"
#include "config/number_format.hpp"

namespace rangecal {

using P = CameraParameter;

namespace {

std::string g3(double v) {
  return format_number("%.3g", v);
}

/// Why parameter p with 1σ `s` is poorly determined, or "" when it is not. `rmax` is the sensor
/// distance (mm) from the principal point to the farthest image corner.
std::string poorly_determined_because(P p, double s, const CameraIntrinsics& in, double rmax,
                                      double max_speed_mps) {
  const double pix = std::min(in.dx_mm, in.dy_mm);
  double effect_px = -1;  // distortion terms: image-corner displacement of a 1σ change
  switch (p) {
    case P::f:
      return s > 0.01 * in.f_mm ? "σ " + g3(s) + " mm is more than 1 % of f" : "";
    case P::u0:
      return s > 0.05 * in.width_px ? "σ " + g3(s) + " px is more than 5 % of the image size" : "";
    case P::v0:
      return s > 0.05 * in.height_px ? "σ " + g3(s) + " px is more than 5 % of the image size" : "";
    case P::sx:
      return s > 0.01 ? "σ " + g3(s) + " is more than 0.01" : "";
    case P::k1:
      effect_px = s * std::pow(rmax, 3) / pix;
      break;
    case P::k2:
      effect_px = s * std::pow(rmax, 5) / pix;
      break;
    case P::k3:
      effect_px = s * std::pow(rmax, 7) / pix;
      break;
    case P::p1:
    case P::p2:
      effect_px = s * 3 * rmax * rmax / pix;
      break;
    case P::a1:
    case P::a2:
      effect_px = s * rmax / pix;
      break;
    case P::clock_offset:
      return s * max_speed_mps > kClockWarningM
                 ? "σ " + g3(s * 1e3) + " ms moves the fastest lamp point (" + g3(max_speed_mps) +
                       " m/s) by " + g3(s * max_speed_mps * 100) +
                       " cm (> 2 cm); fly faster ascents and descents, or fix it"
                 : "";
    default:
      if (is_rotation(p)) return s > 1e-3 ? "σ " + g3(s) + " rad is more than 1 mrad" : "";
      if (is_center(p)) return s > 1.0 ? "σ " + g3(s) + " m is more than 1 m" : "";
      return "";
  }
  const double limit = 1;
  return effect_px > limit
             ? "a 1σ change moves the image corner by " + g3(effect_px) + " px (> " + g3(limit) + " px)"
             : "";
}

}  // namespace

std::vector<CalibrationWarning> poorly_determined_warnings(const CalibrationResult& cal, double max_speed_mps,
                                                           double correlation_warning) {
  std::vector<CalibrationWarning> out;
  const int p = static_cast<int>(cal.parameters.size());
  if (cal.covariance.rows() != p) return out;
  const CameraIntrinsics& in = cal.camera.intr;
  const double hw = std::max(in.u0_px, in.width_px - 1 - in.u0_px) * in.dx_mm / in.sx;
  const double hh = std::max(in.v0_px, in.height_px - 1 - in.v0_px) * in.dy_mm;
  const double rmax = std::sqrt(hw * hw + hh * hh);  // sensor mm to the farthest corner
  for (int k = 0; k < p; ++k) {
    const std::string why = poorly_determined_because(cal.parameters[k], std::sqrt(cal.covariance(k, k)), in,
                                                      rmax, max_speed_mps);
    if (!why.empty())
      out.push_back(
          {CalibrationWarningKind::poorly_determined,
           {cal.parameters[k]},
           "parameter " + std::string(parameter_name(cal.parameters[k])) + " is poorly determined: " + why});
  }
  for (int a = 0; a < p; ++a)
    for (int b = a + 1; b < p; ++b) {
      const double rho = cal.correlation(cal.parameters[a], cal.parameters[b]);
      if (std::abs(rho) > correlation_warning)
        out.push_back({CalibrationWarningKind::correlated,
                       {cal.parameters[a], cal.parameters[b]},
                       "parameters " + std::string(parameter_name(cal.parameters[a])) + " and " +
                           parameter_name(cal.parameters[b]) + " are correlated (ρ = " + g3(rho) +
                           "): the data cannot separate them; fix one or add a prior"});
    }
  return out;
}

std::vector<CalibrationWarning> fit_warnings(const BundleDetails& d) {
  std::vector<CalibrationWarning> out;
  if (d.clock_offset_s && std::abs(*d.clock_offset_s) > kLargeClockOffsetS) {
    const double c = *d.clock_offset_s;
    out.push_back(
        {CalibrationWarningKind::large_clock_offset,
         {CameraParameter::clock_offset},
         "clock offset " + g3(c * 1e3) +
             " ms is large for the first-order model X − v·δ (it misses ½·a·δ², " +
             g3(0.5 * 1.5 * c * c * 1e3) +
             " mm at 1.5 m/s²): shift the frame time stamps by it and rerun align, detect and calibrate"});
  }
  if (d.dof > 0) {
    // χ² test at the 1 % level.
    if (d.chi2 > chi2_quantile_wilson_hilferty(d.dof, kNormalQuantile99))
      out.push_back({CalibrationWarningKind::variance_factor,
                     {},
                     "a-posteriori variance factor " + g3(d.variance_factor) +
                         " exceeds 1: the assumed pixel/PPK noise is too optimistic or the model misses "
                         "something; σ scaled by √factor are in details.sigma_scaled"});
  } else {
    out.push_back({CalibrationWarningKind::no_redundancy,
                   {},
                   "no redundancy (dof = 0): the variance factor and outlier test are meaningless"});
  }
  return out;
}

}  // namespace rangecal
