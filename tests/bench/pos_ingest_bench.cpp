// End-to-end PPK ingest (docs/gnss.md): a one-hour 20 Hz RTKLIB .pos (72,000 epochs, lat/lon/h in
// degrees, GPST calendar time, RTKLIB's columns and mixed LF/CRLF), generated into a temp file at
// start; measured: read + parse + filter + site ENU + lever arm (body FRD with interpolated
// attitude) → lamp track. Target: well under 0.2 s.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "pipeline/stages/gnss_stage.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

constexpr int kEpochs = 72000;  // 1 h at 20 Hz
const GeodeticOrigin kOrigin{45.6, 122.8, 150.0};

std::string make_pos_file() {
  const auto dir = test::scratch_dir("bench_pos_ingest");
  const std::string path = (dir / "one_hour_20hz.pos").string();
  std::string s =
      "% program   : rnx2rtkp ver.2.4.3 b34\n% inp file  : rover.obs\n% inp file  : base.obs\n"
      "% obs start : 2026/05/01 02:00:00.0 GPST\n"
      "% obs end   : 2026/05/01 02:59:59.9 GPST\n"
      "% ref pos   :  45.600100000  122.800200000   151.0000\n%\n"
      "% (lat/lon/height=WGS84/ellipsoidal,Q=1:fix,2:float,3:sbas,4:dgps,5:single,6:ppp,ns=# of "
      "satellites)\r\n"
      "%  GPST                  latitude(deg) longitude(deg)  height(m)   Q  ns   sdn(m)   sde(m)   sdu(m)  "
      "sdne(m)  "
      "sdeu(m)  sdun(m) age(s)  ratio\r\n";
  s.reserve(s.size() + kEpochs * 150);
  char buf[256];
  for (int i = 0; i < kEpochs; ++i) {
    const double t = i * 0.05;
    const int ms = (i % 20) * 50;
    const int sec = i / 20;
    // A slow circle of 100 m radius climbing and descending.
    const double lat = 45.6 + 0.0009 * std::sin(t * 0.01), lon = 122.8 + 0.0012 * std::cos(t * 0.01);
    const double h = 150 + 40 * std::sin(t * 0.003);
    const int q = (i % 50 == 0) ? 2 : 1;
    const double sd = q == 1 ? 0.008 + 0.002 * std::sin(t) : 0.25;
    std::snprintf(
        buf, sizeof buf,
        "2026/05/01 %02d:%02d:%02d.%03d %14.9f %14.9f %10.4f %3d %3d %8.4f %8.4f %8.4f %8.4f %8.4f %8.4f "
        "%6.2f %6.1f\r\n",
        2 + sec / 3600, sec / 60 % 60, sec % 60, ms, lat, lon, h, q, 17, sd, sd * 0.9, sd * 2.1, sd * 0.3,
        -sd * 0.2, sd * 0.4, 0.4, 52.3);
    s += buf;
  }
  test::write_text(path, s);
  return path;
}

AttitudeSeries make_attitude() {
  AttitudeSeries a;
  a.path = "attitude";
  const UtcTime t0 = utc_from_civil(2026, 5, 1, 1, 59, 40, 0);  // GPST 02:00:00 − 18 s, with margin
  for (int i = 0; i < kEpochs + 40; ++i) {
    const double t = i * 0.05;
    a.samples.push_back({UtcTime{t0.ns + i * 50'000'000LL},
                         {3 * std::sin(t), 2 * std::cos(t), std::fmod(t, 360) - 180},
                         i + 2});
  }
  return a;
}

void BM_PosIngestOneHour20Hz(benchmark::State& state) {
  const std::string path = make_pos_file();
  LampTrackInputs in;
  in.attitude = make_attitude();
  in.lever.form = ResolvedLeverArm::Form::body_frd;
  in.lever.body_frd_m = Eigen::Vector3d(0.05, 0.0, 0.25);
  in.origin = kOrigin;
  in.filter.accept_quality = {1};
  in.filter.max_sd_m = 0.05;
  in.filter.max_gap_s = 0.5;
  std::size_t kept = 0;
  for (auto _ : state) {
    in.pos_files.clear();
    in.pos_files.push_back(read_rtklib_pos(path));
    const LampTrackResult r = compute_lamp_track(in);
    kept = r.track.epochs.size();
    benchmark::DoNotOptimize(r.track.epochs.data());
  }
  state.counters["epochs"] = kEpochs;
  state.counters["kept"] = static_cast<double>(kept);
  state.counters["epochs_per_s"] =
      benchmark::Counter(static_cast<double>(kEpochs), benchmark::Counter::kIsIterationInvariantRate);
  std::filesystem::remove_all(std::filesystem::path(path).parent_path());
}
BENCHMARK(BM_PosIngestOneHour20Hz)->Unit(benchmark::kMillisecond)->MinTime(2.0);

void BM_PosReadOnly(benchmark::State& state) {
  const std::string path = make_pos_file();
  for (auto _ : state) {
    PosFile f = read_rtklib_pos(path);
    benchmark::DoNotOptimize(f.epochs.data());
  }
  std::filesystem::remove_all(std::filesystem::path(path).parent_path());
}
BENCHMARK(BM_PosReadOnly)->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace
}  // namespace rangecal
