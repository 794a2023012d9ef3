#include "pipeline/io/correspondences_csv.hpp"

#include <gtest/gtest.h>

#include "config/error.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

TEST(CorrespondencesIo, RoundTripIsExactToPrintedPrecision) {
  std::vector<Correspondence> pairs(2);
  pairs[0].utc = *parse_iso8601_utc("2025-06-01T03:00:00.123456789Z");
  pairs[0].enu = {12.3456, -7.0001, 55.5};
  pairs[0].uv = {640.1234, 399.9876};
  pairs[0].sd_enu = Eigen::Vector3d(0.01, 0.01, 0.015);
  pairs[0].vel_enu = Eigen::Vector3d(0.25, -0.5, 2.5);
  pairs[1] = pairs[0];
  pairs[1].utc.ns += 100'000'000;
  pairs[1].residual_px = 0.25;
  pairs[1].used = false;
  const auto dir = test::scratch_dir("corr_rt");
  const std::string path = (dir / "c.csv").string();
  write_correspondences_csv(path, pairs);
  const auto back = read_correspondences_csv(path);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].utc, pairs[0].utc);
  EXPECT_NEAR((back[0].enu - pairs[0].enu).norm(), 0, 1e-9);
  EXPECT_NEAR((back[0].uv - pairs[0].uv).norm(), 0, 1e-9);
  EXPECT_FALSE(back[0].used.has_value());
  EXPECT_EQ(*back[1].used, false);
  EXPECT_DOUBLE_EQ(*back[1].residual_px, 0.25);
  ASSERT_TRUE(back[1].sd_enu);
  EXPECT_DOUBLE_EQ(back[1].sd_enu->z(), 0.015);
  ASSERT_TRUE(back[1].vel_enu);
  EXPECT_DOUBLE_EQ(back[1].vel_enu->z(), 2.5);
  EXPECT_NE(test::read_text(path).find(",sdE,sdN,sdU,vE,vN,vU\n"), std::string::npos);
  // Same pairs → same bytes.
  EXPECT_EQ(format_correspondences_csv(back), test::read_text(path));
}

// An imported track's own σ per label: written only when some pair has one, blank where a pair has
// none, read back; a σ of zero is refused naming its line and column.
TEST(CorrespondencesIo, PixelSigmaColumn) {
  std::vector<Correspondence> pairs(2);
  pairs[0].utc = *parse_iso8601_utc("2025-06-01T03:00:00Z");
  pairs[1].utc = *parse_iso8601_utc("2025-06-01T03:00:01Z");
  pairs[0].enu = pairs[1].enu = {1, 2, 3};
  EXPECT_EQ(format_correspondences_csv(pairs).find("pixel_sigma_px"), std::string::npos);
  pairs[1].pixel_sigma_px = 1.25;
  const std::string text = format_correspondences_csv(pairs);
  EXPECT_NE(text.find(",used,pixel_sigma_px\n"), std::string::npos) << text;
  const auto back = parse_correspondences_csv(text, "c.csv");
  EXPECT_FALSE(back[0].pixel_sigma_px);
  EXPECT_DOUBLE_EQ(*back[1].pixel_sigma_px, 1.25);
  try {
    parse_correspondences_csv("utc,E,N,U,u,v,pixel_sigma_px\n2025-06-01T03:00:00Z,1,2,3,4,5,0\n", "c.csv");
    FAIL() << "a zero σ was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.field(), "pixel_sigma_px");
  }
}

TEST(CorrespondencesIo, BadLinesNameFileLineAndField) {
  const auto dir = test::scratch_dir("corr_bad");
  const std::string header = "utc,E,N,U,u,v,residual_px,used\n";
  const std::string good = "2025-06-01T03:00:00Z,1,2,3,4,5,,\n";
  struct Case {
    std::string body, field;
    long line;
  } cases[] = {
      {good + "2025-06-01T03:00:01Z,1,2,x,4,5,,\n", "U", 3},
      {good + "2025-06-01T03:00:00Z,1,2,3,4,5,,\n", "utc", 3},
      {good + "2025-06-01 03:00:01,1,2,3,4,5,,\n", "utc", 3},
      {good + "2025-06-01T03:00:01Z,1,2,3,4,5,,2\n", "used", 3},
  };
  for (const auto& c : cases) {
    const auto path = dir / "c.csv";
    test::write_text(path, header + c.body);
    try {
      read_correspondences_csv(path.string());
      ADD_FAILURE() << "no error for " << c.body;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::input);
      EXPECT_EQ(e.line(), c.line) << e.what();
      EXPECT_EQ(e.field(), c.field) << e.what();
      EXPECT_NE(std::string(e.what()).find("c.csv"), std::string::npos);
    }
  }
  test::write_text(dir / "vel.csv",
                   "utc,E,N,U,u,v,residual_px,used,vE,vN\n2025-06-01T03:00:00Z,1,2,3,4,5,,,0,1\n");
  try {
    read_correspondences_csv((dir / "vel.csv").string());
    ADD_FAILURE() << "no error for an incomplete velocity set";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "vE");
    EXPECT_NE(std::string(e.what()).find("vE,vN,vU"), std::string::npos) << e.what();
  }
  test::write_text(dir / "short.csv", header + "2025-06-01T03:00:00Z,1,2,3\n");
  EXPECT_THROW(read_correspondences_csv((dir / "short.csv").string()), Error);
  EXPECT_THROW(read_correspondences_csv((dir / "missing.csv").string()), Error);
}

}  // namespace
}  // namespace rangecal
