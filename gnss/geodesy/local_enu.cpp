#include "gnss/geodesy/local_enu.hpp"

#include <GeographicLib/Geocentric.hpp>
#include <cmath>
#include <vector>

#include "config/error.hpp"

namespace rangecal {

Eigen::Vector3d geodetic_to_ecef(const Eigen::Vector3d& llh) {
  Eigen::Vector3d x;
  GeographicLib::Geocentric::WGS84().Forward(llh[0], llh[1], llh[2], x[0], x[1], x[2]);
  return x;
}

Eigen::Vector3d ecef_to_geodetic(const Eigen::Vector3d& xyz) {
  Eigen::Vector3d llh;
  GeographicLib::Geocentric::WGS84().Reverse(xyz[0], xyz[1], xyz[2], llh[0], llh[1], llh[2]);
  return llh;
}

Eigen::Matrix3d ecef_to_enu_rotation(double lat_deg, double lon_deg) {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  const double sp = std::sin(lat_deg * kDeg), cp = std::cos(lat_deg * kDeg);
  const double sl = std::sin(lon_deg * kDeg), cl = std::cos(lon_deg * kDeg);
  Eigen::Matrix3d R;
  R << -sl, cl, 0,             //
      -sp * cl, -sp * sl, cp,  //
      cp * cl, cp * sl, sp;
  return R;
}

LocalEnu::LocalEnu(const GeodeticOrigin& origin)
    : origin_(origin), lc_(origin.lat_deg, origin.lon_deg, origin.h_m) {
  origin_ecef_ = geodetic_to_ecef(Eigen::Vector3d(origin.lat_deg, origin.lon_deg, origin.h_m));
  r_ecef_to_enu_ = ecef_to_enu_rotation(origin.lat_deg, origin.lon_deg);
}

Eigen::Vector3d LocalEnu::from_geodetic(const Eigen::Vector3d& llh) const {
  Eigen::Vector3d e;
  lc_.Forward(llh[0], llh[1], llh[2], e[0], e[1], e[2]);
  return e;
}

Eigen::Vector3d LocalEnu::from_geodetic(const Eigen::Vector3d& llh, Eigen::Matrix3d* M) const {
  Eigen::Vector3d e;
  std::vector<double> m(9);
  lc_.Forward(llh[0], llh[1], llh[2], e[0], e[1], e[2], m);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) (*M)(r, c) = m[3 * r + c];  // row-major, v_site = M·v_point
  return e;
}

Eigen::Vector3d LocalEnu::to_geodetic(const Eigen::Vector3d& enu) const {
  Eigen::Vector3d llh;
  lc_.Reverse(enu[0], enu[1], enu[2], llh[0], llh[1], llh[2]);
  return llh;
}

Eigen::Vector3d LocalEnu::from_ecef(const Eigen::Vector3d& xyz) const {
  // LocalCartesian has no ECEF entry point; the rotation of the ECEF difference is what its
  // Forward does after its own geodetic → ECEF step (GeographicLib LocalCartesian.cpp).
  return r_ecef_to_enu_ * (xyz - origin_ecef_);
}

Eigen::Vector3d LocalEnu::to_ecef(const Eigen::Vector3d& enu) const {
  return origin_ecef_ + r_ecef_to_enu_.transpose() * enu;
}

EnuFix to_site_enu(const PosFile& file, const PosEpoch& ep, const LocalEnu& site) {
  EnuFix out;
  const Eigen::Matrix3d& Rs = site.ecef_to_enu();
  switch (file.header.position_format) {
    case PosPositionFormat::llh_deg:
    case PosPositionFormat::llh_dms: {
      Eigen::Matrix3d M;
      out.enu = site.from_geodetic(ep.position, &M);
      out.cov_enu = M * ep.covariance * M.transpose();
      out.sd_local = ep.covariance.diagonal().cwiseSqrt();
      if (ep.has_velocity) out.vel_enu = M * ep.velocity;
      break;
    }
    case PosPositionFormat::ecef: {
      out.enu = site.from_ecef(ep.position);
      out.cov_enu = Rs * ep.covariance * Rs.transpose();
      const Eigen::Vector3d llh = ecef_to_geodetic(ep.position);
      const Eigen::Matrix3d Rl = ecef_to_enu_rotation(llh[0], llh[1]);
      out.sd_local = (Rl * ep.covariance * Rl.transpose()).diagonal().cwiseSqrt();
      if (ep.has_velocity) out.vel_enu = Rs * ep.velocity;
      break;
    }
    case PosPositionFormat::enu_baseline: {
      if (!file.header.ref_pos_ecef)
        throw_input_error(file.path, file.header.column_header_line, "ref pos",
                          "an e/n/u-baseline file needs the '% ref pos :' header line to place the baseline");
      const Eigen::Vector3d& ref = *file.header.ref_pos_ecef;
      const Eigen::Vector3d ref_llh = ecef_to_geodetic(ref);
      const Eigen::Matrix3d Rr = ecef_to_enu_rotation(ref_llh[0], ref_llh[1]);
      // RTKLIB outenu: enu = R_ref·(rover − ref), so rover = ref + R_refᵀ·enu.
      out.enu = site.from_ecef(ref + Rr.transpose() * ep.position);
      const Eigen::Matrix3d M = Rs * Rr.transpose();  // ref ENU → site ENU
      out.cov_enu = M * ep.covariance * M.transpose();
      out.sd_local = ep.covariance.diagonal().cwiseSqrt();
      break;
    }
  }
  return out;
}

}  // namespace rangecal
