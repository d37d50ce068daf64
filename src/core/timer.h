#pragma once
/// Stage timings for benchmarks: printed to stderr when SSCS_TIMING is set, else silent.
#include <chrono>
#include <cstdio>
#include <cstdlib>

namespace sscs {

class StageTimer {
 public:
  StageTimer() : enabled_(std::getenv("SSCS_TIMING") != nullptr), last_(std::chrono::steady_clock::now()) {}
  /// Prints the time since the previous lap under `stage`.
  void lap(const char* stage) {
    auto now = std::chrono::steady_clock::now();
    if (enabled_)
      std::fprintf(stderr, "timing: %-8s %8.3f s\n", stage, std::chrono::duration<double>(now - last_).count());
    last_ = now;
  }

 private:
  bool enabled_;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace sscs
