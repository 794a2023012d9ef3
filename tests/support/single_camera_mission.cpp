#include "support/single_camera_mission.hpp"

#include "gnss/time/utc_time.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "support/paths.hpp"

namespace rangecal::test {

void write_single_camera_mission(const std::filesystem::path& dir,
                                 const std::vector<PointCorrespondence>& pts, double sd_m,
                                 const std::string& calibrate_json, const std::string& mission) {
  std::vector<Correspondence> pairs;
  UtcTime t = *parse_iso8601_utc("2025-06-01T03:00:00Z");
  for (const auto& c : pts) {
    Correspondence k;
    k.utc = t;
    t.ns += 100'000'000;
    k.enu = c.world;
    k.uv = c.pixel;
    k.sd_enu = Eigen::Vector3d::Constant(sd_m);
    pairs.push_back(k);
  }
  write_correspondences_csv((dir / "out/cam1/correspondences.csv").string(), pairs);
  write_text(dir / "pos.pos", "");
  write_text(dir / "frames.csv", "frame,file,utc\n");
  write_text(dir / "mission.json", R"({
    "mission": ")" + mission + R"(", "site": {"origin": {"lat": 45.6, "lon": 122.8, "h": 150}},
    "gnss": {"pos_files": ["pos.pos"]}, "lever_arm": {"vertical_m": 0.25},
    "cameras": [{"id": "cam1", "frames": {"timestamps": "frames.csv"},
                 "sensor": {"width_px": 1280, "height_px": 800, "pixel_size_um": [20, 20]},
                 "lens": {"nominal_focal_mm": 135}}],
    "calibrate": )" + calibrate_json + R"(,
    "output_dir": "out"})");
}

}  // namespace rangecal::test
