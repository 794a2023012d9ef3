// `rangecal inspect`'s facts (pipeline/steps/file_inspection.hpp), one test per kind: the real
// files of tests/data/external (.pos, .ulg, .cine, .mraw + .cihx) against what their SOURCE.md
// states and against an independent reading written here (Q counted per .pos line, the .cine's
// TIME64 block decoded from its bytes, the Photron clock from the header text); the kinds without a
// real sample (.bin, the CSVs, video, image) on small files written by the test with known content.
#include "pipeline/steps/file_inspection.hpp"

#include <gtest/gtest.h>
#include <algorithm>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <regex>
#include <sstream>

#include "config/error.hpp"
#include "support/dataflash_writer.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;

std::uint64_t count(const FileFacts& f, const std::string& what) {
  for (const auto& [w, n] : f.counts)
    if (w == what) return n;
  ADD_FAILURE() << f.path << " has no count '" << what << "'";
  return 0;
}
std::string detail(const FileFacts& f, const std::string& label) {
  for (const auto& [l, v] : f.details)
    if (l == label) return v;
  ADD_FAILURE() << f.path << " has no detail '" << label << "'";
  return "";
}

// ---- RTKLIB .pos ------------------------------------------------------------------------------

struct PosTruth {
  std::map<int, std::uint64_t> by_q;
  std::uint64_t epochs = 0;
};

// Q counted from the text: the token before ns, then 6 sd terms, age and ratio (and 9 velocity
// columns when the column header has them) — counted from the end of each data line.
PosTruth count_pos_lines(const fs::path& p) {
  std::ifstream in(p);
  PosTruth t;
  bool velocity = false;
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    if (line[0] == '%') {
      velocity = velocity || line.find("vn(m/s)") != std::string::npos;
      continue;
    }
    std::istringstream ls(line);
    std::vector<std::string> tok;
    for (std::string s; ls >> s;) tok.push_back(s);
    const std::size_t from_end = velocity ? 19 : 10;
    ++t.by_q[std::stoi(tok.at(tok.size() - from_end))];
    ++t.epochs;
  }
  return t;
}

// First and last data line of the UTC file, read as calendar UTC text.
UtcSpan utc_file_span() {
  std::ifstream in(test::external("gnss/pos/rover20181009_kin_llh_utc.pos"));
  std::vector<std::string> data;
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '%') data.push_back(line);
  const auto parse = [](const std::string& l) {
    int y, mo, d, h, mi, s, ms;
    EXPECT_EQ(std::sscanf(l.c_str(), "%d/%d/%d %d:%d:%d.%d", &y, &mo, &d, &h, &mi, &s, &ms), 7) << l;
    return utc_from_civil(y, mo, d, h, mi, s, ms * 1'000'000LL);
  };
  return UtcSpan{parse(data.front()), parse(data.back())};
}

TEST(InspectPos, EveryRealVariantGivesItsEpochsByQTimeSystemAndSpan) {
  const UtcSpan truth = utc_file_span();
  // SOURCE.md: 12:22:11.000 GPST → 12:21:53.000 UTC.
  EXPECT_EQ(truth.first, utc_from_civil(2018, 10, 9, 12, 21, 53, 0));
  for (const auto& entry : fs::directory_iterator(test::external("gnss/pos"))) {
    const std::string path = entry.path().string();
    SCOPED_TRACE(path);
    EXPECT_EQ(input_file_kind(path), InputFileKind::rtklib_pos);
    const FileFacts f = inspect_input_file(path);
    const PosTruth t = count_pos_lines(entry.path());
    EXPECT_EQ(f.kind, "RTKLIB .pos");
    EXPECT_EQ(f.size_bytes, fs::file_size(entry.path()));
    EXPECT_EQ(count(f, "epochs"), t.epochs);
    for (const auto& [q, n] : t.by_q) {
      const char* name = q == 1 ? " (fix)" : q == 2 ? " (float)" : q == 5 ? " (single)" : " (?)";
      EXPECT_EQ(count(f, "epochs Q=" + std::to_string(q) + name), n) << "Q=" << q;
    }
    ASSERT_TRUE(f.rate_hz.has_value());
    EXPECT_DOUBLE_EQ(*f.rate_hz, 1.0);
    ASSERT_TRUE(f.utc.has_value());
    EXPECT_FALSE(f.width_px.has_value());
    const std::string name = entry.path().filename().string();
    if (name.find("single") != std::string::npos) {
      EXPECT_EQ(t.epochs, 121u);
      EXPECT_EQ(t.by_q.at(5), 121u);  // SOURCE.md: all Q=5
      EXPECT_EQ(detail(f, "ref pos"), "none");
      // -ts 12:30:00 -te 12:32:00 GPST → 12:29:42 … 12:31:42 UTC.
      EXPECT_EQ(f.utc->first, utc_from_civil(2018, 10, 9, 12, 29, 42, 0));
      EXPECT_EQ(f.utc->last, utc_from_civil(2018, 10, 9, 12, 31, 42, 0));
      continue;
    }
    // SOURCE.md §5: 1878 epochs, Q=1: 444, Q=2: 1434; 14 gaps of 2–24 s.
    EXPECT_EQ(t.epochs, 1878u);
    EXPECT_EQ(t.by_q.at(1), 444u);
    EXPECT_EQ(t.by_q.at(2), 1434u);
    EXPECT_EQ(count(f, "gaps > 1.5 intervals"), 14u);
    EXPECT_EQ(f.utc->first, truth.first);
    EXPECT_EQ(f.utc->last, truth.last);
    EXPECT_EQ(detail(f, "ref pos"), "yes");
    EXPECT_EQ(detail(f, "velocity columns"), name.find("vel") != std::string::npos ? "yes" : "no");
    const std::string system = name.find("_utc") != std::string::npos   ? "UTC ("
                               : name.find("_jst") != std::string::npos ? "JST ("
                                                                        : "GPST (";
    EXPECT_EQ(f.time_system.rfind(system, 0), 0u) << f.time_system;
    if (system == "GPST (") {
      EXPECT_NE(f.time_system.find("GPST - 18 s"), std::string::npos) << f.time_system;
    }
    EXPECT_NE(detail(f, "obs start").find("(week2022 217331.0s)"), std::string::npos);
    EXPECT_EQ(f.notes.size(), 1u);  // most epochs are float
  }
}

// ---- PX4 ULog ---------------------------------------------------------------------------------

TEST(InspectUlog, RealLogsGiveTheirTopicsAndAttitudeOnUtc) {
  const FileFacts f = inspect_input_file(test::external("px4-ulog/sample_log_small.ulg").string());
  EXPECT_EQ(f.kind, "PX4 ULog");
  EXPECT_EQ(f.size_bytes, 921631u);
  // SOURCE.md: 1,298 vehicle_attitude and 32 vehicle_gps_position messages, flown 2021-04-21 UTC.
  EXPECT_EQ(count(f, "messages vehicle_attitude"), 1298u);
  EXPECT_EQ(count(f, "messages vehicle_gps_position"), 32u);
  EXPECT_EQ(count(f, "attitude samples (vehicle_attitude)"), 1298u);
  EXPECT_EQ(count(f, "GNSS messages (vehicle_gps_position)"), 32u);
  ASSERT_TRUE(f.utc.has_value());
  EXPECT_EQ(format_iso8601_utc(f.utc->first, 0).substr(0, 10), "2021-04-21");
  EXPECT_EQ(format_iso8601_utc(f.utc->last, 0).substr(0, 10), "2021-04-21");
  EXPECT_NE(f.time_system.find("vehicle_gps_position"), std::string::npos);
  ASSERT_TRUE(f.rate_hz.has_value());
  EXPECT_GT(*f.rate_hz, 0);

  const FileFacts e = inspect_input_file(test::external("px4-ulog/sample_px4_events.ulg").string());
  // SOURCE.md: 622 attitude and 583 GPS messages, some without a fix.
  EXPECT_EQ(count(e, "messages vehicle_attitude"), 622u);
  EXPECT_EQ(count(e, "messages vehicle_gps_position"), 583u);
  EXPECT_EQ(count(e, "GNSS messages (vehicle_gps_position)"), 583u);
  EXPECT_GT(count(e, "GNSS messages without fix or time"), 0u);
  ASSERT_TRUE(e.utc.has_value());
}

// ---- ArduPilot DataFlash (no real sample: built from the published layout) --------------------

TEST(InspectDataflash, BuiltLogGivesMessagesPerTypeAndUtcFromGpsWeek) {
  // GPS week 2414 starts 2026-04-11 23:59:42 UTC (GPS − UTC = 18 s); boot 0 at 12,000,000 ms of week.
  const UtcTime week_start = utc_from_civil(2026, 4, 11, 23, 59, 42, 0);
  // inspect puts the log on UTC with ArduPilot's default receiver lag, 120 ms (docs/gnss.md "Receiver
  // lag"): each GPS stamp names the fix 120 ms before it.
  const auto utc_of_boot = [&](std::int64_t us) {
    return UtcTime{week_start.ns + 12'000'000'000'000LL + us * 1000 + 120'000'000};
  };
  test::DataflashWriter w;
  w.define_att_and_gps();
  for (int i = 0; i < 50; ++i) {
    const std::uint64_t t = 10'000'000 + 200'000ULL * static_cast<std::uint64_t>(i);
    w.gps(t, 3, 2414, static_cast<std::uint32_t>(12'000'000 + t / 1000));
  }
  for (int i = 0; i < 200; ++i) w.att(10'000'000 + 40'000ULL * static_cast<std::uint64_t>(i), 1, 2, 3);
  const fs::path p = test::scratch_dir("inspect_dataflash") / "flight.bin";
  test::write_text(p, w.bytes());
  EXPECT_EQ(input_file_kind(p.string()), InputFileKind::ardupilot_dataflash);
  const FileFacts f = inspect_input_file(p.string());
  EXPECT_EQ(f.kind, "ArduPilot DataFlash");
  EXPECT_EQ(f.size_bytes, w.bytes().size());
  EXPECT_EQ(count(f, "messages ATT"), 200u);
  EXPECT_EQ(count(f, "messages GPS"), 50u);
  EXPECT_EQ(count(f, "messages"), 250u + 3u);  // FMT of FMT, ATT and GPS
  ASSERT_TRUE(f.utc.has_value());
  EXPECT_EQ(f.utc->first, utc_of_boot(10'000'000));
  EXPECT_EQ(f.utc->last, utc_of_boot(10'000'000 + 40'000LL * 199));
  ASSERT_TRUE(f.rate_hz.has_value());
  EXPECT_NEAR(*f.rate_hz, 25.0, 1e-9);
  EXPECT_NE(f.time_system.find("18 leap seconds"), std::string::npos) << f.time_system;
}

// A log cut off mid-message is noted once, with the bytes left unread, whether or not its attitude
// could be put on UTC (the note came twice: once from the attitude, once from the file walk).
TEST(InspectDataflash, LogCutOffMidMessageIsNotedOnce) {
  test::DataflashWriter w;
  w.define_att_and_gps();
  for (int i = 0; i < 50; ++i) {
    const std::uint64_t t = 10'000'000 + 200'000ULL * static_cast<std::uint64_t>(i);
    w.gps(t, 3, 2414, static_cast<std::uint32_t>(12'000'000 + t / 1000));
    w.att(t, 1, 2, 3);
  }
  const std::string whole = w.bytes();
  w.att(30'000'000, 1, 2, 3);
  const std::size_t att_bytes = w.bytes().size() - whole.size();
  const std::string cut = w.bytes().substr(0, whole.size() + att_bytes - 7);  // 7 bytes short
  for (const bool with_gps : {true, false}) {  // without GPS the attitude cannot be put on UTC
    std::string bytes = cut;
    if (!with_gps) {
      test::DataflashWriter a;
      a.define_att_and_gps();
      for (int i = 0; i < 20; ++i) a.att(10'000'000 + 40'000ULL * static_cast<std::uint64_t>(i), 1, 2, 3);
      a.att(20'000'000, 1, 2, 3);
      bytes = a.bytes().substr(0, a.bytes().size() - 7);
    }
    const fs::path p = test::scratch_dir("inspect_dataflash_cut") / "cut.bin";
    test::write_text(p, bytes);
    const FileFacts f = inspect_input_file(p.string());
    const std::string note = std::to_string(att_bytes - 7) + " bytes of an incomplete last message not read";
    EXPECT_EQ(std::count(f.notes.begin(), f.notes.end(), note), 1) << "with GPS " << with_gps;
    EXPECT_EQ(f.notes.size(), with_gps ? 1u : 2u);  // without GPS: also "no attitude on UTC"
  }
}

// ---- Phantom .cine ----------------------------------------------------------------------------

std::uint64_t le(const std::string& b, std::size_t at, int n) {
  std::uint64_t v = 0;
  for (int i = n - 1; i >= 0; --i)
    v = (v << 8) | static_cast<unsigned char>(b.at(at + static_cast<std::size_t>(i)));
  return v;
}

TEST(InspectCine, RealFileGivesItsHeaderAndTheTime64OfItsFrame) {
  const fs::path p = test::external("phantom-cine/chart1.cine");
  const FileFacts f = inspect_input_file(p.string());
  EXPECT_EQ(f.kind, "Phantom .cine");
  EXPECT_EQ(f.size_bytes, 2775328u);
  // SOURCE.md: 2048 × 1080, 16 bits per pixel, ImageCount 1, TotalImageCount 176, FirstImageNo −123.
  EXPECT_EQ(f.width_px, 2048);
  EXPECT_EQ(f.height_px, 1080);
  EXPECT_EQ(f.stored_bits.value_or(*f.bits), 16);
  EXPECT_EQ(count(f, "frames"), 1u);
  EXPECT_EQ(count(f, "frames recorded (TotalImageCount)"), 176u);
  EXPECT_EQ(detail(f, "first image number"), "-123");
  // Independently: the tagged blocks after SETUP (OffSetup 0x54 + its Length), type 1002 holds one
  // TIME64 per frame: 32-bit fraction (lowest bit = IRIG) then 32-bit seconds since 1970.
  const std::string b = test::read_text(p);
  const std::size_t off_setup = le(b, 28, 4), off_offsets = le(b, 32, 4);
  std::size_t at = off_setup + le(b, off_setup + 142, 2);
  std::uint64_t raw = 0;
  bool found = false;
  while (at + 8 <= off_offsets && !found) {
    const std::uint64_t size = le(b, at, 4), type = le(b, at + 4, 2);
    if (type == 1002) raw = le(b, at + 8, 8), found = true;
    if (size == 0) break;
    at += size;
  }
  ASSERT_TRUE(found);
  const std::uint64_t fraction = raw & 0xFFFFFFFFu, seconds = raw >> 32;
  const double t = static_cast<double>(seconds) + static_cast<double>(fraction & ~1ull) / 4294967296.0;
  ASSERT_TRUE(f.utc.has_value());
  EXPECT_NEAR(static_cast<double>(f.utc->first.ns) * 1e-9, t, 1e-6);
  EXPECT_EQ(f.utc->first, f.utc->last);
  EXPECT_EQ(count(f, "frames IRIG-synchronised"), fraction & 1u);
  EXPECT_EQ(input_file_kind(p.string()), InputFileKind::phantom_cine);
}

// ---- Photron .mraw + .cihx --------------------------------------------------------------------

TEST(InspectPhotron, RealRecordingsGiveTheirHeaderValuesFromEitherFile) {
  // SOURCE.md: beam 1024 × 80, 16 bits stored with 12 effective, 4 frames, 50,000 fps, no IRIG.
  const FileFacts beam = inspect_input_file(test::external("photron-mraw/beam.mraw").string());
  EXPECT_EQ(beam.kind, "Photron .mraw");
  EXPECT_EQ(beam.size_bytes, 655360u);
  EXPECT_EQ(beam.width_px, 1024);
  EXPECT_EQ(beam.height_px, 80);
  EXPECT_EQ(beam.bits, 12);
  EXPECT_EQ(beam.stored_bits, 16);
  EXPECT_EQ(count(beam, "frames"), 4u);
  EXPECT_EQ(detail(beam, "record rate"), "50000 fps");
  EXPECT_EQ(detail(beam, "IRIG"), "no");
  EXPECT_FALSE(beam.utc.has_value());  // its header time "13:13" has no seconds

  // ball: 384 × 384, 12-bit packed, 15 frames, 30,000 fps, recorded 2023-01-18 11:56:13 (camera clock).
  for (const char* name : {"photron-mraw/ball_12bit.mraw", "photron-mraw/ball_12bit.cihx"}) {
    SCOPED_TRACE(name);
    EXPECT_EQ(input_file_kind(test::external(name).string()), InputFileKind::photron_mraw);
    const FileFacts f = inspect_input_file(test::external(name).string());
    EXPECT_EQ(f.path, test::external("photron-mraw/ball_12bit.mraw").string());
    EXPECT_EQ(f.size_bytes, 3317760u);
    EXPECT_EQ(f.width_px, 384);
    EXPECT_EQ(f.height_px, 384);
    EXPECT_EQ(f.bits, 12);
    EXPECT_FALSE(f.stored_bits.has_value());
    EXPECT_EQ(count(f, "frames"), 15u);
    ASSERT_TRUE(f.rate_hz.has_value());
    EXPECT_DOUBLE_EQ(*f.rate_hz, 30000.0);
    EXPECT_EQ(detail(f, "IRIG"), "no");
    // Frame k at the header clock + (startFrame + k) / rate, startFrame read from the text here.
    std::smatch m;
    const std::string cihx = test::read_text(test::external("photron-mraw/ball_12bit.cihx"));
    ASSERT_TRUE(std::regex_search(cihx, m, std::regex("<startFrame>(-?[0-9]+)</startFrame>")));
    const long start = std::stol(m[1]);
    const UtcTime clock = utc_from_civil(2023, 1, 18, 11, 56, 13, 0);
    ASSERT_TRUE(f.utc.has_value());
    EXPECT_EQ(f.utc->first, add_seconds(clock, static_cast<double>(start) / 30000.0));
    EXPECT_EQ(f.utc->last, add_seconds(clock, static_cast<double>(start + 14) / 30000.0));
    EXPECT_NE(f.time_system.find("camera clock"), std::string::npos);
  }
  // Given both files, one recording.
  EXPECT_EQ(distinct_recordings({test::external("photron-mraw/ball_12bit.mraw").string(),
                                 test::external("photron-mraw/ball_12bit.cihx").string(),
                                 test::external("photron-mraw/beam.cihx").string()})
                .size(),
            2u);
}

// ---- CSVs -------------------------------------------------------------------------------------

TEST(InspectCsv, TimestampsAttitudeLampTrackPolesAndPicksByTheirHeaders) {
  const fs::path d = test::scratch_dir("inspect_csv");
  std::string ts = "frame,file,utc\n";
  for (int i = 0; i < 40; ++i)
    ts += std::to_string(i) + ",f" + std::to_string(i % 4) + ".png,2026-05-14T02:30:" + (i < 10 ? "0" : "") +
          std::to_string(i) + ".000000000Z\n";
  test::write_text(d / "timestamps.csv", ts);
  test::write_text(d / "f0.png", "");  // only existence is counted
  const FileFacts t = inspect_input_file((d / "timestamps.csv").string());
  EXPECT_EQ(t.kind, "frame timestamps CSV");
  EXPECT_EQ(count(t, "frames"), 40u);
  EXPECT_EQ(count(t, "frame files"), 4u);
  EXPECT_EQ(count(t, "frame files missing"), 3u);
  EXPECT_EQ(t.utc->first, utc_from_civil(2026, 5, 14, 2, 30, 0, 0));
  EXPECT_EQ(t.utc->last, utc_from_civil(2026, 5, 14, 2, 30, 39, 0));
  EXPECT_DOUBLE_EQ(*t.rate_hz, 1.0);

  test::write_text(d / "att.csv",
                   "\xEF\xBB\xBF# attitude\nutc,roll_deg,pitch_deg,yaw_deg\n2026-05-14T02:30:00Z,1,2,3\n"
                   "2026-05-14T02:30:00.02Z,1,2,3\n2026-05-14T02:30:00.04Z,1,2,3\n");
  const FileFacts a = inspect_input_file((d / "att.csv").string());
  EXPECT_EQ(a.kind, "attitude CSV");
  EXPECT_EQ(count(a, "samples"), 3u);
  EXPECT_DOUBLE_EQ(*a.rate_hz, 50.0);
  EXPECT_DOUBLE_EQ(a.utc->duration_s(), 0.04);

  test::write_text(d / "lamp_track.csv",
                   "utc,E,N,U,sdE,sdN,sdU,quality\n"
                   "2026-05-14T02:30:00.000000000Z,0,0,1,0.01,0.01,0.02,1\n"
                   "2026-05-14T02:30:00.100000000Z,0,0,1,0.01,0.01,0.02,1\n"
                   "2026-05-14T02:30:00.200000000Z,0,0,1,0.01,0.01,0.02,2\n");
  const FileFacts l = inspect_input_file((d / "lamp_track.csv").string());
  EXPECT_EQ(l.kind, "lamp track CSV");
  EXPECT_EQ(count(l, "epochs"), 3u);
  EXPECT_EQ(count(l, "epochs Q=1 (fix)"), 2u);
  EXPECT_EQ(count(l, "epochs Q=2 (float)"), 1u);
  EXPECT_DOUBLE_EQ(*l.rate_hz, 10.0);

  test::write_text(d / "poles.csv",
                   "id,role,lat,lon,h\nP1,control,45.6,122.8,150\nP2,check,45.6001,122.8,151\n"
                   "P3,check,45.6,122.8001,150\n");
  const FileFacts p = inspect_input_file((d / "poles.csv").string());
  EXPECT_EQ(p.kind, "pole survey CSV");
  EXPECT_EQ(count(p, "poles"), 3u);
  EXPECT_EQ(count(p, "control poles"), 1u);
  EXPECT_EQ(count(p, "check poles"), 2u);
  EXPECT_FALSE(p.utc.has_value());

  test::write_text(d / "poles_px.csv", "id,u,v\nP1,10.5,20.25\nP2,30,40\n");
  const FileFacts k = inspect_input_file((d / "poles_px.csv").string());
  EXPECT_EQ(k.kind, "pole picks CSV");
  EXPECT_EQ(count(k, "picks"), 2u);
}

// ---- video and image --------------------------------------------------------------------------

TEST(InspectVideo, OpenCvReadableVideoGivesSizeFramesAndRate) {
  const fs::path p = test::scratch_dir("inspect_video") / "clip.avi";
  cv::VideoWriter w(p.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 25.0, cv::Size(64, 48), false);
  ASSERT_TRUE(w.isOpened());
  for (int i = 0; i < 12; ++i) w.write(cv::Mat(48, 64, CV_8UC1, cv::Scalar(i * 10)));
  w.release();
  EXPECT_EQ(input_file_kind(p.string()), InputFileKind::video);
  const FileFacts f = inspect_input_file(p.string());
  EXPECT_EQ(f.kind, "video");
  EXPECT_EQ(f.width_px, 64);
  EXPECT_EQ(f.height_px, 48);
  EXPECT_EQ(count(f, "frames"), 12u);
  ASSERT_TRUE(f.rate_hz.has_value());
  EXPECT_DOUBLE_EQ(*f.rate_hz, 25.0);
  EXPECT_EQ(detail(f, "codec (FourCC)"), "MJPG");
  EXPECT_FALSE(f.utc.has_value());

  const fs::path png = p.parent_path() / "frame.png";
  ASSERT_TRUE(cv::imwrite(png.string(), cv::Mat(30, 40, CV_16UC1, cv::Scalar(1000))));
  const FileFacts i = inspect_input_file(png.string());
  EXPECT_EQ(i.kind, "image");
  EXPECT_EQ(i.width_px, 40);
  EXPECT_EQ(i.height_px, 30);
  EXPECT_EQ(i.bits, 16);
}

// ---- files of no known kind -------------------------------------------------------------------

TEST(InspectBadInput, UnknownAndMissingFilesAreInputErrorsNamingTheFile) {
  const auto refused = [](const std::string& path, const std::string& why) {
    try {
      (void)inspect_input_file(path);
      ADD_FAILURE() << path << " was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.exit_code(), 3);
      EXPECT_EQ(e.file(), path);
      EXPECT_NE(e.reason().find(why), std::string::npos) << e.what();
    }
  };
  refused(test::external("gnss/SOURCE.md").string(), "no header rangecal knows");
  refused(test::external("gnss/rinex/base-20181009-1220.obs.gz").string(), "binary file");
  refused(test::external("gnss/oracle/oracle_enu_cartconvert.csv").string(), "no header rangecal knows");
  refused((test::scratch_dir("inspect_bad") / "missing.pos").string(), "no such file");
  const fs::path empty = test::scratch_dir("inspect_bad_empty") / "empty.pos";
  test::write_text(empty, "");
  refused(empty.string(), "empty");
  // A known kind whose content is broken: its reader's error, still on the file.
  const fs::path broken = test::scratch_dir("inspect_bad_pos") / "broken.pos";
  test::write_text(broken,
                   "% program : x\n%  GPST latitude(deg) longitude(deg) height(m) Q ns\n2018/10/09 x\n");
  try {
    (void)inspect_input_file(broken.string());
    ADD_FAILURE() << "broken .pos accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.exit_code(), 3);
    EXPECT_EQ(e.file(), broken.string());
  }
  // A Photron header without its .mraw.
  const fs::path lone = test::scratch_dir("inspect_bad_cihx") / "lone.cihx";
  test::write_text(lone, "x");
  refused(lone.string(), "no .mraw beside");
}

// ---- several files ----------------------------------------------------------------------------

TEST(InspectSpans, PairsOfTimedFilesAreCompared) {
  std::vector<FileFacts> files(3);
  const UtcTime t0 = utc_from_civil(2026, 5, 14, 2, 30, 0, 0);
  files[0].utc = UtcSpan{t0, add_seconds(t0, 600)};
  files[1].utc = UtcSpan{add_seconds(t0, 86400), add_seconds(t0, 86400 + 600)};
  files[2].utc = std::nullopt;  // a pole survey: no time
  const auto cmp = compare_file_spans(files);
  ASSERT_EQ(cmp.size(), 1u);
  EXPECT_EQ(cmp[0].a, 0u);
  EXPECT_EQ(cmp[0].b, 1u);
  EXPECT_EQ(cmp[0].comparison.relation, SpanRelation::clock_not_set);
}

}  // namespace
}  // namespace rangecal
