#pragma once
/// Frames of a run: rendered on the simulation's thread at the frame times, encoded to PNG and
/// written on a small thread pool while the simulation goes on. The queue between them is
/// bounded, so memory stays flat however long the run.
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <exception>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <functional>

#include "render/action_camera.h"
#include "render/camera_path.h"
#include "render/contact_sheet.h"
#include "render/text.h"
#include "render/renderer.h"

namespace sscs {

struct FrameStats {
  int frames = 0;
  double render_s = 0;   ///< drawing and reading back, on the simulation's thread
  double draw_s = 0, readback_s = 0;  ///< the two parts of render_s
  double encode_s = 0;   ///< PNG encoding and writing, summed over the workers
  double wait_s = 0;     ///< the simulation waiting for a full queue
};

class FrameRecorder {
 public:
  /// Frames go to `dir/frame_NNNNNN.png`, their times to `dir/index.csv` (at finish()).
  FrameRecorder(const Workcell& wc, const GeometryModel& geometry, CameraPath cameras, const RenderOptions& options,
                std::string dir, int threads = 2, size_t queue = 4);
  ~FrameRecorder();
  FrameRecorder(const FrameRecorder&) = delete;
  FrameRecorder& operator=(const FrameRecorder&) = delete;

  /// Also pipes every frame (raw RGB) to `ffmpeg`, which encodes `path` (H.264 MP4) at `fps`;
  /// finish() waits for it and moves the file into place. Throws when ffmpeg cannot start.
  void record_video(const std::string& path, double fps);
  /// Whether an `ffmpeg` executable is on PATH.
  static bool ffmpeg_available();

  /// Renders frame `n` of the state at simulated time `t`.
  void frame(int n, double t, const ScenePose& pose);
  /// A thumbnail for the contact sheet: the state when step `index` ended (a later call for the
  /// same index replaces it: a parallel group ends with its last member), seen by the action
  /// camera on `focus` (the step's device, what it carries or acts on); none: the frames' camera.
  void step_end(size_t index, const std::string& label, double t, const ScenePose& pose, const Focus& focus = {});
  /// How much of each of `objects` contact-sheet panel `index` shows (the id pass of its camera
  /// at its moment); empty when no such panel was drawn.
  std::vector<Renderer::Visibility> panel_visibility(size_t index, const std::vector<int>& objects);
  /// What the run is doing at time t, for the frames' camera when the scenario has none.
  void set_focus(std::function<Focus(double)> focus) { focus_ = std::move(focus); }
  /// Waits for the queue to drain, writes index.csv and, when any step ended, the contact sheet
  /// to `contact_sheet`. Rethrows a worker's error (a full disk).
  FrameStats finish(const std::string& contact_sheet);
  /// The camera at time t (the view sequence of the run: the scenario's keyframes, else the
  /// action camera on the focus).
  Camera camera_at(double t, const ScenePose& pose);

 private:
  void work();
  struct Job {
    int n;
    Image image;
  };
  const GeometryModel& geometry_;
  Renderer renderer_;
  CameraPath cameras_;
  std::function<Focus(double)> focus_;
  ActionCamera action_, sheet_camera_;  // the frames' and the contact sheet's: each keeps its side
  double aspect_;
  std::string dir_;
  size_t capacity_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Job> queue_;
  bool closing_ = false;
  std::exception_ptr error_;
  std::vector<std::thread> workers_;
  std::vector<std::pair<int, double>> index_;
  std::map<size_t, Thumbnail> thumbs_;
  std::map<size_t, std::pair<Camera, ScenePose>> panels_;  ///< how each thumbnail was drawn
  int width_, height_;
  FILE* video_ = nullptr;
  std::string video_path_, video_tmp_;
  Font font_;
  FrameStats stats_;
};

}  // namespace sscs
