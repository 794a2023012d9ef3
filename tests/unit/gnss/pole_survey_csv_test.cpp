#include "gnss/formats/pole_survey_csv.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "config/error.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

// Independent truth: GeographicLib's CartConvert tool (geographiclib-tools).
Eigen::Vector3d cartconvert_enu(const GeodeticOrigin& o, double lat, double lon, double h) {
  char cmd[512];
  std::snprintf(cmd, sizeof cmd, "echo '%.10f %.10f %.5f' | CartConvert -p 9 -l %.10f %.10f %.5f", lat, lon,
                h, o.lat_deg, o.lon_deg, o.h_m);
  FILE* p = popen(cmd, "r");
  Eigen::Vector3d e = Eigen::Vector3d::Constant(std::nan(""));
  if (p) {
    if (std::fscanf(p, "%lf %lf %lf", &e.x(), &e.y(), &e.z()) != 3) e.setConstant(std::nan(""));
    pclose(p);
  }
  return e;
}

TEST(PoleSurvey, GeodeticRowsMatchCartConvert) {
  const GeodeticOrigin o{45.6, 122.8, 150.0};
  const auto dir = test::scratch_dir("poles_geo");
  test::write_text(
      dir / "poles.csv",
      "id,role,lat,lon,h\nA1,check,45.6003,122.8004,151.25\nB1,control,45.5998,122.7991,149.5\n");
  const auto poles = read_pole_survey((dir / "poles.csv").string(), o);
  ASSERT_EQ(poles.size(), 2u);
  EXPECT_EQ(poles[0].role, PoleRole::check);
  EXPECT_EQ(poles[1].role, PoleRole::control);
  const Eigen::Vector3d a = cartconvert_enu(o, 45.6003, 122.8004, 151.25);
  const Eigen::Vector3d b = cartconvert_enu(o, 45.5998, 122.7991, 149.5);
  ASSERT_TRUE(a.allFinite()) << "CartConvert not available";
  EXPECT_LT((poles[0].enu - a).norm(), 1e-4);
  EXPECT_LT((poles[1].enu - b).norm(), 1e-4);
}

TEST(PoleSurvey, EnuRowsAreTakenAsGiven) {
  const auto dir = test::scratch_dir("poles_enu");
  test::write_text(dir / "poles.csv", "id,role,E,N,U\nA1,check,10.5,-3.25,2.0\n");
  const auto poles = read_pole_survey((dir / "poles.csv").string(), GeodeticOrigin{});
  ASSERT_EQ(poles.size(), 1u);
  EXPECT_EQ(poles[0].enu, Eigen::Vector3d(10.5, -3.25, 2.0));
}

TEST(PoleSurvey, BadRowsNameLineAndField) {
  const auto dir = test::scratch_dir("poles_bad");
  struct Case {
    std::string text, field;
    long line;
  } cases[] = {
      {"id,role,E,N,U\nA1,chek,1,2,3\n", "role", 2},
      {"id,role,E,N,U\nA1,check,1,2,3\nA1,check,1,2,3\n", "id", 3},
      {"id,role,E,N,U\nA1,check,1,x,3\n", "N", 2},
      {"id,role,lat,lon,h\nA1,check,91,2,3\n", "lat", 2},
      {"id,role,X,Y,Z\nA1,check,1,2,3\n", "", 1},
  };
  for (const auto& c : cases) {
    test::write_text(dir / "p.csv", c.text);
    try {
      read_pole_survey((dir / "p.csv").string(), GeodeticOrigin{});
      ADD_FAILURE() << c.text;
    } catch (const Error& e) {
      EXPECT_EQ(e.line(), c.line) << e.what();
      EXPECT_EQ(e.field(), c.field) << e.what();
      EXPECT_EQ(e.exit_code(), 3);
    }
  }
  test::write_text(dir / "empty.csv", "id,role,E,N,U\n");
  EXPECT_THROW(read_pole_survey((dir / "empty.csv").string(), GeodeticOrigin{}), Error);
}

TEST(PolePicks, ReadsAndRejectsDuplicates) {
  const auto dir = test::scratch_dir("picks");
  test::write_text(dir / "px.csv", "id,u,v\nA1,640.25,399.5\nA2,100,700\n");
  const auto picks = read_pole_picks((dir / "px.csv").string(), {});
  ASSERT_EQ(picks.size(), 2u);
  EXPECT_EQ(picks[0].uv, Eigen::Vector2d(640.25, 399.5));
  test::write_text(dir / "dup.csv", "id,u,v\nA1,640.25,399.5\nA1,100,700\n");
  try {
    read_pole_picks((dir / "dup.csv").string(), {});
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "id");
  }
}

}  // namespace
}  // namespace rangecal
