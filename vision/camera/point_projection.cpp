#include "vision/camera/point_projection.hpp"

#include <cstdio>

#include "config/csv_table.hpp"
#include "config/error.hpp"

namespace rangecal {

std::string project_points_csv(const Camera& cam, const std::string& points_csv_text,
                               const std::string& points_file) {
  const CsvTable t = parse_csv(points_csv_text, points_file);
  const std::size_t ci = t.column("id"), ce = t.column("E"), cn = t.column("N"), cu = t.column("U");
  std::string out = "id,u,v\n";
  for (const CsvRecord& r : t.records) {
    const Eigen::Vector3d Xw(t.number(r, ce), t.number(r, cn), t.number(r, cu));
    const std::string& id = t.text(r, ci);
    const double zc = world_to_camera(cam.pose, Xw).z();
    if (!(zc > 0))
      throw_input_error(points_file, r.line, "E,N,U",
                        "point '" + id + "' is behind camera '" + cam.id +
                            "' (depth along the optical axis " + std::to_string(zc) + " m)");
    Eigen::Vector2d uv;
    if (!project(cam, Xw, &uv))
      throw_input_error(points_file, r.line, "E,N,U",
                        "point '" + id + "' lies outside the region where camera '" + cam.id +
                            "''s distortion model can be inverted");
    char buf[96];
    std::snprintf(buf, sizeof buf, ",%.6f,%.6f\n", uv.x(), uv.y());
    out += id + buf;
  }
  return out;
}

}  // namespace rangecal
