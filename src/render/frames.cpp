#include "render/frames.h"

#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <sstream>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "core/files.h"

namespace sscs {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
}  // namespace

FrameRecorder::FrameRecorder(const Workcell& wc, const GeometryModel& geometry, CameraPath cameras,
                             const RenderOptions& options, std::string dir, int threads, size_t queue)
    : geometry_(geometry), renderer_(wc, geometry, options), cameras_(std::move(cameras)), aspect_(double(options.width) / options.height),
      dir_(std::move(dir)), capacity_(std::max<size_t>(1, queue)), width_(options.width),
      height_(options.height), font_(default_font_path(), 15) {
  std::filesystem::create_directories(dir_);
  for (int i = 0; i < std::max(1, threads); ++i) workers_.emplace_back([this] { work(); });
}

namespace {
/// `s` for inside single quotes in a shell command.
std::string shell_quoted(const std::string& s) {
  std::string out;
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out;
}
}  // namespace

bool FrameRecorder::ffmpeg_available() {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (!dir.empty() && ::access((dir + "/ffmpeg").c_str(), X_OK) == 0) return true;
  return false;
}

void FrameRecorder::record_video(const std::string& path, double fps) {
  video_path_ = path;
  video_tmp_ = temp_path_for(path);
  std::string cmd = fmt::format(
      "ffmpeg -y -loglevel error -f rawvideo -pix_fmt rgb24 -s {}x{} -framerate {:g} -i - -c:v libx264 -preset veryfast "
      "-pix_fmt yuv420p -movflags +faststart '{}'",
      width_, height_, fps, shell_quoted(video_tmp_));
  std::signal(SIGPIPE, SIG_IGN);  // a failed ffmpeg shows as a write error, not a killed sscs
  video_ = ::popen(cmd.c_str(), "w");
  if (!video_) throw std::runtime_error("cannot start ffmpeg for --video");
}

FrameRecorder::~FrameRecorder() {
  if (video_) {
    ::pclose(video_);
    std::remove(video_tmp_.c_str());
  }
  {
    std::lock_guard lock(mutex_);
    closing_ = true;
  }
  changed_.notify_all();
  for (std::thread& t : workers_)
    if (t.joinable()) t.join();
}

Camera FrameRecorder::camera_at(double t, const ScenePose& pose) {
  // No cameras in the scenario: the action camera, on what the run is doing.
  if (cameras_.keys().empty() && focus_) return action_.at(focus_(t), pose, geometry_, renderer_, aspect_);
  return cameras_.at(t, pose, renderer_.bounds(), aspect_);
}

void FrameRecorder::frame(int n, double t, const ScenePose& pose) {
  auto t0 = Clock::now();
  Image image = renderer_.render(camera_at(t, pose), pose);
  stats_.render_s += since(t0);
  if (video_ && std::fwrite(image.rgb.data(), 1, image.rgb.size(), video_) != image.rgb.size())
    throw std::runtime_error("ffmpeg stopped taking frames for --video");
  index_.emplace_back(n, t);
  auto t1 = Clock::now();
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return queue_.size() < capacity_ || error_; });
  stats_.wait_s += since(t1);
  if (error_) std::rethrow_exception(error_);
  queue_.push_back({n, std::move(image)});
  changed_.notify_all();
}

void FrameRecorder::step_end(size_t index, const std::string& label, double t, const ScenePose& pose, const Focus& focus) {
  auto t0 = Clock::now();
  // A panel shows what its step did, whatever the scenario's cameras film: the action camera.
  const Camera camera = focus.empty() ? camera_at(t, pose) : sheet_camera_.at(focus, pose, geometry_, renderer_, aspect_);
  thumbs_[index] = {downscale(renderer_.render(camera, pose), 320), label};
  panels_.insert_or_assign(index, std::pair{camera, pose});
  stats_.render_s += since(t0);
}

std::vector<Renderer::Visibility> FrameRecorder::panel_visibility(size_t index, const std::vector<int>& objects) {
  auto it = panels_.find(index);
  if (it == panels_.end()) return {};
  return renderer_.visibility(it->second.first, it->second.second, objects);
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
      if (std::string err = write_file(path, png); !err.empty()) throw OutputError(err);
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
  if (std::string err = write_file(dir_ + "/index.csv", csv); !err.empty()) throw OutputError(err);
  stats_.frames = static_cast<int>(index_.size());
  stats_.draw_s = renderer_.draw_seconds();
  stats_.readback_s = renderer_.readback_seconds();
  if (video_) {
    int status = ::pclose(video_);
    video_ = nullptr;
    if (status != 0) {
      std::remove(video_tmp_.c_str());
      throw std::runtime_error(fmt::format("ffmpeg failed to encode '{}' (exit status {})", video_path_, status));
    }
    if (std::string err = commit_file(video_tmp_, video_path_); !err.empty()) throw OutputError(err);
  }
  if (!thumbs_.empty()) {
    std::vector<Thumbnail> thumbs;
    for (auto& [i, t] : thumbs_) thumbs.push_back(std::move(t));
    if (std::string err = write_file(contact_sheet_path, encode_png(contact_sheet(thumbs, font_))); !err.empty())
      throw OutputError(err);
  }
  return stats_;
}

}  // namespace sscs
