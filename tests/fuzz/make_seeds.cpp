// Writes tiny, valid binary seeds for the fuzz targets whose real samples are too large to fuzz
// from (docs/reliability.md "Fuzzing"): .cine files and Photron .mraw/.cihx pairs written by the
// project's own writers, a .cih text header, and a DataFlash log built from the format's published
// layout (tests/support/dataflash_writer.hpp). Usage: make_seeds OUT_DIR (one folder per target).
#include <filesystem>
#include <fstream>
#include <iostream>
#include <opencv2/core.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "support/dataflash_writer.hpp"
#include "vision/frames/cine_writer.hpp"
#include "vision/frames/photron_mraw_writer.hpp"

namespace fs = std::filesystem;
using namespace rangecal;

namespace {

const std::string kMrawSeparator = "\n--rangecal-fuzz-mraw--\n";  // as in fuzz_photron_mraw.cpp

void put(const fs::path& file, const std::string& bytes) {
  fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << bytes;
}

std::vector<cv::Mat> ramp_images(int type, int max_value, int count) {
  std::vector<cv::Mat> images;
  for (int k = 0; k < count; ++k) {
    cv::Mat m(4, 8, type);
    for (int r = 0; r < m.rows; ++r)
      for (int c = 0; c < m.cols; ++c) {
        const int v = (r * 8 + c + k * 5) % (max_value + 1);
        if (type == CV_8UC1)
          m.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>(v);
        else
          m.at<std::uint16_t>(r, c) = static_cast<std::uint16_t>(v);
      }
    images.push_back(m);
  }
  return images;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_seeds OUT_DIR\n";
    return 2;
  }
  const fs::path out = argv[1];
  const fs::path scratch = out / "scratch";
  fs::create_directories(scratch);
  try {
    // Phantom .cine: 8, 10 (packed), 12 (packed) and 16-bit storage, two images with TIME64.
    for (const int bits : {8, 10, 12, 16}) {
      CineWriteOptions o;
      o.storage_bits = bits;
      o.frame_rate = 1000;
      o.exposure_s = 0.0005;
      o.trigger_time = UtcTime{1'778'725'800'000'000'000};
      const std::vector<UtcTime> times{UtcTime{1'778'725'800'000'000'000},
                                       UtcTime{1'778'725'800'001'000'000}};
      const fs::path p = scratch / ("gen_" + std::to_string(bits) + ".cine");
      write_cine(p.string(), ramp_images(bits == 8 ? CV_8UC1 : CV_16UC1, (1 << bits) - 1, 2), times, o);
      put(out / "cine" / p.filename(), read_file_text(p.string()));
    }
    // Photron .mraw + .cihx: 8, 12 (packed) and 16-bit storage, two frames.
    for (const int bits : {8, 12, 16}) {
      PhotronWriteOptions o;
      o.storage_bits = bits;
      o.record_rate_fps = 1000;
      o.date = "2026/5/14";
      o.time = "04:30:00";
      o.device_name = "FASTCAM SA-Z type 2100K-M-64GB";
      const fs::path mraw = scratch / ("gen_" + std::to_string(bits) + ".mraw");
      const std::string header = write_photron_mraw(
          mraw.string(), ramp_images(bits == 8 ? CV_8UC1 : CV_16UC1, (1 << bits) - 1, 2), o);
      const std::string cihx = read_file_text(header);
      put(out / "photron_header" / ("gen_" + std::to_string(bits) + ".cihx"), cihx);
      put(out / "photron_mraw" / ("gen_" + std::to_string(bits) + "_cihx"),
          "x" + cihx + kMrawSeparator + read_file_text(mraw.string()));
    }
    // Photron .cih (text form), 8-bit, two 8×4 frames.
    const std::string cih =
        "#Camera Information Header\r\nDate : 2026/5/14\r\nTime : 04:30:00\r\n"
        "Camera Type : FASTCAM SA-Z type 2100K-M-64GB\r\nRecord Rate(fps) : 1000\r\n"
        "Shutter Speed(s) : 1/2000\r\nTotal Frame : 2\r\nStart Frame : 0\r\nSave Step : 1\r\n"
        "Image Width : 8\r\nImage Height : 4\r\nColor Type : Mono\r\nColor Bit : 8\r\n"
        "EffectiveBit Depth : 8\r\nEffectiveBit Side : Lower\r\nFile Format : MRaw\r\nIRIG : Off\r\nEND\r\n";
    put(out / "photron_header" / "gen_8.cih", cih);
    put(out / "photron_mraw" / "gen_8_cih", "c" + cih + kMrawSeparator + std::string(64, '\x10'));
    // ArduPilot DataFlash: ATT at 50 Hz and GPS at 5 Hz with a 3-D fix, one second.
    test::DataflashWriter w;
    w.define_att_and_gps();
    for (int i = 0; i <= 50; ++i) {
      const std::uint64_t t = 10'000'000 + static_cast<std::uint64_t>(i) * 20'000;
      if (i % 10 == 0) w.gps(t, 3, 2400, 100'000 + static_cast<std::uint32_t>(i) * 20);
      w.att(t, 1.5, -2.0, 350.0 + i * 0.1);
    }
    put(out / "ardupilot_dataflash" / "gen_att_gps.bin", w.bytes());
  } catch (const Error& e) {
    std::cerr << "make_seeds: " << e.what() << "\n";
    return 1;
  }
  fs::remove_all(scratch);
  return 0;
}
