#pragma once
// The site origin (docs/conventions.md): the point the local ENU world frame is tangent at, on the WGS84
// ellipsoid. Every ENU coordinate in rangecal is about one such origin (config `site.origin`).

namespace rangecal {

struct GeodeticOrigin {
  double lat_deg = 0;  ///< WGS84 latitude, degrees, [-90, 90]
  double lon_deg = 0;  ///< WGS84 longitude, degrees, [-180, 180]
  double h_m = 0;      ///< ellipsoidal height, metres
};

}  // namespace rangecal
