#pragma once
/// Progress of a sweep on stderr: one line rewritten in place on a terminal (done/total, rate,
/// ETA), or a plain line now and then when stderr is a log file.
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <string>

namespace sscs {

/// "37/500 variants, 12.4/s, ETA 37 s" (`done` counts this session's variants; `rate` is theirs
/// per second of `elapsed`; ETA is unknown before the first). Pure, for tests.
std::string progress_text(size_t done, size_t total, double elapsed_s);

/// A duration for people: "8 s", "3 min 20 s", "2 h 05 min".
std::string human_duration(double seconds);

class ProgressBar {
 public:
  enum class Mode { None, Lines, Live };
  ProgressBar(Mode mode, size_t total, std::FILE* out = stderr);
  /// `done` variants of `total` finished; draws at most 10 times a second (Live) or every
  /// 10% / 30 s (Lines).
  void update(size_t done);
  /// The last state, and a newline after a live line.
  void finish(size_t done);

 private:
  void draw(size_t done);
  Mode mode_;
  size_t total_;
  std::FILE* out_;
  std::chrono::steady_clock::time_point start_, last_;
  size_t last_done_ = 0;
  bool drawn_ = false;
};

}  // namespace sscs
