#include "sweep/progress.h"

#include <cmath>

#include <fmt/format.h>

namespace sscs {

std::string human_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "?";
  auto total = static_cast<long long>(std::llround(s));
  if (total < 60) return fmt::format("{} s", total);
  if (total < 3600) return fmt::format("{} min {:02} s", total / 60, total % 60);
  return fmt::format("{} h {:02} min", total / 3600, (total % 3600) / 60);
}

std::string progress_text(size_t done, size_t total, double elapsed_s) {
  std::string text = fmt::format("{}/{} variants", done, total);
  if (done == 0 || elapsed_s <= 0) return text;
  double rate = static_cast<double>(done) / elapsed_s;
  text += rate >= 10 ? fmt::format(", {:.0f}/s", rate) : fmt::format(", {:.2g}/s", rate);
  if (done < total) text += fmt::format(", ETA {}", human_duration(static_cast<double>(total - done) / rate));
  return text;
}

ProgressBar::ProgressBar(Mode mode, size_t total, std::FILE* out)
    : mode_(mode), total_(total), out_(out), start_(std::chrono::steady_clock::now()), last_(start_) {}

void ProgressBar::draw(size_t done) {
  double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::string text = progress_text(done, total_, elapsed);
  if (mode_ == Mode::Live) {
    // A bar of 24 cells before the text; \33[K clears what a longer earlier line left.
    size_t cells = total_ ? done * 24 / total_ : 24;
    std::fprintf(out_, "\r[%s%s] %s\33[K", std::string(cells, '#').c_str(), std::string(24 - cells, '.').c_str(), text.c_str());
  } else {
    std::fprintf(out_, "%s\n", text.c_str());
  }
  std::fflush(out_);
  drawn_ = true;
  last_done_ = done;
  last_ = std::chrono::steady_clock::now();
}

void ProgressBar::update(size_t done) {
  if (mode_ == Mode::None) return;
  auto now = std::chrono::steady_clock::now();
  double since = std::chrono::duration<double>(now - last_).count();
  if (mode_ == Mode::Live ? since >= 0.1 || !drawn_
                          : since >= 30 || (total_ >= 10 ? done >= last_done_ + total_ / 10 : done > last_done_))
    draw(done);
}

void ProgressBar::finish(size_t done) {
  if (mode_ == Mode::None) return;
  if (!drawn_ || done != last_done_ || mode_ == Mode::Live) draw(done);
  if (mode_ == Mode::Live) std::fputc('\n', out_);
}

}  // namespace sscs
