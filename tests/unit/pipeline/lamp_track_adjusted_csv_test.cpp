// gnss/lamp_track_adjusted.csv (pipeline/io/lamp_track_adjusted_csv.hpp): a hand-written file reads
// back to its numbers, the writer's text reads back to the network result it came from (σ the
// root of the covariance's diagonal, unused points left out), and every malformed line is an input
// error naming the file, the line and the field.
#include "pipeline/io/lamp_track_adjusted_csv.hpp"

#include <gtest/gtest.h>

#include "config/error.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

const std::string kHeader = "utc,E,N,U,sdE,sdN,sdU,dE,dN,dU,flag\n";

TEST(LampTrackAdjustedCsv, AHandWrittenFileReadsBackToItsNumbers) {
  const auto dir = test::scratch_dir("lamp_track_adjusted_good");
  const auto path = dir / "lamp_track_adjusted.csv";
  test::write_text(path, kHeader +
                             "2025-06-01T03:00:00.100000000Z,0.5000,64.0000,2.0000,0.0021,0.0032,0.0043,"
                             "0.0012,-0.0034,0.0056,0\n"
                             "# a comment line is skipped\n"
                             "2025-06-01T03:00:00.300000000Z,0.5100,64.0200,2.5000,0.0500,0.0600,0.0700,"
                             "-0.2000,0.0000,0.1500,1\n");
  const std::vector<LampTrackAdjustedRow> rows = read_lamp_track_adjusted_csv(path.string());
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].utc, *parse_iso8601_utc("2025-06-01T03:00:00.1Z"));
  EXPECT_EQ(rows[1].utc.ns - rows[0].utc.ns, 200'000'000);
  EXPECT_EQ(rows[0].enu, Eigen::Vector3d(0.5, 64.0, 2.0));
  EXPECT_EQ(rows[0].sd_enu, Eigen::Vector3d(0.0021, 0.0032, 0.0043));
  EXPECT_EQ(rows[0].correction, Eigen::Vector3d(0.0012, -0.0034, 0.0056));
  EXPECT_FALSE(rows[0].flagged);
  EXPECT_EQ(rows[0].line, 2);
  EXPECT_EQ(rows[1].correction, Eigen::Vector3d(-0.2, 0.0, 0.15));
  EXPECT_EQ(rows[1].sd_enu.z(), 0.07);
  EXPECT_TRUE(rows[1].flagged);
  EXPECT_EQ(rows[1].line, 4);
  // A network that used no epoch writes the header alone: no rows, not an error.
  EXPECT_TRUE(parse_lamp_track_adjusted_csv(kHeader, "empty.csv").empty());
}

TEST(LampTrackAdjustedCsv, TheWritersTextReadsBackToTheNetworkResult) {
  LampTrack track;
  for (int i = 0; i < 4; ++i) {
    LampEpoch e;
    e.utc = UtcTime{1'748'746'800'000'000'000 + i * 100'000'000LL};
    track.epochs.push_back(e);
  }
  NetworkResult r;
  r.points.resize(4);
  // Points 0..2 are epochs 2, 0, 3 (not in time order); point 3 a pole; epoch 3's point unused.
  const std::vector<long> epoch_of_point = {2, 0, 3, -1};
  for (std::size_t k = 0; k < 4; ++k) {
    NetworkPointResult& p = r.points[k];
    p.used = k != 2;
    p.enu = Eigen::Vector3d(1.0 + k, 60.0 - k, 3.0 + 0.5 * k);
    p.cov = Eigen::Vector3d(4e-6, 9e-6, 1.6e-5 * (k + 1)).asDiagonal();
    p.cov(0, 1) = p.cov(1, 0) = 1e-6;  // off-diagonal terms do not enter the σ
    p.correction = Eigen::Vector3d(0.001 * (k + 1), -0.002, 0.0035);
    p.ppk_outlier = k == 0;
  }
  const std::vector<LampTrackAdjustedRow> rows =
      parse_lamp_track_adjusted_csv(format_lamp_track_adjusted_csv(track, r, epoch_of_point), "x.csv");
  ASSERT_EQ(rows.size(), 2u);  // epochs 0 and 2 in time order
  const std::size_t point_of_row[2] = {1, 0};
  const std::size_t epoch_of_row[2] = {0, 2};
  for (std::size_t i = 0; i < 2; ++i) {
    const NetworkPointResult& p = r.points[point_of_row[i]];
    EXPECT_EQ(rows[i].utc, track.epochs[epoch_of_row[i]].utc);
    EXPECT_LT((rows[i].enu - p.enu).cwiseAbs().maxCoeff(), 0.5e-4 + 1e-12);
    EXPECT_LT((rows[i].correction - p.correction).cwiseAbs().maxCoeff(), 0.5e-4 + 1e-12);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(rows[i].sd_enu[a], std::sqrt(p.cov(a, a)), 0.5e-4 + 1e-12);
    EXPECT_EQ(rows[i].flagged, p.ppk_outlier);
  }
  EXPECT_NEAR(rows[1].sd_enu.z(), 0.004, 1e-12);  // √1.6e-5
}

TEST(LampTrackAdjustedCsv, MalformedLinesNameFileLineAndField) {
  const auto dir = test::scratch_dir("lamp_track_adjusted_bad");
  const std::string good = "2025-06-01T03:00:00Z,1,2,3,0.01,0.01,0.02,0.001,0.002,0.003,0\n";
  struct Case {
    std::string body, field;
    long line;
  } cases[] = {
      {good + "2025-06-01T03:00:01Z,1,2,3,0.01,0.01,0.02,0.001,zero,0.003,0\n", "dN", 3},
      {good + "2025-06-01T03:00:01Z,1,2,3,0.01,-0.01,0.02,0.001,0.002,0.003,0\n", "sdN", 3},
      {good + "2025-06-01T03:00:01Z,1,2,3,0.01,0.01,0.02,0.001,0.002,0.003,yes\n", "flag", 3},
      {good + "2025-06-01T03:00:00Z,1,2,3,0.01,0.01,0.02,0.001,0.002,0.003,0\n", "utc", 3},
      {good + "2025-06-01 03:00:01,1,2,3,0.01,0.01,0.02,0.001,0.002,0.003,0\n", "utc", 3},
      {"2025-06-01T03:00:00Z,1,2,inf,0.01,0.01,0.02,0.001,0.002,0.003,0\n", "U", 2},
  };
  const auto path = dir / "lamp_track_adjusted.csv";
  for (const auto& c : cases) {
    test::write_text(path, kHeader + c.body);
    try {
      read_lamp_track_adjusted_csv(path.string());
      ADD_FAILURE() << "no error for " << c.body;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::input);
      EXPECT_EQ(e.exit_code(), 3);
      EXPECT_EQ(e.file(), path.string());
      EXPECT_EQ(e.line(), c.line) << e.what();
      EXPECT_EQ(e.field(), c.field) << e.what();
      EXPECT_NE(std::string(e.what()).find("lamp_track_adjusted.csv:" + std::to_string(c.line)),
                std::string::npos)
          << e.what();
    }
  }
  // A missing column is named, on the header line.
  test::write_text(
      path, "utc,E,N,U,sdE,sdN,sdU,dE,dN,flag\n2025-06-01T03:00:00Z,1,2,3,0.01,0.01,0.02,0.001,0.002,0\n");
  try {
    read_lamp_track_adjusted_csv(path.string());
    ADD_FAILURE() << "no error for a missing dU column";
  } catch (const Error& e) {
    EXPECT_EQ(e.line(), 1);
    EXPECT_NE(std::string(e.what()).find("dU"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_lamp_track_adjusted_csv((dir / "missing.csv").string()), Error);
}

}  // namespace
}  // namespace rangecal
