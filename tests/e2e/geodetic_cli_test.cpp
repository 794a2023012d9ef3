// `rangecal project --geodetic` and `rangecal intersect --geodetic`: points given and returned as
// WGS84 lat, lon, h about the site origin calibration.json records, checked against GeographicLib's
// own command-line tool CartConvert (geographiclib-tools) as the independent conversion; files
// without the origin (older ones) still project E,N,U but refuse geodetic coordinates; cameras in
// different ENU frames are not triangulated together.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>

#include "config/csv_table.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "support/paths.hpp"
#include "support/synthetic_camera.hpp"

namespace rangecal {
namespace {

// Near Galway (tests/data/external/gnss), an ellipsoidal height typical of the site.
const GeodeticOrigin kOrigin{53.2744213, -9.0490137, 64.318};
const Eigen::Vector3d kAim(0, 0, 4);

std::string q(const std::filesystem::path& p) {
  return "'" + p.string() + "'";
}

const char* kCartConvert = "/usr/bin/CartConvert";

/// Runs CartConvert on `input` lines (its own text interface) and returns its output lines.
std::vector<std::string> cart_convert(const std::string& options, const std::string& input,
                                      const std::filesystem::path& dir) {
  const auto in = dir / "cartconvert_in.txt";
  test::write_text(in, input);
  const std::string cmd = std::string(kCartConvert) + " " + options + " -p 9 --input-file " + q(in);
  FILE* f = popen(cmd.c_str(), "r");
  EXPECT_NE(f, nullptr) << cmd;
  std::string out;
  std::array<char, 512> buf;
  while (f && fgets(buf.data(), buf.size(), f)) out += buf.data();
  if (f) {
    EXPECT_EQ(pclose(f), 0) << cmd;
  }
  std::vector<std::string> lines;
  std::istringstream is(out);
  for (std::string l; std::getline(is, l);) lines.push_back(l);
  return lines;
}

std::string origin_options() {
  char buf[128];
  std::snprintf(buf, sizeof buf, "-l %.10f %.10f %.6f", kOrigin.lat_deg, kOrigin.lon_deg, kOrigin.h_m);
  return buf;
}

struct Scene {
  std::vector<Camera> cameras;
  std::vector<std::pair<std::string, Eigen::Vector3d>> points;  // id, ENU (m)
};

Scene scene() {
  Scene s;
  s.cameras = {test::range_camera_at("cam1", {-45, -45, 1.5}, kAim),
               test::range_camera_at("cam2", {45, -45, 1.8}, kAim)};
  s.points = {
      {"P1", {0, 0, 4}}, {"P2", {-2.5, 1.5, 7.25}}, {"P3", {3.0, -2.0, 1.1}}, {"P4", {1.2, 2.8, 6.1}}};
  return s;
}

std::filesystem::path write_calibration(const std::filesystem::path& dir, const Camera& cam,
                                        std::optional<GeodeticOrigin> origin) {
  CalibrationResult r;
  r.camera_id = cam.id;
  r.method = "bundle";
  r.camera = cam;
  r.site_origin = origin;
  const auto path = dir / (cam.id + ".json");
  write_calibration_json(path.string(), r);
  return path;
}

TEST(GeodeticCli, CartConvertIsInstalled) {
  ASSERT_TRUE(std::filesystem::exists(kCartConvert))
      << "CartConvert (Debian package geographiclib-tools, installed by setup.sh) is the independent "
         "truth of these tests";
}

TEST(GeodeticCli, ProjectTakesLatLonHAgreeingWithCartConvert) {
  if (!std::filesystem::exists(kCartConvert)) GTEST_SKIP() << "see CartConvertIsInstalled";
  const auto dir = test::scratch_dir("geodetic_project");
  const Scene s = scene();
  const auto cal = write_calibration(dir, s.cameras[0], kOrigin);
  // ENU → geodetic by CartConvert (-r: local cartesian to geodetic).
  std::string enu;
  for (const auto& [id, p] : s.points)
    enu += std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
  const auto llh = cart_convert("-r " + origin_options(), enu, dir);
  ASSERT_EQ(llh.size(), s.points.size());
  std::string csv = "id,lat,lon,h\n";
  for (std::size_t i = 0; i < llh.size(); ++i) {
    std::istringstream is(llh[i]);
    std::string lat, lon, h;
    is >> lat >> lon >> h;
    csv += s.points[i].first + "," + lat + "," + lon + "," + h + "\n";
  }
  test::write_text(dir / "geo.csv", csv);
  const auto r =
      test::run_cli("project --calibration " + q(cal) + " --points " + q(dir / "geo.csv") + " --geodetic");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const CsvTable t = parse_csv(r.out, "stdout");
  ASSERT_EQ(t.records.size(), s.points.size());
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    // std::to_string kept 6 decimals of the ENU input (1 µm): its pixels are the truth here.
    const Eigen::Vector3d p(std::stod(std::to_string(s.points[i].second.x())),
                            std::stod(std::to_string(s.points[i].second.y())),
                            std::stod(std::to_string(s.points[i].second.z())));
    Eigen::Vector2d uv;
    ASSERT_TRUE(project(s.cameras[0], p, &uv));
    EXPECT_EQ(t.text(t.records[i], 0), s.points[i].first);
    // CartConvert prints 9 decimals of metres and 14 of degrees: ~1e-9 m, ≪ 1e-5 px at 64 m.
    EXPECT_NEAR(t.number(t.records[i], 1), uv.x(), 1e-5) << s.points[i].first;
    EXPECT_NEAR(t.number(t.records[i], 2), uv.y(), 1e-5) << s.points[i].first;
  }
  // A swapped lat/lon puts the point thousands of km away: refused with its line.
  test::write_text(dir / "swapped.csv", "id,lat,lon,h\nP1," + std::to_string(kOrigin.lon_deg) + "," +
                                            std::to_string(kOrigin.lat_deg) + ",60\n");
  const auto sw = test::run_cli("project --calibration " + q(cal) + " --points " + q(dir / "swapped.csv") +
                                " --geodetic");
  EXPECT_EQ(sw.exit_code, 3);
  EXPECT_NE(sw.err.find("swapped.csv:2"), std::string::npos) << sw.err;
}

TEST(GeodeticCli, IntersectGivesLatLonHAgreeingWithCartConvert) {
  if (!std::filesystem::exists(kCartConvert)) GTEST_SKIP() << "see CartConvertIsInstalled";
  const auto dir = test::scratch_dir("geodetic_intersect");
  const Scene s = scene();
  std::string args = "intersect --geodetic";
  for (const Camera& c : s.cameras) {
    std::string picks = "id,u,v\n";
    for (const auto& [id, p] : s.points) {
      Eigen::Vector2d uv;
      ASSERT_TRUE(project(c, p, &uv));
      ASSERT_TRUE(inside_image(c.intr, uv)) << id;
      char buf[96];
      std::snprintf(buf, sizeof buf, ",%.9f,%.9f\n", uv.x(), uv.y());
      picks += id + buf;
    }
    test::write_text(dir / (c.id + "_picks.csv"), picks);
    args += " --calibration " + q(write_calibration(dir, c, kOrigin)) + " --observations " +
            q(dir / (c.id + "_picks.csv"));
  }
  const auto r = test::run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const CsvTable t = parse_csv(r.out, "stdout");
  ASSERT_EQ(t.header, (std::vector<std::string>{"id", "lat", "lon", "h", "rms_px"}));
  ASSERT_EQ(t.records.size(), s.points.size());
  std::string enu;
  char buf[128];
  for (const auto& [id, p] : s.points) {
    std::snprintf(buf, sizeof buf, "%.9f %.9f %.9f\n", p.x(), p.y(), p.z());
    enu += buf;
  }
  const auto llh = cart_convert("-r " + origin_options(), enu, dir);
  ASSERT_EQ(llh.size(), s.points.size());
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    std::istringstream is(llh[i]);
    double lat, lon, h;
    is >> lat >> lon >> h;
    EXPECT_EQ(t.text(t.records[i], 0), s.points[i].first);
    // 1e-9° is 0.1 mm of latitude; the exact picks triangulate to well under that.
    EXPECT_NEAR(t.number(t.records[i], 1), lat, 2e-9) << s.points[i].first;
    EXPECT_NEAR(t.number(t.records[i], 2), lon, 3e-9) << s.points[i].first;
    EXPECT_NEAR(t.number(t.records[i], 3), h, 2e-4) << s.points[i].first;
  }
}

TEST(GeodeticCli, OldFilesWithoutTheOriginRefuseGeodeticOnly) {
  const auto dir = test::scratch_dir("geodetic_old");
  const Scene s = scene();
  const auto cal = write_calibration(dir, s.cameras[0], std::nullopt);
  test::write_text(dir / "enu.csv", "id,E,N,U\nP1,0,0,4\n");
  test::write_text(dir / "geo.csv", "id,lat,lon,h\nP1,53.27,-9.05,64\n");
  EXPECT_EQ(test::run_cli("project --calibration " + q(cal) + " --points " + q(dir / "enu.csv")).exit_code,
            0);
  const auto r =
      test::run_cli("project --calibration " + q(cal) + " --points " + q(dir / "geo.csv") + " --geodetic");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("world_frame"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("geodetic coordinates are unavailable"), std::string::npos) << r.err;
}

TEST(GeodeticCli, CamerasInDifferentFramesAreNotTriangulatedTogether) {
  const auto dir = test::scratch_dir("geodetic_mixed");
  const Scene s = scene();
  GeodeticOrigin other = kOrigin;
  other.lat_deg += 0.01;
  test::write_text(dir / "a.csv", "id,u,v\nP1,640,400\n");
  test::write_text(dir / "b.csv", "id,u,v\nP1,640,400\n");
  const auto r =
      test::run_cli("intersect --calibration " + q(write_calibration(dir, s.cameras[0], kOrigin)) +
                    " --observations " + q(dir / "a.csv") + " --calibration " +
                    q(write_calibration(dir, s.cameras[1], other)) + " --observations " + q(dir / "b.csv"));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("different ENU frames"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace rangecal
