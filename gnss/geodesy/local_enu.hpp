#pragma once
// The world frame (docs/conventions.md): local ENU (x east, y north, z up, metres) about site.origin (WGS84
// lat, lon in degrees, ellipsoidal height in metres), via GeographicLib::LocalCartesian. Also the
// conversion of every RTKLIB .pos position format (and its covariance) into that frame.
#include <Eigen/Core>
#include <GeographicLib/LocalCartesian.hpp>
#include <limits>

#include "gnss/formats/rtklib_pos_reader.hpp"
#include "gnss/geodesy/geodetic_origin.hpp"

namespace rangecal {

/// WGS84 geodetic (lat deg, lon deg, h m) → ECEF (m).
Eigen::Vector3d geodetic_to_ecef(const Eigen::Vector3d& llh);
/// ECEF (m) → WGS84 geodetic (lat deg, lon deg, h m).
Eigen::Vector3d ecef_to_geodetic(const Eigen::Vector3d& xyz);
/// Rotation taking ECEF vector components to the local ENU frame at geodetic (lat, lon) (deg):
/// v_enu = R · v_ecef (rows are the E, N, U unit vectors in ECEF).
Eigen::Matrix3d ecef_to_enu_rotation(double lat_deg, double lon_deg);

/// The site's ENU frame.
class LocalEnu {
 public:
  explicit LocalEnu(const GeodeticOrigin& origin);

  const GeodeticOrigin& origin() const { return origin_; }
  /// geodetic (lat deg, lon deg, h m) → ENU (m).
  Eigen::Vector3d from_geodetic(const Eigen::Vector3d& llh) const;
  /// As from_geodetic, also returning the rotation M taking vector components in the local ENU
  /// frame at the point to the site ENU frame (v_site = M · v_point), for covariances.
  Eigen::Vector3d from_geodetic(const Eigen::Vector3d& llh, Eigen::Matrix3d* M) const;
  /// ENU (m) → geodetic (lat deg, lon deg, h m).
  Eigen::Vector3d to_geodetic(const Eigen::Vector3d& enu) const;
  /// ECEF (m) → ENU (m).
  Eigen::Vector3d from_ecef(const Eigen::Vector3d& xyz) const;
  /// ENU (m) → ECEF (m).
  Eigen::Vector3d to_ecef(const Eigen::Vector3d& enu) const;
  /// v_site_enu = R · v_ecef.
  const Eigen::Matrix3d& ecef_to_enu() const { return r_ecef_to_enu_; }

 private:
  GeodeticOrigin origin_;
  GeographicLib::LocalCartesian lc_;
  Eigen::Vector3d origin_ecef_;
  Eigen::Matrix3d r_ecef_to_enu_;
};

/// A .pos epoch's antenna position in site ENU, with covariance in site ENU and the 1σ used for
/// filtering (sd in the local ENU frame at the epoch, as RTKLIB's sdn/sde/sdu; for ECEF files the
/// ECEF covariance rotated to the local ENU at the epoch).
struct EnuFix {
  Eigen::Vector3d enu = Eigen::Vector3d::Zero();
  Eigen::Matrix3d cov_enu = Eigen::Matrix3d::Zero();   ///< site ENU, m²
  Eigen::Vector3d sd_local = Eigen::Vector3d::Zero();  ///< (sdE, sdN, sdU) at the epoch, m
  /// Velocity in site ENU (m/s), NaN when the file has none.
  Eigen::Vector3d vel_enu = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
};

/// Converts one epoch of `file` into site ENU. llh: via LocalCartesian; ECEF: via LocalCartesian
/// of the ECEF point; ENU baseline: rover ECEF = ref pos ECEF + R_ref⁻¹·(e, n, u), then as ECEF.
/// Throws rangecal::Error (input) when an ENU-baseline file has no `ref pos` header.
EnuFix to_site_enu(const PosFile& file, const PosEpoch& epoch, const LocalEnu& site);

}  // namespace rangecal
