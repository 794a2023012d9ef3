// Frame decoding throughput (docs/accuracy_analysis.md, Quality bars): 16-bit PNG and TIFF (1280×800) through
// the frame source's decoder, and 16-bit and packed 12-bit .cine images through CineReader.
#include <benchmark/benchmark.h>

#include <opencv2/core/utility.hpp>

#include "support/paths.hpp"
#include "vision/frames/cine_reader.hpp"
#include "vision/frames/cine_writer.hpp"
#include "vision/frames/frame_renderer.hpp"
#include "vision/frames/frame_source.hpp"

using namespace rangecal;

namespace {

const cv::Mat& frame16() {
  static const cv::Mat m = [] {
    FrameRenderSettings st;
    st.width = 1280;
    st.height = 800;
    st.bits = 12;
    st.sky_level = 300;
    st.read_noise = 6;
    return render_frame(st, {{640.3, 400.7, 1.5, 2000}}, 3);
  }();
  return m;
}

std::string file_for(const std::string& name) {
  static const auto dir = test::scratch_dir("frame_decode_bench");
  const std::string p = (dir / name).string();
  if (name.find(".cine") != std::string::npos) {
    CineWriteOptions o;
    o.storage_bits = name.find("p12") != std::string::npos ? 12 : 16;
    write_cine(p, {frame16()}, {UtcTime{1'780'000'000'000'000'000ll}}, o);
  } else {
    write_frame_image(p, frame16());
  }
  return p;
}

void decode_image(benchmark::State& state, const std::string& name) {
  cv::setNumThreads(1);
  const std::string p = file_for(name);
  int bits = 0;
  for (auto _ : state) {
    const cv::Mat m = decode_image_file(p, &bits);
    benchmark::DoNotOptimize(m.data);
  }
  state.counters["frames_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_Decode_Png16_1280x800(benchmark::State& s) {
  decode_image(s, "f16.png");
}
void BM_Decode_Tiff16_1280x800(benchmark::State& s) {
  decode_image(s, "f16.tif");
}
BENCHMARK(BM_Decode_Png16_1280x800)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Decode_Tiff16_1280x800)->Unit(benchmark::kMillisecond);

void decode_cine(benchmark::State& state, const std::string& name) {
  const CineReader r(file_for(name));
  for (auto _ : state) {
    const cv::Mat m = r.read_image(0);
    benchmark::DoNotOptimize(m.data);
  }
  state.counters["frames_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
void BM_Decode_Cine16_1280x800(benchmark::State& s) {
  decode_cine(s, "f16.cine");
}
void BM_Decode_CinePacked12_1280x800(benchmark::State& s) {
  decode_cine(s, "f_p12.cine");
}
BENCHMARK(BM_Decode_Cine16_1280x800)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Decode_CinePacked12_1280x800)->Unit(benchmark::kMillisecond);

}  // namespace
