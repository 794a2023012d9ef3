#include "pipeline/io/progress_bar.hpp"

#include <algorithm>
#include <cstdio>

namespace rangecal {
namespace {
std::atomic<bool> g_on{false};
}

void set_progress_bars(bool on) {
  g_on = on;
}

ProgressBar::ProgressBar(std::string label, std::size_t total)
    : label_(std::move(label)), total_(total), on_(g_on && total > 0) {
  if (on_) draw(0);
}

ProgressBar::~ProgressBar() {
  if (!on_) return;
  draw(done_.load());
  std::fputc('\n', stderr);
}

void ProgressBar::tick(std::size_t n) {
  const std::size_t d = done_ += n;
  if (!on_) return;
  const auto now = std::chrono::steady_clock::now();
  std::lock_guard<std::mutex> lock(mu_);
  if (now - last_ < std::chrono::milliseconds(100) && d < total_) return;
  last_ = now;
  draw(d);
}

void ProgressBar::draw(std::size_t done) {
  constexpr int kWidth = 30;
  const int fill = total_ ? static_cast<int>(kWidth * std::min(done, total_) / total_) : kWidth;
  std::string bar(static_cast<std::size_t>(fill), '#');
  bar.append(static_cast<std::size_t>(kWidth - fill), '.');
  std::fprintf(stderr, "\r%s [%s] %zu/%zu", label_.c_str(), bar.c_str(), done, total_);
  std::fflush(stderr);
}

}  // namespace rangecal
