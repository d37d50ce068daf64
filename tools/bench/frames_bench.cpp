// Frames of a run: the arm drum transfer simulated with 1280x720 frames on, against the same
// run with frames off, with rendering alone (frames drawn and dropped) and with PNG encoding
// alone (the same number of frames encoded on the same two-thread pool). Prints frames per
// second end to end, the time per frame of drawing, readback and encoding, the simulation's
// slowdown with frames, and how well encoding overlaps rendering. Targets (issue 7): >= 15
// frames/s end to end; total with frames <= 1.2x the larger of render-only and encode-only.
//
//   frames_bench [scenario=scenarios/drum-transfer/arm-loads-drum.yaml] [WIDTHxHEIGHT=1280x720]
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "pipeline/prepare.h"
#include "render/frames.h"
#include "simulate/simulate.h"

namespace {

using Clock = std::chrono::steady_clock;
using namespace sscs;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

int main(int argc, char** argv) {
  std::string scenario = argc > 1 ? argv[1] : "scenarios/drum-transfer/arm-loads-drum.yaml";
  RenderOptions ro;
  if (argc > 2 && std::sscanf(argv[2], "%dx%d", &ro.width, &ro.height) != 2) return 2;
  PreparedScenario ps;
  if (!ps.prepare(scenario, CompileOptions{})) {
    std::fputs(ps.diag.format(ps.sources, false).c_str(), stderr);
    return 2;
  }
  const Plan& plan = *ps.plan;
  const double fps = plan.settings.frames ? plan.settings.fps : 15;

  // Frames off.
  auto t0 = Clock::now();
  run_simulation(*ps.wc, ps.geometry, plan, RunOptions{});  // no outputs: nothing to fail
  const double off = since(t0);

  // Frames on: rendered on this thread, encoded and written on the pool.
  const std::string dir = (std::filesystem::temp_directory_path() / "sscs-frames-bench").string();
  std::filesystem::remove_all(dir);
  FrameStats stats;
  double on = 0;
  {
    FrameRecorder recorder(*ps.wc, ps.geometry, ps.cameras, ro, dir);
    RunOptions run;
    run.frame_interval = 1 / fps;
    run.on_frame = [&](int n, double t, const ScenePose& pose) { recorder.frame(n, t, pose); };
    t0 = Clock::now();
    run_simulation(*ps.wc, ps.geometry, plan, run);
    stats = recorder.finish(dir + "/contact_sheet.png");
    on = since(t0);
  }

  // Rendering alone: the same run, frames drawn and dropped; a few kept for the encoding run.
  std::vector<Image> samples;
  double render_only = 0;
  {
    Renderer renderer(*ps.wc, ps.geometry, ro);
    RunOptions run;
    run.frame_interval = 1 / fps;
    run.on_frame = [&](int n, double t, const ScenePose& pose) {
      Image img = renderer.render(ps.cameras.at(t, pose, renderer.bounds(), double(ro.width) / ro.height), pose);
      if (n % 10 == 0) samples.push_back(std::move(img));
    };
    t0 = Clock::now();
    run_simulation(*ps.wc, ps.geometry, plan, run);
    render_only = since(t0);
  }

  // Encoding alone: as many frames as the run had, on two threads like the recorder's pool.
  t0 = Clock::now();
  {
    std::vector<std::thread> pool;
    for (int w = 0; w < 2; ++w)
      pool.emplace_back([&, w] {
        for (int n = w; n < stats.frames; n += 2) {
          std::string png = encode_png(samples[static_cast<size_t>(n / 10) % samples.size()]);
          std::FILE* f = std::fopen((dir + "/encode-only.png").c_str(), "wb");
          std::fwrite(png.data(), 1, png.size(), f);
          std::fclose(f);
        }
      });
    for (auto& t : pool) t.join();
  }
  const double encode_only = since(t0);
  std::filesystem::remove_all(dir);

  const int n = stats.frames;
  std::printf("%s: %d frames of %dx%d, one every 1/%g s of simulated time\n", scenario.c_str(), n, ro.width, ro.height,
              fps);
  std::printf("  per frame: draw %.1f ms, readback %.1f ms, PNG encode+write %.1f ms (on 2 threads)\n",
              1e3 * stats.draw_s / n, 1e3 * stats.readback_s / n, 1e3 * stats.encode_s / n);
  std::printf("  run with frames off:    %7.3f s\n", off);
  std::printf("  run with frames on:     %7.3f s   (%.1fx slower)\n", on, on / off);
  std::printf("  render only:            %7.3f s\n  encode only:            %7.3f s\n", render_only, encode_only);
  std::printf("  end to end:             %7.1f frames/s   (target >= 15)\n", n / on);
  std::printf("  overlap: frames-on / max(render-only, encode-only) = %.2f   (target <= 1.2)\n",
              on / std::max(render_only, encode_only));
  return 0;
}
