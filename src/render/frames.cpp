#include "render/frames.h"

#include <chrono>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

namespace sscs {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
}  // namespace

FrameRecorder::FrameRecorder(const Workcell& wc, const GeometryModel& geometry, CameraPath cameras,
                             const RenderOptions& options, std::string dir, int threads, size_t queue)
    : renderer_(wc, geometry, options), cameras_(std::move(cameras)), aspect_(double(options.width) / options.height),
      dir_(std::move(dir)), capacity_(std::max<size_t>(1, queue)), font_(default_font_path(), 15) {
  std::filesystem::create_directories(dir_);
  for (int i = 0; i < std::max(1, threads); ++i) workers_.emplace_back([this] { work(); });
}

FrameRecorder::~FrameRecorder() {
  {
    std::lock_guard lock(mutex_);
    closing_ = true;
  }
  changed_.notify_all();
  for (std::thread& t : workers_)
    if (t.joinable()) t.join();
}

Camera FrameRecorder::camera_at(double t, const ScenePose& pose) const { return cameras_.at(t, pose, renderer_.bounds(), aspect_); }

void FrameRecorder::frame(int n, double t, const ScenePose& pose) {
  auto t0 = Clock::now();
  Image image = renderer_.render(camera_at(t, pose), pose);
  stats_.render_s += since(t0);
  index_.emplace_back(n, t);
  auto t1 = Clock::now();
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return queue_.size() < capacity_ || error_; });
  stats_.wait_s += since(t1);
  if (error_) std::rethrow_exception(error_);
  queue_.push_back({n, std::move(image)});
  changed_.notify_all();
}

void FrameRecorder::step_end(size_t index, const std::string& label, double t, const ScenePose& pose) {
  auto t0 = Clock::now();
  thumbs_[index] = {downscale(renderer_.render(camera_at(t, pose), pose), 320), label};
  stats_.render_s += since(t0);
}

void FrameRecorder::work() {
  for (;;) {
    Job job;
    {
      std::unique_lock lock(mutex_);
      changed_.wait(lock, [&] { return !queue_.empty() || closing_; });
      if (queue_.empty()) return;
      job = std::move(queue_.front());
      queue_.pop_front();
    }
    changed_.notify_all();
    try {
      auto t0 = Clock::now();
      std::string png = encode_png(job.image);
      std::string path = fmt::format("{}/frame_{:06d}.png", dir_, job.n);
      std::ofstream f(path, std::ios::binary);
      f << png;
      if (!f) throw std::runtime_error(fmt::format("cannot write '{}'", path));
      std::lock_guard lock(mutex_);
      stats_.encode_s += since(t0);
    } catch (...) {
      std::lock_guard lock(mutex_);
      if (!error_) error_ = std::current_exception();
      changed_.notify_all();
    }
  }
}

FrameStats FrameRecorder::finish(const std::string& contact_sheet_path) {
  {
    std::lock_guard lock(mutex_);
    closing_ = true;
  }
  changed_.notify_all();
  for (std::thread& t : workers_) t.join();
  workers_.clear();
  if (error_) std::rethrow_exception(error_);
  std::string csv = "frame,t,file\n";
  for (auto [n, t] : index_) csv += fmt::format("{},{:.4f},frame_{:06d}.png\n", n, t, n);
  std::ofstream f(dir_ + "/index.csv", std::ios::binary);
  f << csv;
  if (!f) throw std::runtime_error(fmt::format("cannot write '{}/index.csv'", dir_));
  stats_.frames = static_cast<int>(index_.size());
  if (!thumbs_.empty()) {
    std::vector<Thumbnail> thumbs;
    for (auto& [i, t] : thumbs_) thumbs.push_back(std::move(t));
    std::ofstream sheet(contact_sheet_path, std::ios::binary);
    sheet << encode_png(contact_sheet(thumbs, font_));
    if (!sheet) throw std::runtime_error(fmt::format("cannot write '{}'", contact_sheet_path));
  }
  return stats_;
}

}  // namespace sscs
