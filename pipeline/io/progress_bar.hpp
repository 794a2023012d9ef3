#pragma once
// Progress bars on stderr for long stages (docs/cli.md: "progress bars on stderr for long stages when
// stderr is a terminal"). Off unless the CLI turns them on (it does so only for a terminal and
// without --quiet), so tests, pipes and batch logs never see them.
#include <atomic>
#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace rangecal {

/// Turns progress bars on or off for the whole process (default off).
void set_progress_bars(bool on);

/// One bar: "label [#######.............]  345/1400". Thread-safe tick(); redraws at most every
/// 100 ms; the destructor finishes the line. Does nothing when bars are off.
class ProgressBar {
 public:
  ProgressBar(std::string label, std::size_t total);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  void tick(std::size_t n = 1);

 private:
  void draw(std::size_t done);
  std::string label_;
  std::size_t total_;
  bool on_;
  std::atomic<std::size_t> done_{0};
  std::mutex mu_;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace rangecal
