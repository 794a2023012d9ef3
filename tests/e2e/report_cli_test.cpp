// `rangecal report MISSION.json` (docs/cli.md): on an output folder built from synthetic data with
// the project's own writers (tests/support/report_output.hpp, the folder the report's unit tests
// read), the command writes report.html for that mission and records its stage in run.json.
#include <gtest/gtest.h>

#include "support/paths.hpp"
#include "support/report_output.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;

TEST(Report, CliCommandWritesTheReport) {
  const fs::path dir = test::scratch_dir("report_cli");
  test::write_report_output(dir);
  test::write_text(dir / "gnss/rover.pos", "% not read by the report stage\n");
  test::write_text(dir / "mission.json", R"({
    "mission": "cli report",
    "site": {"origin": {"lat": 45.6, "lon": 122.8, "h": 150.0}},
    "gnss": {"pos_files": ["gnss/rover.pos"]},
    "lever_arm": {"vertical_m": 0.25},
    "cameras": [{"id": "cam1", "sensor": {"width_px": 1280, "height_px": 800, "pixel_size_um": [20, 20]},
                 "lens": {"nominal_focal_mm": 135}},
                {"id": "cam2", "sensor": {"width_px": 1280, "height_px": 800, "pixel_size_um": [20, 20]},
                 "lens": {"nominal_focal_mm": 135}}],
    "output_dir": "out"
  })");
  const test::CliResult r = test::run_cli("report '" + (dir / "mission.json").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(test::read_text(dir / "out/report.html").find("cli report"), std::string::npos);
  EXPECT_TRUE(test::read_json(dir / "out/run.json")["stages"].contains("report"));
}

}  // namespace
}  // namespace rangecal
