#pragma once
// A one-line progress bar on stderr: "\r[#####     ]  48% cut 1234/2560", at most 10 redraws
// a second, only when stderr is a terminal.
#include <chrono>
#include <cstddef>
#include <string>
#include <string_view>

namespace tool {

class ProgressBar {
 public:
  explicit ProgressBar(bool enabled);
  ~ProgressBar();
  void update(std::string_view stage, std::size_t done, std::size_t total);
  void finish();

 private:
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace tool
