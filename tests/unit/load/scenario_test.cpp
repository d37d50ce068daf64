#include <gtest/gtest.h>

#include "load/scenario.h"
#include "vault_fixture.h"

namespace sscs {
namespace {

class Scenario : public ::testing::Test {
 public:
  Sources sources;
  Diagnostics diag;
  void TearDown() override { testing::expect_examined(diag, sources); }
  std::optional<ScenarioSpec> load(const std::string& text) {
    return load_scenario(sources.add("dir/s.yaml", text), sources, diag);
  }
  std::string first_error(const std::string& text) {
    load(text);
    EXPECT_TRUE(diag.has_errors()) << "expected an input error";
    return diag.errors().empty() ? "" : diag.errors()[0].message;
  }
};

// The example of scenario-format.md, whole.
const char* kExample = R"(sscs: 1
scenario: load-drum
vault: ../vaults/demo.yaml
set: {aisle: 1.4}
sim:
  timestep: 1 ms
  gravity: true
  limit: 120 s
record:
  trajectory: {rate: 100 Hz}
  frames: {fps: 30, width: 1280, height: 720}
cameras:
  - {t: 0, eye: [12, -8, 6], target: [0, 0, 1], fov: 50}
  - {t: 4, orbit: {target: Robot1, radius: 6, azimuth: 120, elevation: 25}, fov: 35}
steps:
  - {device: Robot1, move_joints: {j1: 30, j2: -60}, speed: 50%}
  - {device: Robot1, move_to: {target: Drum_1.top, offset: {xyz: [0, 0, 0.2], rpy: [180, 0, 0]}}, path: joint}
  - {device: Robot1, move_to: {target: Drum_1.top, offset: {rpy: [180, 0, 0]}}, path: linear, speed: 0.25 m/s}
  - {device: Robot1, grasp: Drum_1}
  - {device: Robot1, move_joints: home}
  - {device: Robot1, release: {}}
  - parallel:
      - {device: Cart1, move_joints: {x: 4}}
      - {device: Robot1, move_joints: home}
  - wait: 500 ms
)";

TEST_F(Scenario, TheSpecExampleLoads) {
  auto sc = load(kExample);
  ASSERT_TRUE(sc);
  ASSERT_FALSE(diag.has_errors()) << diag.format(sources);
  EXPECT_EQ(sc->name, "load-drum");
  EXPECT_EQ(sc->vault_path, "vaults/demo.yaml");  // relative to the scenario's folder
  ASSERT_EQ(sc->set.size(), 1u);
  EXPECT_EQ(sc->timestep.text, "1 ms");
  EXPECT_TRUE(sc->frames);
  ASSERT_EQ(sc->cameras.size(), 2u);
  EXPECT_TRUE(sc->cameras[1].orbit);
  EXPECT_EQ(sc->cameras[1].orbit_target.text, "Robot1");
  ASSERT_EQ(sc->steps.size(), 8u);
  const char* kinds[] = {"move_joints", "move_to", "move_to", "grasp", "move_joints", "release", "parallel", "wait"};
  for (size_t i = 0; i < 8; ++i) EXPECT_STREQ(sc->steps[i].kind(), kinds[i]) << i;
  const auto& m = std::get<MoveJointsSpec>(sc->steps[0].action);
  ASSERT_EQ(m.joints.size(), 2u);
  EXPECT_EQ(m.joints[1].first, "j2");
  EXPECT_EQ(sc->steps[0].speed.text, "50%");
  EXPECT_TRUE(std::get<MoveToSpec>(sc->steps[2].action).linear);
  EXPECT_EQ(std::get<MoveToSpec>(sc->steps[1].action).target.ref.text, "Drum_1.top");
  EXPECT_TRUE(std::get<MoveJointsSpec>(sc->steps[4].action).home);
  EXPECT_EQ(std::get<ParallelSpec>(sc->steps[6].action).steps.size(), 2u);
}

TEST_F(Scenario, StepsAreCheckedStrictly) {
  const std::string head = "sscs: 1\nscenario: s\nvault: v.yaml\nsteps:\n";
  EXPECT_NE(first_error(head + "  - {device: R, move_joint: {j1: 3}}\n").find("unknown step kind 'move_joint'"), std::string::npos);
  diag = Diagnostics();
  EXPECT_NE(first_error(head + "  - {device: R, grasp: D, release: {}}\n").find("one action"), std::string::npos);
  diag = Diagnostics();
  EXPECT_NE(first_error(head + "  - {grasp: D}\n").find("needs 'device'"), std::string::npos);
  diag = Diagnostics();
  EXPECT_NE(first_error(head + "  - {device: R, grasp: D, speed: 50%}\n").find("'speed' applies"), std::string::npos);
  diag = Diagnostics();
  EXPECT_NE(first_error(head + "  - {device: R, move_joints: home, path: linear}\n").find("'path' applies to move_to"),
            std::string::npos);
  diag = Diagnostics();
  EXPECT_NE(first_error(head + "  - parallel: [{parallel: [{wait: 1}]}]\n").find("cannot hold another parallel"),
            std::string::npos);
  diag = Diagnostics();
  EXPECT_NE(first_error(head + "  - {device: R, move_to: {target: D, ofset: {xyz: [0, 0, 1]}}}\n").find("did you mean 'offset'"),
            std::string::npos);
  diag = Diagnostics();
  EXPECT_NE(first_error("sscs: 1\nscenario: s\nvault: v.yaml\nsteps: []\n").find("non-empty sequence of steps"),
            std::string::npos);
  diag = Diagnostics();
  EXPECT_NE(first_error("sscs: 1\nscenario: s\nsteps:\n  - wait: 1 s\n").find("vault"), std::string::npos);
}

TEST_F(Scenario, CamerasNeedEyeAndTargetOrAnOrbit) {
  const std::string head = "sscs: 1\nscenario: s\nvault: v.yaml\nsteps: [{wait: 1 s}]\ncameras:\n";
  EXPECT_NE(first_error(head + "  - {t: 0, eye: [1, 2, 3]}\n").find("needs 'eye' and 'target'"), std::string::npos);
  diag = Diagnostics();
  EXPECT_NE(first_error(head + "  - {t: 0, eye: [1, 2, 3], orbit: {target: R, radius: 3}}\n").find("not both"), std::string::npos);
}

}  // namespace
}  // namespace sscs
