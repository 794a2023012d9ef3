// A small JSON file nested 100,000 levels deep (docs/reliability.md "Bounded work"): every command
// that reads JSON — the mission config, a scenario, a calibration.json — refuses it with its exit
// code and a message naming the file, the line and the key path, in well under a second and
// 100 MB. The file is generated here; the command runs as a child whose CPU time and peak memory
// (wait4's ru_utime + ru_stime, ru_maxrss) are measured, under limits that stop a regression from
// taking the machine with it (the same file once took 109 s and 17.8 GB to be refused). CPU time,
// not wall time, is held to the second: starting the program (its shared libraries) takes most of
// it, 0.6-1.0 s of wall time on a machine busy with two builds, 0.3 s of CPU.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>
#include <chrono>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "config/json_view.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;

struct MeasuredRun {
  int exit_code = -1;  ///< -1: killed by a signal (a limit below)
  double wall_s = 0;
  double cpu_s = 0;  ///< user + system
  long max_rss_kb = 0;
  std::string err;
};

// Runs the rangecal binary with `args` as a child process: at most 20 CPU-seconds and 2 GiB of
// address space, stdout discarded, stderr captured.
MeasuredRun run_measured(const std::vector<std::string>& args, const fs::path& err_file) {
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    const rlimit cpu{20, 20}, as{2L << 30, 2L << 30};
    setrlimit(RLIMIT_CPU, &cpu);
    setrlimit(RLIMIT_AS, &as);
    const int out = open("/dev/null", O_WRONLY);
    const int err = open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(out, 1);
    dup2(err, 2);
    const std::string bin = test::rangecal_binary().string();
    std::vector<char*> argv{const_cast<char*>(bin.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(bin.c_str(), argv.data());
    _exit(127);
  }
  MeasuredRun r;
  int status = 0;
  rusage ru{};
  if (pid > 0 && wait4(pid, &status, 0, &ru) == pid) {
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.max_rss_kb = ru.ru_maxrss;
    r.cpu_s = static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
              1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.err = test::read_text(err_file);
  return r;
}

// `levels` nested arrays: ~2 bytes a level, so 100,000 levels are a 200 KB file.
std::string nested_arrays(std::size_t levels) {
  return std::string(levels, '[') + std::string(levels, ']');
}

constexpr std::size_t kDeep = 100000;

void expect_refused_quickly(const MeasuredRun& r, int exit_code, const fs::path& file, int line,
                            const std::string& key) {
  EXPECT_EQ(r.exit_code, exit_code) << r.err;
  EXPECT_NE(r.err.find(file.string() + ":" + std::to_string(line) + ": field '" + key + "[0][0]"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("nested deeper than " + std::to_string(kMaxJsonNesting) + " levels"),
            std::string::npos)
      << r.err;
  EXPECT_LT(r.cpu_s, 1.0);
  EXPECT_LT(r.wall_s, 10.0);
  EXPECT_LT(r.max_rss_kb, 100 * 1024) << "peak memory of the refusal, KiB";
}

TEST(DeepJsonCli, MissionConfigWithADeepUnknownKeyIsRefusedInUnderASecondAnd100MB) {
  const fs::path d = test::scratch_dir("deep_json_mission");
  const fs::path cfg = d / "mission.json";
  test::write_text(cfg,
                   "{\n  \"site\": {\"origin\": {\"lat\": 53.28, \"lon\": -8.98, \"h\": 87.4}},\n"
                   "  \"cameras\": [],\n  \"output_dir\": \"out\",\n  \"extras\": " +
                       nested_arrays(kDeep) + "\n}\n");
  ASSERT_GT(fs::file_size(cfg), 200000u);
  for (const char* command : {"run", "gnss", "report"}) {
    const MeasuredRun r = run_measured({command, cfg.string()}, d / "err.txt");
    expect_refused_quickly(r, 2, cfg, 5, "extras");
    std::printf("rangecal %s on the %ju-byte config: exit %d, %.3f s CPU, %.3f s wall, peak %ld KiB\n",
                command, static_cast<std::uintmax_t>(fs::file_size(cfg)), r.exit_code, r.cpu_s, r.wall_s,
                r.max_rss_kb);
  }
  EXPECT_FALSE(fs::exists(d / "out")) << "a refused config leaves no output folder";
}

TEST(DeepJsonCli, ScenarioAndCalibrationFilesAreRefusedTheSameWay) {
  const fs::path d = test::scratch_dir("deep_json_other");
  // A scenario (simulate, plan): its reader is the same; the kind is the config's (exit 2).
  const fs::path scenario = d / "scenario.json";
  test::write_text(scenario, "{\"seed\": 1,\n\"routes\": " + nested_arrays(kDeep) + "}\n");
  expect_refused_quickly(
      run_measured({"simulate", scenario.string(), "--out", (d / "sim").string()}, d / "err.txt"), 2,
      scenario, 2, "routes");
  EXPECT_FALSE(fs::exists(d / "sim"));
  // A calibration.json handed to `project` is input data (exit 3).
  const fs::path calibration = d / "calibration.json";
  test::write_text(calibration, "{\"camera\":\n {\"k\": " + nested_arrays(kDeep) + "}}\n");
  test::write_text(d / "points.csv", "id,E,N,U\nP1,1,2,3\n");
  expect_refused_quickly(run_measured({"project", "--calibration", calibration.string(), "--points",
                                       (d / "points.csv").string()},
                                      d / "err.txt"),
                         3, calibration, 2, "camera.k");
}

}  // namespace
}  // namespace rangecal
