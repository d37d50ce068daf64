// A campaign's dispatcher (campaign-format.md, "Semantics") over random campaigns: every job
// accounted for once, a device and a claim held by one job at a time, nothing started before it
// is ready or while a device it lists sits idle with its claims free, the same seed the same plan.
#include <map>
#include <random>

#include <fmt/format.h>

#include "geometry/geometry.h"
#include "load/campaign.h"
#include "pipeline/campaign.h"
#include "simulate/dispatch.h"
#include "vault_fixture.h"

namespace sscs::testing {
namespace {

// Three gantries apart in one hall, and marks (zones: no bodies) for jobs to go over.
const char* kDispatchCell = R"(objects:
  - {type: room, name: Hall, length: 26 m, width: 8 m, height: 4 m}
  - {type: gantry, name: G1, parent: Hall, location: [0.2, 0.5, 0], x_stroke: 5 m, y_stroke: 3 m}
  - {type: gantry, name: G2, parent: Hall, location: [8.5, 0.5, 0], x_stroke: 5 m, y_stroke: 3 m}
  - {type: gantry, name: G3, parent: Hall, location: [17, 0.5, 0], x_stroke: 5 m, y_stroke: 3 m}
  - {type: keepout_zone, name: Z1, parent: Hall, location: [1, 7, 0], length: 0.2 m, width: 0.2 m, height: 0.2 m}
  - {type: keepout_zone, name: Z2, parent: Hall, location: [2, 7, 0], length: 0.2 m, width: 0.2 m, height: 0.2 m}
  - {type: keepout_zone, name: M_1, parent: Hall, location: [3, 7, 0], length: 0.1 m, width: 0.1 m, height: 0.1 m}
  - {type: keepout_zone, name: M_2, parent: Hall, location: [4, 7, 0], length: 0.1 m, width: 0.1 m, height: 0.1 m}
  - {type: keepout_zone, name: M_3, parent: Hall, location: [5, 7, 0], length: 0.1 m, width: 0.1 m, height: 0.1 m}
  - {type: keepout_zone, name: M_4, parent: Hall, location: [6, 7, 0], length: 0.1 m, width: 0.1 m, height: 0.1 m}
  - {type: keepout_zone, name: M_5, parent: Hall, location: [7, 7, 0], length: 0.1 m, width: 0.1 m, height: 0.1 m}
  - {type: keepout_zone, name: M_6, parent: Hall, location: [8, 7, 0], length: 0.1 m, width: 0.1 m, height: 0.1 m}
)";

class Dispatch : public VaultTest {
 public:
  void SetUp() override {
    wc_ = must_compile(kDispatchCell);
    geometry_ = build_geometry(wc_, diag);
  }
  /// A random campaign: one to four job templates over random marks, each with random devices,
  /// claims, readiness and moves.
  std::string random_campaign(std::mt19937& rng) {
    auto pick = [&](int n) { return static_cast<int>(rng() % n); };
    std::string text = "sscs: 1\ncampaign: random\nvault: v.yaml\nsim: {limit: 1000 s}\njobs:\n";
    const int templates = 1 + pick(4);
    for (int k = 0; k < templates; ++k) {
      std::vector<std::string> marks, devices, claims;
      for (int m = 1; m <= 6; ++m)
        if (pick(2)) marks.push_back(fmt::format("M_{}", m));
      if (marks.empty()) marks.push_back(fmt::format("M_{}", 1 + pick(6)));
      for (const char* d : {"G1", "G2", "G3"})
        if (pick(2)) devices.push_back(d);
      if (devices.empty()) devices.push_back(fmt::format("G{}", 1 + pick(3)));
      std::shuffle(devices.begin(), devices.end(), rng);
      for (const char* z : {"Z1", "Z2"})
        if (pick(3) == 0) claims.push_back(z);
      text += fmt::format("  - name: t{}\n    each: \"[{}]\"\n    after: {} s\n    devices: [{}]\n", k, fmt::join(marks, ", "), pick(3) * 2,
                          fmt::join(devices, ", "));
      if (!claims.empty()) text += fmt::format("    claims: [{}]\n", fmt::join(claims, ", "));
      // (A wait last: the device is the job's until it ends, though no motion of it shows that.)
      text += fmt::format("    steps:\n      - {{move_joints: {{x: {} m}}}}\n      - {{wait: {} s}}\n      - {{move_joints: {{x: 0 m}}}}\n"
                          "      - {{wait: {} s}}\n",
                          0.5 + pick(9) * 0.5, pick(3), pick(3));
    }
    return text;
  }
  std::optional<Plan> plan(const std::string& text, CampaignCommands* out = nullptr) {
    uint32_t f = sources.add("c.yaml", text);
    spec_ = load_campaign(f, sources, diag);
    EXPECT_TRUE(spec_ && !diag.has_errors()) << diag.format(sources) << text;
    if (!spec_ || diag.has_errors()) return std::nullopt;
    auto commands = compile_campaign(*spec_, wc_, geometry_, diag);
    EXPECT_TRUE(commands) << diag.format(sources) << text;
    if (!commands) return std::nullopt;
    if (out) *out = *commands;
    return plan_campaign(*commands, wc_, geometry_, diag);
  }
  Workcell wc_;
  GeometryModel geometry_;
  std::optional<CampaignSpec> spec_;
};

TEST_F(Dispatch, RandomCampaignsKeepTheQueueClaimsAndDevicesRules) {
  std::mt19937 rng(37);
  for (int round = 0; round < 60; ++round) {
    const std::string text = random_campaign(rng);
    CampaignCommands c;
    std::optional<Plan> p = plan(text, &c);
    ASSERT_TRUE(p) << diag.format(sources) << text;
    // Every job once, every one started (nothing fails, the limit is far), its steps its own.
    ASSERT_EQ(p->jobs.size(), c.jobs.size()) << text;
    std::map<std::pair<std::string, int>, int> seen;
    for (const PlannedJob& j : p->jobs) {
      EXPECT_EQ(++seen[std::make_pair(j.name, j.object)], 1) << text;
      EXPECT_TRUE(j.started) << j.name << " " << wc_.objects[j.object].name << ": " << j.why_not << "\n" << text;
    }
    for (size_t i = 0; i < p->jobs.size(); ++i) {
      const PlannedJob& a = p->jobs[i];
      const JobTemplate& ta = c.templates[c.jobs[i].job_template];
      EXPECT_GE(a.start, a.ready - 1e-12) << text;
      EXPECT_NE(std::find(ta.devices.begin(), ta.devices.end(), a.device), ta.devices.end()) << text;
      double first = INFINITY, last = -INFINITY;
      for (const PlannedStep& ps : p->steps)
        if (ps.job == static_cast<int>(i)) {
          first = std::min(first, ps.start);
          last = std::max(last, ps.end);
          if (ps.device >= 0) {
            EXPECT_EQ(ps.device, a.device) << text;
          }
        }
      EXPECT_NEAR(first, a.start, 1e-9) << text;
      EXPECT_NEAR(last, a.end, 1e-9) << text;
      // One job at a time on a device and on a claim.
      for (size_t k = i + 1; k < p->jobs.size(); ++k) {
        const PlannedJob& b = p->jobs[k];
        const JobTemplate& tb = c.templates[c.jobs[k].job_template];
        const bool overlap = a.start < b.end - 1e-9 && b.start < a.end - 1e-9;
        if (!overlap) continue;
        EXPECT_NE(a.device, b.device) << text;
        for (int z : ta.claims) EXPECT_EQ(std::count(tb.claims.begin(), tb.claims.end(), z), 0) << text;
      }
      // Nothing waits for no reason: at its ready time (when it did not start then) each device
      // it lists is busy with another job, or a claim of its is held, or a job before it in the
      // queue that this device could take was waiting too.
      if (a.start > a.ready + 1e-9) {
        const double t = a.ready;
        for (int d : ta.devices) {
          bool reason = false;
          for (size_t k = 0; k < p->jobs.size(); ++k) {
            const PlannedJob& b = p->jobs[k];
            if (k == i) continue;
            const bool running = b.start <= t + 1e-9 && t < b.end - 1e-9;
            if (running && b.device == d) reason = true;
            if (running)
              for (int z : c.templates[c.jobs[k].job_template].claims)
                reason = reason || std::count(ta.claims.begin(), ta.claims.end(), z) > 0;
            if (k < i && b.ready <= t + 1e-9 && b.start >= t - 1e-9 && b.device == d) reason = true;  // ahead in the queue
          }
          EXPECT_TRUE(reason) << a.name << " " << wc_.objects[a.object].name << " waited from " << a.ready << " to " << a.start
                              << " while " << wc_.objects[d].name << " was idle\n" << text;
        }
      }
    }
    // The same campaign, the same plan.
    std::optional<Plan> again = plan(text);
    ASSERT_TRUE(again);
    ASSERT_EQ(again->jobs.size(), p->jobs.size());
    for (size_t i = 0; i < p->jobs.size(); ++i) {
      EXPECT_EQ(again->jobs[i].device, p->jobs[i].device);
      EXPECT_EQ(again->jobs[i].start, p->jobs[i].start);
    }
  }
}

}  // namespace
}  // namespace sscs::testing
