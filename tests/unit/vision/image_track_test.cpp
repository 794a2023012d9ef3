// Imported 2-D tracks (vision/tracks/): the CSV and xypts readers against pixels written in the test
// in each file's own convention, the registry's choice by header, and every bad input naming its file,
// line and field.
#include <gtest/gtest.h>

#include "support/expect_error.hpp"
#include "support/paths.hpp"
#include "vision/tracks/track_csv.hpp"
#include "vision/tracks/track_formats.hpp"
#include "vision/tracks/track_frame_times.hpp"
#include "vision/tracks/xypts_csv.hpp"

namespace rangecal {
namespace {

TrackReadOptions image(int w = 1920, int h = 1080) {
  TrackReadOptions o;
  o.width_px = w;
  o.height_px = h;
  return o;
}

TEST(TrackCsv, ReadsLabelsBlanksAndSigma) {
  const ImageTrack t = parse_track_csv(
      "frame,u,v,sigma_px\n3,10.5,20.25,\n4,,,\n# a comment\n7,1919.4,0,0.8\n8,nan,NaN,\n", "t.csv", image());
  ASSERT_EQ(t.points.size(), 2u);
  EXPECT_EQ(t.points[0].frame, 3);
  EXPECT_DOUBLE_EQ(t.points[0].uv.x(), 10.5);
  EXPECT_DOUBLE_EQ(t.points[0].uv.y(), 20.25);
  EXPECT_FALSE(t.points[0].sigma_px);
  EXPECT_EQ(t.points[1].frame, 7);
  EXPECT_DOUBLE_EQ(*t.points[1].sigma_px, 0.8);
  EXPECT_EQ(t.points[1].line, 5);
  EXPECT_EQ(t.unlabelled_frames, 2u);
}

TEST(TrackCsv, LabelsOutsideTheImageAreListedNotUsed) {
  const ImageTrack t = parse_track_csv("frame,u,v\n1,1921.01,511\n2,100,100\n3,5,-0.6\n", "t.csv", image());
  ASSERT_EQ(t.points.size(), 1u);
  EXPECT_EQ(t.points[0].frame, 2);
  EXPECT_EQ(t.outside_image_lines, (std::vector<long>{2, 4}));
}

TEST(TrackCsv, BadInputNamesLineAndField) {
  Error e = test::expect_error([] { parse_track_csv("frame,u,v\n5,1,1\n5,2,2\n", "t.csv", image()); });
  EXPECT_EQ(e.exit_code(), 3);
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.field(), "frame");
  e = test::expect_error([] { parse_track_csv("frame,u,v\n1,3,\n", "t.csv", image()); });
  EXPECT_EQ(e.field(), "v");
  e = test::expect_error([] { parse_track_csv("frame,u,v\n1,abc,3\n", "t.csv", image()); });
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.field(), "u");
  e = test::expect_error([] { parse_track_csv("frame,u,v,sigma_px\n1,3,3,0\n", "t.csv", image()); });
  EXPECT_EQ(e.field(), "sigma_px");
  e = test::expect_error([] { parse_track_csv("frame,u\n1,3\n", "t.csv", image()); });
  EXPECT_EQ(e.exit_code(), 3);
}

// DLTdv / Argus: MATLAB pixels (first pixel's centre 1), Y up from the bottom row or down from the top.
TEST(XyptsCsv, MapsBothOriginsToRangecalPixels) {
  const std::string text =
      "pt1_cam1_X,pt1_cam1_Y,pt1_cam2_X,pt1_cam2_Y\nNaN,NaN,1,1\n101,51,NaN,NaN\n1920,1080,10,20\n";
  TrackReadOptions o = image();
  o.camera = 1;
  o.y_origin = TrackReadOptions::YOrigin::top;
  ImageTrack t = parse_xypts_csv(text, "x.csv", o);
  ASSERT_EQ(t.points.size(), 2u);
  EXPECT_EQ(t.points[0].frame, 2);  // data row 2
  EXPECT_DOUBLE_EQ(t.points[0].uv.x(), 100);
  EXPECT_DOUBLE_EQ(t.points[0].uv.y(), 50);
  EXPECT_DOUBLE_EQ(t.points[1].uv.x(), 1919);
  EXPECT_DOUBLE_EQ(t.points[1].uv.y(), 1079);
  o.y_origin = TrackReadOptions::YOrigin::bottom;
  t = parse_xypts_csv(text, "x.csv", o);
  EXPECT_DOUBLE_EQ(t.points[0].uv.y(), 1080 - 51);  // Y = 51 from the bottom: 50 rows above the last
  EXPECT_DOUBLE_EQ(t.points[1].uv.y(), 0);          // Y = 1080: the top row
  o.camera = 2;
  t = parse_xypts_csv(text, "x.csv", o);
  ASSERT_EQ(t.points.size(), 2u);
  EXPECT_EQ(t.points[0].frame, 1);
  EXPECT_DOUBLE_EQ(t.points[0].uv.x(), 0);
  EXPECT_DOUBLE_EQ(t.points[0].uv.y(), 1079);
  EXPECT_EQ(t.unlabelled_frames, 1u);
}

TEST(XyptsCsv, NeedsItsOriginAndItsColumns) {
  const std::string text = "pt1_cam1_X,pt1_cam1_Y\n1,1\n";
  Error e = test::expect_error([&] { parse_xypts_csv(text, "x.csv", image()); });
  EXPECT_EQ(e.exit_code(), 3);
  EXPECT_NE(std::string(e.what()).find("y_origin"), std::string::npos);
  TrackReadOptions o = image();
  o.y_origin = TrackReadOptions::YOrigin::top;
  o.point = 2;
  e = test::expect_error([&] { parse_xypts_csv(text, "x.csv", o); });
  EXPECT_EQ(e.field(), "pt2_cam1_X");
}

TEST(TrackFormats, ChosenByHeaderOrByName) {
  const auto dir = test::scratch_dir("image_track_formats");
  test::write_text(dir / "a.csv", "frame,u,v\n1,2,3\n");
  test::write_text(dir / "b.csv", "pt1_cam1_X,pt1_cam1_Y\n2,4\n");
  test::write_text(dir / "c.csv", "id,u,v\nP1,2,3\n");
  test::write_text(dir / "d.csv", "frame,u,v\n1,,\n");
  TrackReadOptions o = image();
  o.y_origin = TrackReadOptions::YOrigin::top;
  EXPECT_EQ(read_image_track((dir / "a.csv").string(), "", o).format, "csv");
  const ImageTrack b = read_image_track((dir / "b.csv").string(), "", o);
  EXPECT_EQ(b.format, "xypts");
  EXPECT_DOUBLE_EQ(b.points[0].uv.y(), 3);
  Error e = test::expect_error([&] { read_image_track((dir / "c.csv").string(), "", o); });
  EXPECT_EQ(e.line(), 1);
  EXPECT_NE(std::string(e.what()).find("not a 2-D track file"), std::string::npos);
  e = test::expect_error([&] { read_image_track((dir / "a.csv").string(), "dltdv9", o); });
  EXPECT_EQ(e.field(), "format");
  e = test::expect_error([&] { read_image_track((dir / "d.csv").string(), "", o); });
  EXPECT_NE(std::string(e.what()).find("no labelled frame"), std::string::npos);
}

TEST(TrackFrameTimes, FromCsvAndFromRate) {
  const ImageTrack t = parse_track_csv("frame,u,v\n1,2,3\n3,2,3\n", "t.csv", image());
  const std::vector<UtcTime> r = track_times_from_rate(t, UtcTime{1'000'000'000}, 1, 25.0);
  EXPECT_EQ(r[0].ns, 1'000'000'000);
  EXPECT_EQ(r[1].ns, 1'080'000'000);
  const auto dir = test::scratch_dir("image_track_times");
  test::write_text(dir / "ts.csv",
                   "frame,file,utc\n1,a.png,2026-05-04T10:00:00Z\n2,b.png,2026-05-04T10:00:00.04Z\n"
                   "3,c.png,2026-05-04T10:00:00.08Z\n");
  const std::vector<UtcTime> c = track_times_from_csv(t, (dir / "ts.csv").string());
  EXPECT_EQ(c[1].ns - c[0].ns, 80'000'000);
  test::write_text(dir / "short.csv", "frame,utc\n1,2026-05-04T10:00:00Z\n");
  Error e = test::expect_error([&] { track_times_from_csv(t, (dir / "short.csv").string()); });
  EXPECT_EQ(e.file(), "t.csv");
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.field(), "frame");
  test::write_text(dir / "back.csv", "frame,utc\n1,2026-05-04T10:00:01Z\n3,2026-05-04T10:00:00Z\n");
  e = test::expect_error([&] { track_times_from_csv(t, (dir / "back.csv").string()); });
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.field(), "utc");
}

}  // namespace
}  // namespace rangecal
