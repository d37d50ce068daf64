// The contact sheet's action camera, on the project's own runs: in every panel of the demo's arm
// run and of the reference store's crane run, the carried drum is seen, counted in pixels of
// the renderer's id pass with the panel's own camera at the panel's own moment: most of what
// the drum and its device cover is the drum in front (before, the demo's sheet hid the drum
// behind a rack upright in two panels).
#include <unistd.h>

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>

#include "pipeline/prepare.h"
#include "pipeline/run_scenario.h"
#include "render/frames.h"
#include "vault_fixture.h"

namespace sscs::testing {
namespace {

struct Panel {
  size_t step;
  std::vector<int> carried;
  std::vector<Renderer::Visibility> seen;
};

std::vector<Panel> panels_of(const std::string& scenario) {
  PreparedScenario ps;
  EXPECT_TRUE(ps.prepare(scenario, {})) << ps.diag.format(ps.sources);
  if (!ps.plan) return {};
  const Workcell& wc = *ps.wc;
  const Plan& plan = *ps.plan;
  const auto dir = std::filesystem::temp_directory_path() / fmt::format("sscs-action-camera-{}", ::getpid());
  RenderOptions ro;
  ro.width = 640;
  ro.height = 360;
  std::vector<Panel> panels;
  {
    FrameRecorder recorder(wc, ps.geometry, ps.cameras, ro, (dir / "frames").string());
    RunOptions run;
    run.work_dir = (dir / "work").string();
    run.on_step_end = [&](const PlannedStep& step, double t, const ScenePose& pose) {
      const Focus focus = step_focus(wc, plan, step, t);
      recorder.step_end(step.index, "", t, pose, focus);
      std::vector<int> carried;  // the focus' objects that are held now
      for (int o : plan_focus(wc, plan, t).objects)
        if (std::find(focus.objects.begin(), focus.objects.end(), o) != focus.objects.end()) carried.push_back(o);
      // Asked with the device drawn too, in both passes: the hook holding the drum covers part
      // of it in any view, and that is no occlusion to avoid.
      std::vector<int> asked = carried;
      asked.insert(asked.end(), focus.devices.begin(), focus.devices.end());
      std::vector<Renderer::Visibility> seen = recorder.panel_visibility(step.index, asked);
      seen.resize(carried.size());
      panels.push_back({step.index, carried, seen});
    };
    Expected<RunSummary> ran = run_simulation(wc, ps.geometry, plan, run);
    EXPECT_TRUE(ran) << ran.error();
  }
  std::filesystem::remove_all(dir);
  return panels;
}

void expect_carried_seen(const std::string& scenario, size_t min_panels_with_load) {
  const std::vector<Panel> panels = panels_of(scenario);
  size_t with_load = 0;
  for (const Panel& p : panels) {
    ASSERT_EQ(p.seen.size(), p.carried.size()) << "step " << p.step;
    for (size_t k = 0; k < p.carried.size(); ++k) {
      ++with_load;
      // In a 192 x 108 id image: the drum covers tens of pixels, and most of it is in front.
      EXPECT_GE(p.seen[k].visible, 40) << scenario << " step " << p.step + 1;
      EXPECT_GE(p.seen[k].fraction(), 0.6) << scenario << " step " << p.step + 1 << ": " << p.seen[k].visible << " of "
                                           << p.seen[k].alone << " pixels";
    }
  }
  EXPECT_GE(with_load, min_panels_with_load) << scenario << ": panels with a carried drum";
}

/// scenarios/`name` of the source tree. (A path, not string concatenation: gcc 12 at -O2 warns of
/// a memcpy out of bounds in `std::string(DIR) + "..."` once the headers are precompiled.)
std::string scenario_path(const char* name) { return (std::filesystem::path(SSCS_SOURCE_DIR) / "scenarios" / name).string(); }

TEST(ActionCamera, TheDemosCarriedDrumIsSeenInEveryPanel) {
  expect_carried_seen(scenario_path("drum-transfer/arm-loads-drum.yaml"), 5);
}

TEST(ActionCamera, TheReferenceStoresCarriedDrumIsSeenInEveryPanel) {
  expect_carried_seen(scenario_path("drum-store/store-drum.yaml"), 5);
}

}  // namespace
}  // namespace sscs::testing
