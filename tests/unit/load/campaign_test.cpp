#include <gtest/gtest.h>

#include "load/campaign.h"
#include "load/scenario.h"
#include "vault_fixture.h"

namespace sscs {
namespace {

class Campaign : public ::testing::Test {
 public:
  Sources sources;
  Diagnostics diag;
  void TearDown() override { testing::expect_examined(diag, sources); }
  std::optional<CampaignSpec> load(const std::string& text) { return load_campaign(sources.add("dir/c.yaml", text), sources, diag); }
  /// Every error message, one a line (a case may report more than one).
  std::string errors(const std::string& text) {
    load(text);
    EXPECT_TRUE(diag.has_errors()) << "expected an input error";
    std::string out;
    for (const auto& e : diag.errors()) out += e.message + "\n";
    diag = Diagnostics();
    return out;
  }
};

// The example of campaign-format.md, whole (the retrieve job's `steps: [...]` written out).
const char* kCampaignExample = R"(sscs: 1
campaign: receive-40
vault: store.yaml
set: {rows: 4}
sim:
  mode: fast
  timestep: 2 ms
  limit: 8 h
  seed: 7
record:
  trajectory: {rate: 10 Hz}
  frames: {fps: 1, width: 640, height: 360}
loads:
  - name: "In_{n}"
    type: drum
    count: 40
    attributes: {fill_mass: 180 kg}
    at: InDock.drop
    arrive: {every: 4 min, first: 0 s}
jobs:
  - name: store
    each: "In_*"
    devices: [Crane]
    slot: {from: "Row_*.top_*", choose: nearest}
    claims: [DoorZone]
    steps:
      - {move_to: {target: "{load}.top", offset: {xyz: [0, 0, 1.2]}}}
      - {move_to: {target: "{load}.top"}, path: linear}
      - {grasp: "{load}"}
      - {move_to: {target: "{slot}", offset: {xyz: [0, 0, 2.2]}}}
      - {move_to: {target: "{slot}", offset: {xyz: [0, 0, 0.9]}}, path: linear}
      - {release: {}}
  - name: retrieve
    each: "Top_1_*"
    after: 2 h
    devices: [Forklift, Crane]
    to: OutDock.drop
    steps:
      - {move_to: {target: "{load}.top"}}
      - {grasp: "{load}"}
      - {move_to: {target: "{to}"}, device: "{device}"}
      - {release: {}}
on_failure: continue
)";

TEST_F(Campaign, TheSpecExampleLoads) {
  auto c = load(kCampaignExample);
  ASSERT_TRUE(c);
  ASSERT_FALSE(diag.has_errors()) << diag.format(sources);
  EXPECT_EQ(c->name, "receive-40");
  EXPECT_EQ(c->vault_path, "dir/store.yaml");
  EXPECT_EQ(c->mode.text, "fast");
  EXPECT_EQ(c->seed.text, "7");
  EXPECT_EQ(c->limit.text, "8 h");
  ASSERT_EQ(c->loads.size(), 1u);
  const LoadStreamSpec& l = c->loads[0];
  EXPECT_EQ(l.name.text, "In_{n}");
  EXPECT_EQ(l.count.text, "40");
  EXPECT_EQ(l.at.text, "InDock.drop");
  ASSERT_EQ(l.attributes.size(), 1u);
  EXPECT_EQ(l.attributes[0].first, "fill_mass");
  EXPECT_EQ(l.arrive.kind, ArrivalSpec::Kind::Every);
  EXPECT_EQ(l.arrive.every.text, "4 min");
  ASSERT_EQ(c->jobs.size(), 2u);
  const JobSpec& store = c->jobs[0];
  EXPECT_EQ(store.name, "store");
  EXPECT_EQ(store.each.text, "In_*");
  ASSERT_TRUE(store.slot);
  EXPECT_EQ(store.slot->from.text, "Row_*.top_*");
  EXPECT_EQ(store.slot->choose.text, "nearest");
  ASSERT_EQ(store.claims.size(), 1u);
  ASSERT_EQ(store.steps.size(), 6u);
  EXPECT_FALSE(store.steps[0].device.present);  // the job's device does it
  EXPECT_EQ(std::get<MoveToSpec>(store.steps[3].action).target.ref.text, "{slot}");
  const JobSpec& retrieve = c->jobs[1];
  EXPECT_EQ(retrieve.after.text, "2 h");
  EXPECT_EQ(retrieve.to.text, "OutDock.drop");
  ASSERT_EQ(retrieve.devices.size(), 2u);
  EXPECT_EQ(retrieve.devices[1].text, "Crane");
  EXPECT_EQ(c->on_failure.text, "continue");
}

TEST_F(Campaign, ArrivalsAreOneOfEveryTimesOrRandom) {
  const std::string head = "sscs: 1\ncampaign: c\nvault: v.yaml\nloads:\n  - {name: \"D_{n}\", type: drum, count: 3, at: Dock.drop, arrive: ";
  const std::string tail = "}\njobs:\n  - {name: j, each: \"D_*\", devices: [R], steps: [{grasp: \"{load}\"}]}\n";
  for (const char* ok : {"{times: [0 s, 90 s, 200 s]}", "{random: {mean: 4 min}}", "{every: 1 min}"}) {
    auto c = load(head + ok + tail);
    EXPECT_FALSE(diag.has_errors()) << ok << ": " << diag.format(sources);
    diag = Diagnostics();
  }
  EXPECT_NE(errors(head + "{}" + tail).find("arrive needs one of every, times or random"), std::string::npos);
  EXPECT_NE(errors(head + "{every: 1 min, times: [0 s]}" + tail).find("not several"), std::string::npos);
  EXPECT_NE(errors(head + "{times: [0 s], first: 5 s}" + tail).find("'first' applies to arrive: {every"), std::string::npos);
  EXPECT_NE(errors(head + "{random: {}}" + tail).find("mean"), std::string::npos);
  EXPECT_NE(errors(head + "{evry: 1 min}" + tail).find("did you mean 'every'"), std::string::npos);
}

TEST_F(Campaign, PlaceholdersAreThoseTheJobDefines) {
  const std::string head = "sscs: 1\ncampaign: c\nvault: v.yaml\njobs:\n  - name: j\n    each: \"D_*\"\n    devices: [R]\n";
  EXPECT_NE(errors(head + "    steps: [{grasp: \"{lod}\"}]\n").find("unknown placeholder '{lod}'"), std::string::npos);
  EXPECT_NE(errors(head + "    steps: [{grasp: \"{lod}\"}]\n").find("did you mean 'load'"), std::string::npos);
  EXPECT_NE(errors(head + "    steps: [{move_to: {target: \"{slot}\"}}]\n").find("'{slot}' is not defined: job 'j' has no 'slot:'"),
            std::string::npos);
  EXPECT_NE(errors(head + "    steps: [{parallel: [{move_to: {target: \"{to}.top\"}}]}]\n").find("'{to}' is not defined"),
            std::string::npos);
  EXPECT_NE(errors(head + "    to: Out.drop\n    slot: {from: \"S_*\"}\n    steps: [{release: {}}]\n").find("both 'slot:' and 'to:'"),
            std::string::npos);
  EXPECT_NE(errors(head + "    slot: {from: \"S_*\", choose: nearst}\n    steps: [{release: {}}]\n").find("did you mean 'nearest'"),
            std::string::npos);
  // A job's step may name its device, and a template step may leave it out.
  load(head + "    to: Out.drop\n    steps: [{move_to: {target: \"{to}\"}, device: \"{device}\"}, {release: {}}]\n");
  EXPECT_FALSE(diag.has_errors()) << diag.format(sources);
}

TEST_F(Campaign, TheFileIsCheckedStrictly) {
  const std::string jobs = "jobs:\n  - {name: j, each: \"D_*\", devices: [R], steps: [{release: {}}]}\n";
  EXPECT_NE(errors("sscs: 1\ncampaign: c\nvault: v.yaml\n" + jobs + jobs.substr(0, 0) + "on_failure: halt\n").find("expected one of continue, stop"),
            std::string::npos);
  EXPECT_NE(errors("sscs: 1\ncampaign: c\nvault: v.yaml\njob:\n  - {}\n").find("did you mean 'jobs'"), std::string::npos);
  EXPECT_NE(errors("sscs: 1\ncampaign: c\nvault: v.yaml\n" + jobs + "  - {name: j, each: \"E_*\", devices: [R], steps: [{release: {}}]}\n")
                .find("duplicate job name 'j'"),
            std::string::npos);
  EXPECT_NE(errors("sscs: 1\ncampaign: c\nvault: v.yaml\njobs:\n  - {name: j, each: \"D_*\", devices: [], steps: [{release: {}}]}\n")
                .find("a non-empty list of devices"),
            std::string::npos);
  // A stream of several loads counts its names.
  const std::string stream = "loads:\n  - {name: In, type: drum, count: 40, at: Dock.drop, arrive: {every: 1 min}}\n";
  EXPECT_NE(errors("sscs: 1\ncampaign: c\nvault: v.yaml\n" + stream + jobs).find("would name them all alike"), std::string::npos);
  const std::string bad_name = "loads:\n  - {name: \"{n}_In\", type: drum, count: 2, at: Dock.drop, arrive: {every: 1 min}}\n";
  EXPECT_NE(errors("sscs: 1\ncampaign: c\nvault: v.yaml\n" + bad_name + jobs).find("must give names"), std::string::npos);
  // A scenario has no seed (its runs are not random).
  Sources s2;
  Diagnostics d2;
  load_scenario(s2.add("s.yaml", "sscs: 1\nscenario: s\nvault: v.yaml\nsim: {seed: 3}\nsteps: [{wait: 1 s}]\n"), s2, d2);
  ASSERT_TRUE(d2.has_errors());
  EXPECT_NE(d2.errors()[0].message.find("seed"), std::string::npos);
}

}  // namespace
}  // namespace sscs
