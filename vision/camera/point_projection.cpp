#include "vision/camera/point_projection.hpp"

#include <functional>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"
#include "config/physical_ranges.hpp"
#include "gnss/geodesy/local_enu.hpp"

namespace rangecal {
namespace {

/// `id,u,v` for every record of `t`, whose world point (site ENU, m) `world` reads; `fields`
/// names the point's columns in messages.
std::string project_table(const Camera& cam, const CsvTable& t, const std::string& fields,
                          const std::string& calibration_file,
                          const std::function<Eigen::Vector3d(const CsvRecord&)>& world) {
  const std::size_t ci = t.column("id");
  std::string out = "id,u,v\n";
  for (const CsvRecord& r : t.records) {
    const Eigen::Vector3d Xw = world(r);
    const std::string& id = t.text(r, ci);
    const double zc = world_to_camera(cam.pose, Xw).z();
    if (!(zc > 0))
      throw_input_error(t.path, r.line, fields,
                        "point '" + id + "' is behind camera '" + cam.id +
                            "' (depth along the optical axis " + std::to_string(zc) + " m)");
    Eigen::Vector2d uv;
    if (!project(cam, Xw, &uv))
      throw_input_error(
          t.path, r.line, fields,
          "point '" + id + "' lies outside the region where camera '" + cam.id + "''s distortion model" +
              (calibration_file.empty() ? "" : " (" + calibration_file + ")") + " can be inverted");
    out += id;
    fmt::format_to(std::back_inserter(out), ",{:.6f},{:.6f}\n", uv.x(), uv.y());
  }
  return out;
}

}  // namespace

std::string project_points_csv(const Camera& cam, const std::string& points_csv_text,
                               const std::string& points_file, const std::string& calibration_file) {
  const CsvTable t = parse_csv(points_csv_text, points_file);
  t.column("id");
  const std::size_t ce = t.column("E"), cn = t.column("N"), cu = t.column("U");
  return project_table(cam, t, "E,N,U", calibration_file, [&](const CsvRecord& r) {
    return Eigen::Vector3d(t.number(r, ce), t.number(r, cn), t.number(r, cu));
  });
}

std::string project_geodetic_points_csv(const Camera& cam, const GeodeticOrigin& origin,
                                        const std::string& points_csv_text, const std::string& points_file,
                                        const std::string& calibration_file) {
  const CsvTable t = parse_csv(points_csv_text, points_file);
  t.column("id");
  const std::size_t cla = t.column("lat"), clo = t.column("lon"), ch = t.column("h");
  const LocalEnu site(origin);
  return project_table(cam, t, "lat,lon,h", calibration_file, [&](const CsvRecord& r) {
    const Eigen::Vector3d llh(
        t.number_in(r, cla, -90, 90, "latitude, degrees"),
        t.number_in(r, clo, -180, 180, "longitude, degrees"),
        t.number_in(r, ch, ranges::kMinHeightM, ranges::kMaxHeightM, "ellipsoidal height, m"));
    const Eigen::Vector3d enu = site.from_geodetic(llh);
    if (!ranges::within_site_box(enu.x(), enu.y(), enu.z()))
      throw_input_error(t.path, r.line, "lat",
                        "point lies " + std::to_string(static_cast<long long>(enu.head<2>().norm() / 1000)) +
                            " km from the calibration's site origin, outside the site box of +/-50 km "
                            "(wrong file, or a swapped lat/lon?)");
    return enu;
  });
}

}  // namespace rangecal
