// Photron recordings as a frame source: the same lamp detections (bit-identical centroids and
// statuses) from 16-bit PNGs and from .mraw files of the same frames; a .mraw named by a
// timestamps CSV and a .mraw alone timed by its header; the `mraw` key of the mission config; the
// time source in the align and detect stages' run.json counts; bad input naming file and field.
#include <gtest/gtest.h>

#include <functional>
#include <nlohmann/json.hpp>
#include <numeric>

#include "config/error.hpp"
#include "gnss/formats/lamp_track_csv.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/io/run_log.hpp"
#include "pipeline/stages/align_stage.hpp"
#include "pipeline/stages/detect_stage.hpp"
#include "pipeline/stages/gnss_stage.hpp"
#include "support/expect_error.hpp"
#include "support/paths.hpp"
#include "vision/detection/lamp_detector.hpp"
#include "vision/frames/frame_renderer.hpp"
#include "vision/frames/frame_source.hpp"
#include "vision/frames/photron_mraw_writer.hpp"

using namespace rangecal;
namespace fs = std::filesystem;

namespace {

constexpr int kW = 320, kH = 200;
// The header clock reads 12:30:05 on a camera clock 2 h ahead of UTC.
const UtcTime kTrigger = *parse_iso8601_utc("2026-05-01T10:30:05Z");
constexpr double kFps = 20;

FrameSourceOptions sensor(int w = kW, int h = kH) {
  FrameSourceOptions s;
  s.width_px = w;
  s.height_px = h;
  return s;
}

/// As sensor(), skipping missing or undecodable frames.
FrameSourceOptions lenient_sensor() {
  FrameSourceOptions s = sensor();
  s.allow_missing = true;
  return s;
}

using test::expect_error;

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

// Lamp truth of frame k (px).
double lamp_u(int k) {
  return 30.3 + 8.7 * k;
}
double lamp_v(int k) {
  return 20.6 + 5.3 * k;
}

// 12-bit frames (CV_16UC1) with a moving lamp, a static light, hot pixels and a sky gradient.
std::vector<cv::Mat> lamp_frames(int n) {
  FrameRenderSettings st;
  st.width = kW;
  st.height = kH;
  st.bits = 12;
  st.sky_level = 300;
  st.read_noise = 6;
  st.hot_pixels = random_hot_pixels(kW, kH, 5, 800, 2000, 11);
  st.static_lights = {{250.4, 150.2, 1.5, 900}};
  std::vector<cv::Mat> out;
  for (int k = 0; k < n; ++k) out.push_back(render_frame(st, {{lamp_u(k), lamp_v(k), 1.3, 1500}}, 300 + k));
  return out;
}

UtcTime frame_utc(int k) {
  return UtcTime{kTrigger.ns + static_cast<std::int64_t>(k * 1e9 / kFps + 0.5)};
}

PhotronWriteOptions mraw_options(int storage, EffectiveBitSide side = EffectiveBitSide::lower) {
  PhotronWriteOptions o;
  o.storage_bits = storage;
  o.effective_depth = 12;
  o.effective_side = side;
  o.record_rate_fps = kFps;
  o.date = "2026/5/1";
  o.time = "12:30:05";
  o.device_name = "FASTCAM Nova S16 type 1100K-M-64GB";
  return o;
}

// A mission config of one 320 × 200 camera "cam1", its `frames` still to be set.
nlohmann::json mission_json() {
  return nlohmann::json::parse(R"({
    "site": {"origin": {"lat": 45.6, "lon": 122.8, "h": 150.0}},
    "gnss": {"pos_files": ["gnss/rover.pos"]},
    "lever_arm": {"vertical_m": 0.25},
    "cameras": [{"id": "cam1", "sensor": {"width_px": 320, "height_px": 200, "pixel_size_um": [20, 20]},
                 "lens": {"nominal_focal_mm": 135}}]})");
}

// frame,file,utc naming `file(k)` for frame k.
std::string csv_text(int n, const std::function<std::string(int)>& file,
                     const std::function<int(int)>& frame) {
  std::string t = "frame,file,utc\n";
  for (int k = 0; k < n; ++k)
    t += std::to_string(frame(k)) + "," + file(k) + "," + format_iso8601_utc(frame_utc(k)) + "\n";
  return t;
}

void expect_same_detections(const std::vector<LampDetection>& a, const std::vector<LampDetection>& b,
                            const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].status, b[i].status) << what << " " << i;
    // Bit-identical: the same pixels through the same code.
    EXPECT_EQ(std::memcmp(&a[i].u, &b[i].u, sizeof(double)), 0) << what << " " << i;
    EXPECT_EQ(std::memcmp(&a[i].v, &b[i].v, sizeof(double)), 0) << what << " " << i;
    EXPECT_EQ(a[i].frame, b[i].frame);
    EXPECT_EQ(a[i].utc, b[i].utc) << what << " " << i;
  }
}

}  // namespace

TEST(PhotronFrameSource, SameDetectionsFromPngAndMraw) {
  const fs::path dir = test::scratch_dir("mraw_fs_same");
  const int n = 12;
  const auto frames = lamp_frames(n);
  for (int k = 0; k < n; ++k)
    write_frame_image((dir / ("f" + std::to_string(k) + ".png")).string(), frames[k]);
  test::write_text(dir / "png.csv",
                   csv_text(
                       n, [](int k) { return "f" + std::to_string(k) + ".png"; }, [](int k) { return k; }));
  write_photron_mraw((dir / "rec12.mraw").string(), frames, mraw_options(12));
  write_photron_mraw((dir / "rec16.mraw").string(), frames, mraw_options(16));
  write_photron_mraw((dir / "rec16h.mraw").string(), frames, mraw_options(16, EffectiveBitSide::higher));
  for (const std::string name : {"rec12", "rec16", "rec16h"})
    test::write_text(dir / (name + ".csv"),
                     csv_text(
                         n, [&](int) { return name + ".mraw"; }, [](int k) { return k; }));

  std::vector<std::size_t> all(n);
  std::iota(all.begin(), all.end(), 0);
  const LampDetectorOptions opt;
  const FrameSource png = FrameSource::from_timestamps_csv((dir / "png.csv").string(), sensor());
  EXPECT_EQ(png.time_source(), "timestamps CSV");
  const auto ref = detect_lamp(png, all, opt, 2);
  int usable = 0;
  double worst = 0;
  for (int k = 0; k < n; ++k) {
    if (!ref[k].usable()) continue;
    ++usable;
    worst = std::max({worst, std::abs(ref[k].u - lamp_u(k)), std::abs(ref[k].v - lamp_v(k))});
  }
  std::printf("[ figures  ] PNG reference: %d of %d frames usable, worst centroid error %.4f px\n", usable, n,
              worst);
  EXPECT_EQ(usable, n);
  EXPECT_LT(worst, 0.1);

  for (const std::string name : {"rec12", "rec16", "rec16h"}) {
    const FrameSource src = FrameSource::from_timestamps_csv((dir / (name + ".csv")).string(), sensor());
    EXPECT_EQ(src.time_source(), "timestamps CSV");
    for (int k : {0, 5, 11}) {
      const auto a = png.load(k), b = src.load(k);
      EXPECT_EQ(cv::norm(a->image, b->image, cv::NORM_INF), 0.0) << name << " " << k;
      EXPECT_EQ(b->bits, 12);
    }
    expect_same_detections(ref, detect_lamp(src, all, opt, 2), name);
    expect_same_detections(ref, detect_lamp(src, all, opt, 1), name + " one thread");
  }

  // A .mraw alone: times from its header (12:30:05 on a clock 2 h ahead of UTC, 20 fps).
  const FrameSource alone = FrameSource::from_mraw((dir / "rec12.mraw").string(), sensor(), 2.0);
  EXPECT_EQ(alone.time_source(), "mraw header + rate");
  ASSERT_EQ(alone.size(), static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) EXPECT_EQ(alone.entry(k).utc, frame_utc(k)) << k;
  expect_same_detections(ref, detect_lamp(alone, all, opt, 2), "rec12 alone");
  // Only the frames asked for, in the order asked.
  const auto some = detect_lamp(alone, {7, 2}, opt, 2);
  EXPECT_EQ(some[0].frame, 7);
  EXPECT_EQ(some[1].u, ref[2].u);
}

TEST(PhotronFrameSource, CsvNamingMrawErrors) {
  const fs::path dir = test::scratch_dir("mraw_fs_csv_bad");
  const auto frames = lamp_frames(3);
  write_photron_mraw((dir / "rec.mraw").string(), frames, mraw_options(12));
  const auto csv = [&](const std::string& name, const std::string& body) {
    test::write_text(dir / name, "frame,file,utc\n" + body);
    return (dir / name).string();
  };
  const std::string t0 = format_iso8601_utc(frame_utc(0)), t1 = format_iso8601_utc(frame_utc(1));
  // A frame index beyond the end of the .mraw: the CSV line and field.
  auto e = expect_error([&] {
    FrameSource::from_timestamps_csv(csv("beyond.csv", "0,rec.mraw," + t0 + "\n3,rec.mraw," + t1 + "\n"),
                                     sensor());
  });
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.field(), "frame");
  EXPECT_TRUE(contains(e.what(), "beyond.csv") && contains(e.what(), "3 frames")) << e.what();
  // A missing .mraw, or one without a header, at its CSV line.
  e = expect_error(
      [&] { FrameSource::from_timestamps_csv(csv("gone.csv", "0,gone.mraw," + t0 + "\n"), sensor()); });
  EXPECT_EQ(e.line(), 2);
  EXPECT_TRUE(contains(e.what(), "gone.csv") && contains(e.what(), "gone.mraw")) << e.what();
  test::write_text(dir / "bare.mraw", std::string(100, '\0'));
  e = expect_error(
      [&] { FrameSource::from_timestamps_csv(csv("bare.csv", "0,bare.mraw," + t0 + "\n"), sensor()); });
  EXPECT_TRUE(contains(e.what(), "bare.csv:2") && contains(e.what(), "bare.cihx")) << e.what();
  // With allow_missing the frames are skipped with the reason.
  const FrameSource lenient = FrameSource::from_timestamps_csv(
      csv("lenient.csv", "0,rec.mraw," + t0 + "\n1,bare.mraw," + t1 + "\n"), lenient_sensor());
  std::string why;
  EXPECT_TRUE(lenient.load(0).has_value());
  EXPECT_FALSE(lenient.load(1, &why).has_value());
  EXPECT_TRUE(contains(why, "bare.cihx")) << why;
  // Wrong sensor size: an error at load naming the frame's size and the sensor's.
  const FrameSource small =
      FrameSource::from_timestamps_csv(csv("ok.csv", "0,rec.mraw," + t0 + "\n"), sensor(640, 480));
  e = expect_error([&] { small.load(0); });
  EXPECT_TRUE(contains(e.what(), "320x200") && contains(e.what(), "640x480")) << e.what();
}

TEST(PhotronFrameSource, MrawAloneNeedsAUsableHeaderClockAndTheOffset) {
  const fs::path dir = test::scratch_dir("mraw_fs_alone_bad");
  const auto frames = lamp_frames(2);
  const std::string mraw = (dir / "rec.mraw").string();
  write_photron_mraw(mraw, frames, mraw_options(12));
  // No offset: refused, pointing to the config key and the timestamps CSV.
  auto e = expect_error([&] { FrameSource::from_mraw(mraw, sensor(), std::nullopt); });
  EXPECT_EQ(e.kind(), ErrorKind::input);
  EXPECT_EQ(e.field(), "fileInfo/time");
  EXPECT_TRUE(contains(e.what(), "clock_utc_offset_h") && contains(e.what(), "frames.timestamps"))
      << e.what();
  // A header without seconds or without a rate: refused naming the field.
  PhotronWriteOptions o = mraw_options(12);
  o.time = "12:30";
  write_photron_mraw(mraw, frames, o);
  e = expect_error([&] { FrameSource::from_mraw(mraw, sensor(), 0.0); });
  EXPECT_EQ(e.field(), "fileInfo/time");
  EXPECT_TRUE(contains(e.what(), "no seconds") && contains(e.what(), "rec.cihx")) << e.what();
  o = mraw_options(12);
  o.record_rate_fps = 0;
  write_photron_mraw(mraw, frames, o);
  e = expect_error([&] { FrameSource::from_mraw(mraw, sensor(), 0.0); });
  EXPECT_EQ(e.field(), "recordInfo/recordRate");
  // The real beam sample writes its time without seconds.
  e = expect_error([&] {
    FrameSource::from_mraw(test::external("photron-mraw/beam.mraw").string(), sensor(1024, 80), 0.0);
  });
  EXPECT_EQ(e.field(), "fileInfo/time");
  // The real ball sample has a usable clock: 52 frames after 11:56:13 at 30,000 fps.
  const FrameSource ball =
      FrameSource::from_mraw(test::external("photron-mraw/ball_12bit.mraw").string(), sensor(384, 384), 0.0);
  ASSERT_EQ(ball.size(), 15u);
  EXPECT_EQ(format_iso8601_utc(ball.entry(0).utc), "2023-01-18T11:56:13.001733333Z");
  EXPECT_EQ(ball.load(14)->bits, 12);
  // The frame kind by extension, any case.
  EXPECT_EQ(frame_file_kind("a/b.MRAW"), FrameFileKind::mraw);
}

TEST(PhotronFrameSource, MissionConfigMrawKey) {
  const auto config = [](const nlohmann::json& frames) {
    nlohmann::json j = mission_json();
    j["cameras"][0]["frames"] = frames;
    return parse_mission_config(j.dump(), "/m/mission.json", false);
  };
  const MissionConfig c = config({{"mraw", "cam1/run.mraw"}, {"clock_utc_offset_h", -5.5}});
  EXPECT_EQ(c.cameras[0].frames.mraw, "/m/cam1/run.mraw");
  EXPECT_EQ(c.cameras[0].frames.clock_utc_offset_h, std::optional<double>(-5.5));
  EXPECT_TRUE(c.cameras[0].frames.timestamps.empty());
  const auto usage_error = [&](const nlohmann::json& frames, const std::string& words) {
    const Error e = expect_error([&] { config(frames); });
    EXPECT_EQ(e.kind(), ErrorKind::usage);
    EXPECT_EQ(e.file(), "/m/mission.json");
    EXPECT_EQ(e.field().rfind("cameras[0].frames", 0), 0u) << e.what();
    EXPECT_TRUE(contains(e.what(), words)) << e.what();
  };
  usage_error({{"mraw", "cam1/run.mraw"}}, "clock_utc_offset_h");
  usage_error({{"mraw", "cam1/run.mraw"}, {"cine", "a.cine"}, {"clock_utc_offset_h", 0}},
              "both 'cine' and 'mraw'");
  usage_error({{"timestamps", "t.csv"}, {"clock_utc_offset_h", 0}}, "applies only to 'mraw'");
  usage_error({{"mraw", "cam1/run.mraw"}, {"clock_utc_offset_h", 20}}, "within ±14");
  usage_error({{"mraw", "cam1/run.mraw"}, {"clock_utc_offset_h", "2"}}, "offset from UTC");
  usage_error({{"mraww", "cam1/run.mraw"}}, "did you mean 'mraw'");
}

// The align and detect stages on the same frames as PNGs with a CSV, as a .mraw named by a CSV and
// as a .mraw alone: identical aligned.csv and detections.csv, and run.json says the time source.
TEST(PhotronFrameSource, StagesReportTheTimeSource) {
  const fs::path dir = test::scratch_dir("mraw_fs_stages");
  const int n = 30;  // 1.5 s at 20 fps
  const auto frames = lamp_frames(n);
  for (int k = 0; k < n; ++k)
    write_frame_image((dir / "cam1" / ("f" + std::to_string(k) + ".png")).string(), frames[k]);
  test::write_text(dir / "cam1/png.csv",
                   csv_text(
                       n, [](int k) { return "f" + std::to_string(k) + ".png"; }, [](int k) { return k; }));
  write_photron_mraw((dir / "cam1/run.mraw").string(), frames, mraw_options(12));
  test::write_text(dir / "cam1/mraw.csv", csv_text(
                                              n, [](int) { return "run.mraw"; }, [](int k) { return k; }));
  // A lamp track at 10 Hz over the frames (the positions only need to be a smooth path).
  LampTrack track;
  for (int i = 0; i <= 16; ++i) {
    LampEpoch e;
    e.utc = UtcTime{kTrigger.ns + i * 100'000'000ll};
    e.enu = Eigen::Vector3d(10 + 0.9 * i, 50 + 0.3 * i, 20 + 0.6 * i);
    e.sd_enu = Eigen::Vector3d(0.01, 0.01, 0.02);
    e.quality = 1;
    track.epochs.push_back(e);
  }

  std::map<std::string, std::pair<std::string, std::string>> outputs;  // aligned.csv, detections.csv
  for (const std::string kind : {"png", "mraw_csv", "mraw_alone"}) {
    nlohmann::json j = mission_json();
    j["output_dir"] = "out_" + kind;
    if (kind == "png") j["cameras"][0]["frames"] = {{"timestamps", "cam1/png.csv"}};
    if (kind == "mraw_csv") j["cameras"][0]["frames"] = {{"timestamps", "cam1/mraw.csv"}};
    if (kind == "mraw_alone")
      j["cameras"][0]["frames"] = {{"mraw", "cam1/run.mraw"}, {"clock_utc_offset_h", 2}};
    const MissionConfig cfg = parse_mission_config(j.dump(), (dir / "mission.json").string(), false);
    write_lamp_track_csv(lamp_track_path(cfg), track);
    const StageLog align = run_align_stage(cfg);
    update_run_log(cfg, align);
    const StageLog detect = run_detect_stage(cfg);
    update_run_log(cfg, detect);
    const auto run = nlohmann::json::parse(test::read_text(fs::path(cfg.output_dir) / "run.json"));
    const std::string want = kind == "mraw_alone" ? "mraw header + rate" : "timestamps CSV";
    EXPECT_EQ(run["stages"]["align"]["counts"]["cam1"]["time_source"], want) << run.dump(1);
    EXPECT_EQ(run["stages"]["detect"]["counts"]["cam1"]["time_source"], want) << run.dump(1);
    bool warned = false;
    for (const std::string& w : align.warnings) warned = warned || contains(w, "Photron header");
    EXPECT_EQ(warned, kind == "mraw_alone");
    EXPECT_EQ(align.counts["cam1"]["frames_aligned"], 15) << align.counts.dump();
    EXPECT_EQ(detect.counts["cam1"]["correspondences"], 15) << detect.counts.dump();
    outputs[kind] = {test::read_text(camera_output(cfg, "cam1", kAlignedCsv)),
                     test::read_text(camera_output(cfg, "cam1", kDetectionsCsv))};
  }
  EXPECT_EQ(outputs["mraw_csv"], outputs["png"]);
  EXPECT_EQ(outputs["mraw_alone"], outputs["png"]);
}
