#include <gtest/gtest.h>

#include "simulate/summary_file.h"

namespace sscs {
namespace {

RunSummaryFile example() {
  RunSummaryFile f;
  f.scenario = "lift";
  f.vault = "Cell";
  f.status = "failed";
  f.simulated_time = 2.5;
  f.stopped = RunSummaryFile::Stopped{"unreachable", 1.25, "Drum_1.top is out of reach"};
  f.steps.push_back({0, "move_to", "Robot", std::nullopt, "store In_3", 0.0, 1.0, 0.25, 12.5});  // a campaign's step names its job; it ended 0.25 m short, turned 12.5 deg off
  f.steps.push_back({1, "wait", std::nullopt, std::nullopt, std::nullopt, 1.0, std::nullopt, std::nullopt, std::nullopt});
  f.devices.push_back({"Robot", {{{"j1", 30.5}, {"x", 0.2}}, 30.5, 0.2, 1.75}});
  f.min_clearance = RunSummaryFile::Clearance{0.012, "Robot.link6", "Drum_1", 0.9};
  f.events = {{"collision", 2}, {"step_start", 2}};
  f.inputs = {{"cell.yaml", "ab12"}};
  f.inputs_not_in_resolved = {"/abs/mesh.stl"};
  f.sscs_version = "0.1.0";
  return f;
}

TEST(SummaryFile, WhatIsWrittenReadsBackTheSame) {
  const std::string text = example().to_json().dump(2);
  std::string error;
  auto back = RunSummaryFile::parse(text, error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->to_json().dump(2), text);
  EXPECT_FALSE(back->cycle_time);  // null: the run stopped
  EXPECT_EQ(back->steps[1].end, std::nullopt);
  EXPECT_EQ(back->steps[0].short_by, 0.25);
  EXPECT_EQ(back->steps[1].short_by, std::nullopt);
  EXPECT_EQ(back->steps[0].turned_by, 12.5);
  EXPECT_EQ(back->steps[1].turned_by, std::nullopt);
}

TEST(SummaryFile, EveryMistypedOrMissingKeyIsNamed) {
  struct Case {
    const char* key;
    nlohmann::ordered_json value;
    const char* message;
  };
  for (const Case& c : {Case{"status", 3, "'summary.status' should be a string"},
                        Case{"devices", nlohmann::ordered_json::array(), "'summary.devices' should be an object"},
                        Case{"events", {{"collision", 1.5}}, "'events.collision' should be a count"},
                        Case{"min_clearance", {{"distance", "near"}}, "'min_clearance.distance' should be a number"},
                        Case{"steps", 7, "'summary.steps' should be an array"}}) {
    nlohmann::ordered_json j = example().to_json();
    j[c.key] = c.value;
    std::string error;
    EXPECT_FALSE(RunSummaryFile::parse(j.dump(), error)) << c.key;
    EXPECT_EQ(error, c.message) << c.key;
  }
  nlohmann::ordered_json j = example().to_json();
  j.erase("scenario");
  std::string error;
  EXPECT_FALSE(RunSummaryFile::parse(j.dump(), error));
  EXPECT_EQ(error, "'summary' has no 'scenario'");
  EXPECT_FALSE(RunSummaryFile::parse("{not json", error));
  EXPECT_EQ(error, "not JSON");
}

}  // namespace
}  // namespace sscs
