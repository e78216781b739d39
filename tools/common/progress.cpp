#include "common/progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace tool {

ProgressBar::ProgressBar(bool enabled) : enabled_(enabled && ::isatty(2)) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(std::string_view stage, std::size_t done, std::size_t total) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && done < total && now - last_ < std::chrono::milliseconds(100)) return;
  last_ = now;
  constexpr int kWidth = 30;
  const double frac = total == 0 ? 1.0 : double(done) / double(total);
  const int filled = int(frac * kWidth);
  std::string bar(std::size_t(filled), '#');
  bar.resize(kWidth, ' ');
  std::fprintf(stderr, "\r[%s] %3d%% %.*s %zu/%zu", bar.c_str(), int(frac * 100), int(stage.size()),
               stage.data(), done, total);
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (!drawn_) return;
  std::fputs("\r\033[K", stderr);
  std::fflush(stderr);
  drawn_ = false;
}

}  // namespace tool
