#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "geometry/collision.h"
#include "model/device.h"
#include "vault_fixture.h"

namespace sscs::testing {
namespace {

using Check = VaultTest;

/// A slide along x, 0..4 m, its tool `tool_z` m up: it reaches the points of that segment.
std::string slider_type(double tool_z) {
  return fmt::format("sscs: 1\ntype: slider\nkind: device\nparts:\n  - {{name: base}}\n"
                     "  - {{name: c, parent: base, joint: {{name: x, type: prismatic, axis: [1, 0, 0], limits: {{min: 0, max: 4}}}}}}\n"
                     "tool: {{part: c, xyz: [0, 0, {}]}}\n", tool_z);
}

/// One bound between two drums' heights, returning the result.
CheckResult bound_result(VaultTest& t, Workcell& keep, const std::string& lhs_h, const std::string& bound) {
  keep = t.must_compile("objects:\n  - {type: drum, name: A, height: " + lhs_h +
                        "}\n  - {type: drum, name: B, height: 1}\nconstraints:\n  - {name: c, bound: " + bound + "}\n");
  CheckReport r = check(keep, build_geometry(keep, t.diag));
  EXPECT_EQ(r.results.size(), 1u);
  return r.results.empty() ? CheckResult{} : r.results[0];
}

TEST_F(Check, RelopsAndMargins) {
  Workcell wc;
  struct Case {
    const char* lhs;
    const char* bound;
    Status status;
    double margin;
  } cases[] = {
      {"0.9", "[A.height, LT, B.height]", Status::Pass, 0.1},
      {"1", "[A.height, LT, B.height]", Status::Fail, 0.0},
      {"1", "[A.height, <, B.height]", Status::Fail, 0.0},
      {"1", "[A.height, LE, B.height]", Status::Pass, 0.0},
      {"1.2", "[A.height, GT, B.height]", Status::Pass, 0.2},
      {"1", "[A.height, \">=\", B.height]", Status::Pass, 0.0},  // YAML needs ">" quoted
      {"0.8", "[A.height, GE, B.height]", Status::Fail, -0.2},
      {"1", "[A.height, EQ, B.height]", Status::Pass, 1e-9},
      {"1.5", "[A.height, ==, B.height]", Status::Fail, 1e-9 - 0.5},
      {"0.5", "[A.height, LT, 600 mm]", Status::Pass, 0.1},
      {"0.5", "[A.height, GT, 2 ft]", Status::Fail, 0.5 - 0.6096},
  };
  for (const Case& c : cases) {
    CheckResult r = bound_result(*this, wc, c.lhs, c.bound);
    EXPECT_EQ(r.status, c.status) << c.bound << " lhs " << c.lhs;
    ASSERT_TRUE(r.margin) << c.bound;
    EXPECT_NEAR(*r.margin, c.margin, 1e-12) << c.bound << " lhs " << c.lhs;
  }
}

TEST_F(Check, ExprMarginsAreInTheFileUnitOfWhatTheyCompareAsABoundsAre) {
  // Random parameters of every dimension with a unit, compared with a literal in another unit
  // of it: the expr's margin, sides and unit equal the bound's (a yaw margin in deg, not rad).
  struct Kind {
    const char* type;
    std::vector<std::pair<const char*, double>> units;  // word, size in the file unit
  };
  const std::vector<Kind> kinds = {
      {"length", {{"m", 1}, {"mm", 1e-3}, {"cm", 1e-2}, {"ft", 0.3048}}},
      {"angle", {{"deg", 1}, {"rad", 180 / std::numbers::pi}}},
      {"mass", {{"kg", 1}, {"t", 1e3}, {"lb", 0.45359237}}},
      {"time", {{"s", 1}, {"min", 60}, {"h", 3600}}},
  };
  std::mt19937 rng(35);
  std::uniform_real_distribution<double> value(0.1, 50);
  for (int round = 0; round < 40; ++round) {
    const Kind& k = kinds[round % kinds.size()];
    const auto& [u1, s1] = k.units[rng() % k.units.size()];
    const auto& [u2, s2] = k.units[rng() % k.units.size()];
    const double x = std::round(value(rng) * 1e6) / 1e6, y = std::round(value(rng) * 1e6) / 1e6;  // as written
    const char* op = round % 2 ? "<=" : ">=";
    Workcell wc = must_compile(fmt::format(
        "parameters: {{p: {{value: {:.6f} {}, type: {}}}}}\nobjects:\n  - {{type: drum, name: A}}\n"
        "constraints:\n  - {{name: e, expr: \"p {} {:.6f} {}\"}}\n  - {{name: b, bound: [p, \"{}\", {:.6f} {}]}}\n",
        x, u1, k.type, op, y, u2, op, y, u2));
    CheckReport r = check(wc, build_geometry(wc, diag));
    ASSERT_EQ(r.results.size(), 2u);
    const CheckResult &e = r.results[0], &b = r.results[1];
    const std::string what = fmt::format("p = {} {} {} {} {}", x, u1, op, y, u2);
    EXPECT_EQ(e.status, b.status) << what;
    ASSERT_TRUE(e.margin && b.margin) << what;
    EXPECT_NEAR(*e.margin, *b.margin, 1e-9 * std::max(1.0, std::abs(*b.margin))) << what;
    EXPECT_NEAR(*e.margin, (round % 2 ? y * s2 - x * s1 : x * s1 - y * s2), 1e-9 * std::max(x * s1, y * s2)) << what;
    EXPECT_STREQ(e.margin_unit(), b.margin_unit()) << what;
    EXPECT_STRNE(e.margin_unit(), "") << what;
    ASSERT_TRUE(e.lhs && b.lhs) << what;
    EXPECT_NEAR(*e.lhs, *b.lhs, 1e-9 * std::max(1.0, std::abs(*b.lhs))) << what;
    EXPECT_NE(e.message.find(fmt::format("p = {:g} {}", x * s1, e.margin_unit())), std::string::npos) << e.message;
  }
}

TEST_F(Check, TolerancesShiftBothSides) {
  Workcell wc;
  // lhs + lhs_tol OP rhs + rhs_tol: 0.7 + 0.2 <= 1 - 0.05
  CheckResult r = bound_result(*this, wc, "0.7", "{lhs: A.height, lhs_tol: 200 mm, op: LE, rhs: B.height, rhs_tol: -0.05}");
  EXPECT_EQ(r.status, Status::Pass);
  EXPECT_NEAR(*r.margin, 0.05, 1e-12);
  EXPECT_NEAR(*r.lhs, 0.7, 1e-12);  // reported values are the operands, tolerances in the margin
  r = bound_result(*this, wc, "0.8", "{lhs: A.height, lhs_tol: 200 mm, op: LE, rhs: B.height, rhs_tol: -0.05}");
  EXPECT_EQ(r.status, Status::Fail);
  EXPECT_NEAR(*r.margin, -0.05, 1e-12);
}

TEST_F(Check, EpsilonMakesRoundingEqual) {
  Workcell wc;
  CheckResult r = bound_result(*this, wc, "\"1 + 1e-12\"", "[A.height, EQ, B.height]");
  EXPECT_EQ(r.status, Status::Pass);
  r = bound_result(*this, wc, "\"1 + 1e-12\"", "[A.height, LE, B.height]");
  EXPECT_EQ(r.status, Status::Pass);  // LE holds within eps
  r = bound_result(*this, wc, "1.004", "{lhs: A.height, op: EQ, rhs: B.height, eps: 5 mm}");
  EXPECT_EQ(r.status, Status::Pass);
  EXPECT_NEAR(*r.margin, 0.001, 1e-12);
  r = bound_result(*this, wc, "1.006", "{lhs: A.height, op: EQ, rhs: B.height, eps: 5 mm}");
  EXPECT_EQ(r.status, Status::Fail);
}

TEST_F(Check, AnglesReportInDegrees) {
  Workcell wc = must_compile(
      "objects:\n  - {type: drum, name: A, orientation: [0, 0, 30]}\n"
      "constraints:\n  - {name: c, bound: [A.orientation.yaw, LT, 45]}\n");
  CheckResult r = check(wc, build_geometry(wc, diag)).results[0];
  EXPECT_EQ(r.status, Status::Pass);
  EXPECT_NEAR(*r.lhs, 30, 1e-9);
  EXPECT_NEAR(*r.margin, 15, 1e-9);
  EXPECT_EQ(r.dim, Dim::Angle);
}

// A set's `clearance` and `no_overlap` say the margin of their nearest pair over every pair,
// whatever the broadphase met (a set with no pair within reach of the limit had no margin, and
// turned boxes whose bounds touch may be farther apart than a pair whose bounds do not): on
// random sets of turned pallets, carts and drums, the set's margin equals the smallest of the
// same pairs checked one by one, and it fails exactly when one of them does.
TEST_F(Check, ASetsMarginIsItsNearestPairsOverEveryPair) {
  std::mt19937 rng(35);
  std::uniform_real_distribution<double> where(1, 19), yaw(-180, 180), limit(0.01, 3);
  const char* kinds[] = {"pallet", "cart", "drum", "drum_30gal"};
  for (int trial = 0; trial < 25; ++trial) {
    const int n = 2 + trial % 6;
    // A few sets with every pair beyond reach of the limit; the limit as the file writes it.
    const double min = std::stod(fmt::format("{:.6f}", limit(rng) * (trial % 3 == 0 ? 0.01 : 1)));
    std::string vault = "objects:\n  - {type: room, name: Hall, length: 20 m, width: 20 m, height: 6 m}\n";
    for (int k = 0; k < n; ++k)
      vault += fmt::format("  - {{type: {}, name: O_{}, parent: Hall, location: [{:.6f}, {:.6f}, 0], orientation: [0, 0, {:.3f}]}}\n",
                           kinds[rng() % 4], k, where(rng), where(rng), yaw(rng));
    vault += fmt::format("constraints:\n  - {{name: set, clearance: {{objects: \"O_*\", min: {:.6f}}}}}\n"
                         "  - {{name: apart, no_overlap: {{objects: \"O_*\"}}}}\n", min);
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b)
        vault += fmt::format("  - {{name: p{}_{}, clearance: {{a: O_{}, b: O_{}, min: {:.6f}}}}}\n", a, b, a, b, min);
    Workcell wc = must_compile(vault);
    CheckReport rep = check(wc, build_geometry(wc, diag));
    double nearest = INFINITY;
    size_t failing = 0;
    std::vector<double> set_margins, overlap_margins;
    for (const CheckResult& r : rep.results) {
      const std::string& name = wc.constraints[r.constraint].name;
      ASSERT_TRUE(r.margin) << name << ": " << r.message;
      if (name == "set") set_margins.push_back(*r.margin);
      else if (name == "apart") overlap_margins.push_back(*r.margin);
      else {
        nearest = std::min(nearest, *r.margin);
        failing += r.status == Status::Fail;
      }
    }
    SCOPED_TRACE(vault);
    if (failing == 0) {
      ASSERT_EQ(set_margins.size(), 1u);
      EXPECT_NEAR(set_margins[0], nearest, 1e-9);
    } else {
      EXPECT_EQ(set_margins.size(), failing);
      EXPECT_NEAR(*std::min_element(set_margins.begin(), set_margins.end()), nearest, 1e-9);
    }
    // no_overlap's passing margin: the nearest distance (min 0).
    if (nearest + min > 1e-6) {
      ASSERT_EQ(overlap_margins.size(), 1u);
      EXPECT_NEAR(overlap_margins[0], nearest + min, 1e-9);
    }
  }
}

TEST_F(Check, ExprResultsCarryMargins) {
  Workcell wc = must_compile(
      "objects:\n  - {type: room, name: R, length: 10, width: 6, height: 4}\n"
      "  - {type: door, name: D, height: 2}\n"
      "constraints:\n"
      "  - {name: ternary, expr: \"R.height > 3 ? D.height == 2 : D.height < 2\"}\n"
      "  - {name: both, expr: \"R.width < R.length && D.height + 1 < R.height\"}\n"
      "  - {name: either, expr: \"R.width > R.length || deg(atan2(D.height, R.width)) < 10\"}\n");
  CheckReport rep = check(wc, build_geometry(wc, diag));
  ASSERT_EQ(rep.results.size(), 3u);
  EXPECT_EQ(rep.results[0].status, Status::Pass);
  EXPECT_FALSE(rep.results[0].margin);  // a ternary has no margin
  EXPECT_EQ(rep.results[1].status, Status::Pass);
  EXPECT_NEAR(*rep.results[1].margin, 1.0, 1e-12);  // min(10 - 6, 4 - 3)
  EXPECT_EQ(rep.results[2].status, Status::Fail);
  EXPECT_NEAR(*rep.results[2].margin, -4.0, 1e-9);  // max(6 - 10, 10 - 18.43)
  EXPECT_EQ(rep.passed, 2u);
  EXPECT_EQ(rep.failed, 1u);
}

TEST_F(Check, NumbersWithUnitsInsideExpressionsAreThoseQuantities) {
  // vault-format.md, `expr`: `turning_radius + 0.3 m`, `yaw + 90 deg`, `sum(...) <= 2 t`.
  Workcell wc = must_compile(
      "parameters:\n  gap: 0.3\nobjects:\n  - {type: room, name: R, length: 10, width: 6, height: 4}\n"
      "  - {type: door, name: D, height: \"R.height - 150 cm\", orientation: [0, 0, \"R.orientation.yaw + 90 deg\"]}\n"
      "  - {type: drum, name: D1, fill_mass: 0.25 t}\n  - {type: drum, name: D2, fill_mass: 600 lb}\n"
      "constraints:\n"
      "  - {name: mass, expr: \"sum([D1, D2].gross_mass) <= 2 t\"}\n"
      "  - {name: head, expr: \"D.height + 30 cm + gap <= R.height\"}\n"
      "  - {name: turned, expr: \"abs(D.orientation.yaw - 90 deg) < 0.5 deg\"}\n"
      "  - {name: area, expr: \"R.length * R.width >= 6000 cm * 1000 mm\"}\n");
  EXPECT_DOUBLE_EQ(value(wc, "D.height"), 2.5);
  EXPECT_NEAR(value(wc, "D.orientation.yaw"), std::numbers::pi / 2, 1e-12);
  CheckReport rep = check(wc, build_geometry(wc, diag));
  ASSERT_EQ(rep.results.size(), 4u);
  const double gross = value(wc, "D1.gross_mass") + value(wc, "D2.gross_mass");
  EXPECT_NEAR(value(wc, "D2.fill_mass"), 600 * 0.45359237, 1e-9);
  EXPECT_EQ(rep.results[0].status, gross <= 2000 ? Status::Pass : Status::Fail);
  EXPECT_NEAR(*rep.results[0].margin, 2000 - gross, 1e-9);
  EXPECT_NEAR(*rep.results[1].margin, 4 - 2.5 - 0.3 - 0.3, 1e-12);
  EXPECT_EQ(rep.results[2].status, Status::Pass);
  EXPECT_EQ(rep.results[3].status, Status::Pass);
  EXPECT_NEAR(*rep.results[3].margin, 0, 1e-9);
}

TEST_F(Check, RulesReadDoorsClearWidthsForkSpreadPayloadAndVehicleMass) {
  // Issue 35: these lived only in descriptions; rules read them as attributes.
  Workcell wc = must_compile(
      "objects:\n  - {type: room, name: R, length: 20, width: 10, height: 6}\n"
      "  - {type: door, name: D, parent: R}\n  - {type: rollup_door, name: T, parent: R, location: [5, 0, 0]}\n"
      "  - {type: forklift, name: F, parent: R, location: [10, 5, 0], fork_spread: 0.7 m}\n"
      "  - {type: arm6, name: A, parent: R, location: [3, 5, 0]}\n  - {type: agv, name: V, parent: R, location: [15, 5, 0]}\n"
      "  - {type: drum_30gal, name: K, parent: R, location: [16, 8, 0], fill_mass: 5 kg}\n"
      "constraints:\n"
      "  - {name: wheelchair, bound: [D.clear_width, GE, 32 in]}\n"
      "  - {name: truck, bound: [T.clear_width, GE, 3.5 m]}\n"
      "  - {name: pallet entries, expr: \"F.fork_spread <= 0.75 m\"}\n"
      "  - {name: arm lifts the drum, expr: \"K.gross_mass <= A.payload\"}\n"
      "  - {name: floor, expr: \"V.body_mass + V.payload <= 2 t\"}\n");
  EXPECT_NEAR(value(wc, "D.clear_width"), 0.914 - 0.044 - 0.016, 1e-12);
  EXPECT_NEAR(value(wc, "T.clear_width"), 3.658 - 0.12, 1e-12);
  CheckReport rep = check(wc, build_geometry(wc, diag));
  ASSERT_EQ(rep.results.size(), 5u);
  EXPECT_NEAR(*rep.results[0].margin, 0.854 - 32 * 0.0254, 1e-9);
  EXPECT_NEAR(*rep.results[1].margin, 3.538 - 3.5, 1e-9);
  EXPECT_NEAR(*rep.results[2].margin, 0.05, 1e-12);
  EXPECT_NEAR(*rep.results[3].margin, 20 - value(wc, "K.gross_mass"), 1e-9);
  EXPECT_NEAR(*rep.results[4].margin, 2000 - 450 - 1000, 1e-9);
  EXPECT_EQ(rep.failed, 0u);
}

TEST_F(Check, SelectorsTakeListsExclusionsAndWhatStandsAtFrames) {
  // vault-format.md: `at:FRAMEGLOB` selects what stands at those frames, `!SEL` in a list removes
  // what SEL selects, and a list works in aggregates (`sum([Drum_1, Drum_2].gross_mass)` was refused).
  Workcell wc = must_compile(
      "objects:\n  - {type: room, name: Hall, length: 30 m, width: 12 m, height: 8 m}\n"
      "  - {type: drum_rack, name: Row_1, parent: Hall, location: [2, 2, 0], levels: 2, bays: 2}\n"
      "  - {type: drum, array: {name: \"Top_{i}\", count: [6]}, at: \"Row_1.top_{i}\", fill_mass: 100 kg}\n"
      "  - {type: drum, name: Loose, parent: Hall, location: [20, 8, 0], fill_mass: 50 kg}\n"
      "  - {type: keepout_zone, name: Walkway, parent: Hall, location: [20, 1, 0]}\n"
      "constraints:\n"
      "  - {name: top drums, expr: \"count(at:Row_1.top_*) == 6\"}\n"
      "  - {name: every top, expr: \"count(at:Row_*.top_?) == 6 && sum(at:Row_1.top_*.fill_mass) == 600\"}\n"
      "  - {name: two drums, expr: \"sum([Top_1, Loose].fill_mass) == 150\"}\n"
      "  - {name: but the zone, expr: \"count([*, !type:keepout_zone, !Hall]) == 8\"}\n"
      "  - {name: quoted as in YAML, expr: 'count([\"*\", \"!type:keepout_zone\", \"!at:Row_1.top_*\"]) == 3'}\n"
      "  - {name: min of a list, expr: \"min([Top_2, Loose].fill_mass) == 50\"}\n"
      "  - {name: no overlap but the zone, no_overlap: {objects: [\"*\", \"!type:keepout_zone\"]}}\n");
  CheckReport rep = check(wc, build_geometry(wc, diag));
  for (const CheckResult& r : rep.results) EXPECT_EQ(r.status, Status::Pass) << wc.constraints[r.constraint].name << ": " << r.message;
  // The zone is left out: its selection holds every object but it.
  const auto& no_overlap = std::get<SpatialCheck>(wc.constraints.back().body);
  EXPECT_EQ(no_overlap.objects.size(), 9u);
  EXPECT_EQ(std::count(no_overlap.objects.begin(), no_overlap.objects.end(), wc.find_object("Walkway")), 0);
}

TEST_F(Check, AtSelectsWhatStandsAtAFrameByAnyNameOrByItsPlace) {
  // vault-format.md: at:FRAMEGLOB is what stands at those frames: placed `at:` one of them, or
  // resting on it (its origin there, however it was placed), and a frame has every name of its
  // place (a drum_rack's top_N is a slot_L_B_P of its top level).
  const std::string head =
      "objects:\n  - {type: room, name: Hall, length: 30 m, width: 12 m, height: 8 m}\n"
      "  - {type: drum_rack, name: Row_1, parent: Hall, location: [2, 2, 0], orientation: [0, 0, 90], levels: 2, bays: 2}\n"
      "  - {type: drum, array: {name: \"Top_{i}\", count: [6]}, at: \"Row_1.top_{i}\"}\n"
      "  - {type: drum, name: Placed, at: Row_1.slot_1_1_1}\n";
  Workcell first = must_compile(head);
  const int row = first.find_object("Row_1");
  std::vector<std::optional<Eigen::Isometry3d>> known(first.objects.size());
  const Eigen::Vector3d slot = first.pose_in_world(row, known) * first.named_frame(row, "slot_1_2_1")->translation();
  Workcell wc = must_compile(head + fmt::format("  - {{type: drum, name: ByHand, parent: Hall, location: [{:.17g}, {:.17g}, {:.17g}]}}\n"
                                                "  - {{type: drum, name: Beside, parent: Hall, location: [{:.17g}, {:.17g}, 0]}}\n",
                                                slot.x(), slot.y(), slot.z(), slot.x() + 0.002, slot.y()));
  auto names = [&](const std::string& sel) {
    std::vector<std::string> out;
    const auto found = wc.select(sel);
    EXPECT_TRUE(found) << sel;
    if (found)
      for (int o : *found) out.push_back(wc.objects[o].name);
    return out;
  };
  EXPECT_EQ(names("at:Row_1.slot_1_*"), (std::vector<std::string>{"Placed", "ByHand"}));
  EXPECT_EQ(names("at:Row_1.slot_1_2_1"), (std::vector<std::string>{"ByHand"}));
  EXPECT_EQ(names("at:Row_1.origin"), (std::vector<std::string>{}));  // the rack itself stands at none of its frames
  // Each top is a slot of the top level: selected by either name.
  for (int k = 1; k <= 6; ++k) {
    const Eigen::Vector3d top = wc.named_frame(row, fmt::format("top_{}", k))->translation();
    std::string same;
    for (const std::string& f : wc.frame_names(row))
      if (f.starts_with("slot_") && (wc.named_frame(row, f)->translation() - top).norm() < 1e-9) same = f;
    ASSERT_FALSE(same.empty()) << k;
    EXPECT_EQ(names("at:Row_1." + same), (std::vector<std::string>{fmt::format("Top_{}", k)})) << same;
  }
  EXPECT_EQ(names("at:Row_1.slot_2_*").size(), 6u);
  // A reach target may be an at: selector with `frame:`, or name the frame after it: the same targets.
  auto reach_targets = [&](const std::string& targets) {
    Workcell r = must_compile(head + "  - {type: arm6, name: Robot, parent: Hall, location: [4, 4, 0]}\n"
                                     "constraints:\n  - {name: r, reach: {device: Robot, targets: \"" + targets + "\"" +
                              (targets.ends_with(".top") ? "" : ", frame: top") + "}}\n");
    std::vector<std::string> out;
    for (const auto& t : std::get<ReachCheck>(r.constraints.at(0).body).targets) out.push_back(t.text);
    return out;
  };
  const std::vector<std::string> tops = reach_targets("at:Row_1.top_*");
  EXPECT_EQ(tops.size(), 6u);
  EXPECT_EQ(tops, reach_targets("at:Row_1.top_*.top"));
  EXPECT_EQ(tops.front(), "Top_1.top");
}

TEST_F(Check, AnUnknownObjectInASelectorListIsReportedAtItsItem) {
  EXPECT_EQ(first_error("objects:\n  - {type: drum, name: Drum_1}\n"
                        "constraints:\n  - {name: s, expr: \"sum([Drum_1, Drum_9].fill_mass) < 1\"}\n"),
            "unknown object 'Drum_9' in selector (did you mean 'Drum_1'?)");
  EXPECT_NE(diag.format(sources).find("vault.yaml:6:35: error"), std::string::npos) << diag.format(sources);  // at Drum_9
  diag = Diagnostics{};
  EXPECT_EQ(first_error("objects:\n  - {type: drum, name: Drum_1}\n"
                        "constraints:\n  - {name: s, expr: \"count(at:Rack_9.top_*) == 0\"}\n"),
            "unknown object 'Rack_9' in selector 'at:Rack_9.top_*'");
}

TEST_F(Check, WarningsAreCountedApart) {
  Workcell wc = must_compile(
      "objects:\n  - {type: drum, name: A}\n"
      "constraints:\n  - {name: w, bound: [A.height, GT, 5], severity: warning}\n");
  CheckReport rep = check(wc, build_geometry(wc, diag));
  EXPECT_EQ(rep.failed, 0u);
  EXPECT_EQ(rep.warnings, 1u);
  EXPECT_FALSE(rep.violated(false));
  EXPECT_TRUE(rep.violated(true));
}

TEST_F(Check, PluginClassesMustBeLoaded) {
  // Without --plugins no class exists: an input error at the class, not a silent pass.
  std::string msg = first_error(
      "objects:\n  - {type: drum, name: A}\n"
      "constraints:\n  - {name: p, plugin: {class: seismic_gap, attributes: [A.height]}}\n");
  EXPECT_NE(msg.find("no loaded plugin provides constraint class 'seismic_gap'"), std::string::npos) << msg;
}

TEST_F(Check, ReachResultsListUnreachableTargetsWithTheirError) {
  // A slide along x, 0..4 m, its tool 0.5 m up: it reaches points on that segment.
  options.library_dirs = {type_dir({{"slider", slider_type(0.5)}})};
  Workcell wc = must_compile(
      "objects:\n  - {type: slider, name: S}\n  - {type: drum, name: A, location: [2, 0, -0.351]}\n"
      "  - {type: drum, name: B, location: [3, 1, -0.351]}\n  - {type: drum, name: C, location: [6, 0, -0.351]}\n"
      "constraints:\n  - {name: r, reach: {device: S, targets: [A.top, B, C.top]}}\n"
      "  - {name: ok, reach: {device: S, targets: {xyz: [1, 0, 0.5]}}}\n");
  CheckReport rep = check(wc, build_geometry(wc, diag));
  ASSERT_EQ(rep.results.size(), 3u) << rep.results[0].message;
  // B's origin is 1 m off the line and 0.851 m below it; C's top 2 m beyond the end.
  EXPECT_EQ(rep.results[0].status, Status::Fail);
  EXPECT_NEAR(*rep.results[0].margin, -std::hypot(1.0, 0.851), 1e-4);
  EXPECT_NE(rep.results[0].message.find("B"), std::string::npos) << rep.results[0].message;
  EXPECT_EQ(rep.results[1].status, Status::Fail);
  EXPECT_NEAR(*rep.results[1].margin, -2.0, 1e-4);
  EXPECT_NE(rep.results[1].message.find("C.top"), std::string::npos) << rep.results[1].message;
  EXPECT_EQ(rep.results[2].status, Status::Pass);
  EXPECT_GE(*rep.results[2].margin, 0);
  EXPECT_EQ(rep.failed, 2u);
}

TEST_F(Check, AReachOffsetAndTargetTakeParametersAndExpressions) {
  // "Wherever a file gives a number ... a parameter or an expression": a reach offset of the
  // carried drum's height was refused ("a number with its unit is needed here").
  options.library_dirs = {type_dir({{"slider", slider_type(2)}})};
  Workcell wc = must_compile(
      "parameters: {lift: 1149 mm, along: 3 m}\n"
      "objects:\n  - {type: slider, name: S}\n  - {type: drum, name: A, location: [2, 0, 0]}\n"
      "constraints:\n  - {name: expr, reach: {device: S, targets: A, offset: {xyz: [0, 0, A.height + lift]}}}\n"
      "  - {name: param, reach: {device: S, targets: {xyz: [along, 0, 2 * 1 m]}}}\n"
      "  - {name: short, reach: {device: S, targets: A, offset: {xyz: [0, 0, lift]}}}\n");
  CheckReport rep = check(wc, build_geometry(wc, diag));
  ASSERT_EQ(rep.results.size(), 3u);
  EXPECT_EQ(rep.results[0].status, Status::Pass) << rep.results[0].message;  // 0.851 + 1.149 = the tool's 2 m
  EXPECT_EQ(rep.results[1].status, Status::Pass) << rep.results[1].message;
  EXPECT_EQ(rep.results[2].status, Status::Fail);  // 0.851 m short of the tool
  EXPECT_NEAR(*rep.results[2].margin, -0.851, 1e-4) << rep.results[2].message;
}

TEST_F(Check, AnUnreachableTargetsMarginIsTheClosestTheDeviceComesNotWhereASearchStopped) {
  // A bridge crane's hook travels y in [1, 9] m (span 10, hook approach 1): a target 2 m past the
  // trolley's travel is exactly 2 m from anything the hook reaches (it said 2.00015, and 27
  // identical targets of one sweep variant read 3.63509 to 3.64455).
  Workcell wc = must_compile(
      "objects:\n  - {type: bridge_crane, name: Crane}\n"
      "  - {type: drum, array: {name: \"D_{i}_{j}\", count: [3, 9], pitch: [4, 0.4, 0]}, location: [2, 10.8, 1]}\n"
      "constraints:\n  - {name: far, reach: {device: Crane, targets: [{xyz: [5, 11, 3]}, {xyz: [5, -1, 3]}, {xyz: [7.25, 12.635, 2]}]}}\n"
      "  - {name: same, reach: {device: Crane, targets: \"D_*\", frame: origin}}\n");
  CheckReport rep = check(wc, build_geometry(wc, diag));
  ASSERT_EQ(rep.results.size(), 30u);
  EXPECT_EQ(*rep.results[0].margin, -2.0);
  EXPECT_EQ(*rep.results[1].margin, -2.0);
  EXPECT_NEAR(*rep.results[2].margin, -3.635, 1e-12);
  EXPECT_EQ(rep.results[2].message, "Crane cannot reach [7.25, 12.635, 2] within its joint limits: the closest its tool comes is 3.635 m");
  // A drum j steps of 0.4 m along y from 10.8 (clear of the runway's columns): 1.8 + 0.4 (j - 1)
  // m past the travel, whatever i.
  for (size_t k = 3; k < 30; ++k) {
    const int j = static_cast<int>((k - 3) % 9) + 1;
    EXPECT_NEAR(*rep.results[k].margin, -(1.8 + 0.4 * (j - 1)), 1e-12) << rep.results[k].message;
  }
}

TEST_F(Check, AFailedReachTargetsClosestPoseIsTheOneItsMarginIsMeasuredAt) {
  // The "why can't it reach" picture draws the device at `closest`: for every standard device and
  // random targets around it, each target not reached has a pose within the joint limits whose
  // tool lies the reported error from the target, and whose parts put the tool there.
  std::mt19937_64 rng(38);
  std::uniform_real_distribution<double> u(-1, 1);
  int failed = 0;
  for (const std::string& type : standard_devices()) {
    SCOPED_TRACE(type);
    std::string targets;
    for (int i = 0; i < 6; ++i)
      targets += fmt::format("{}{{xyz: [{:.3f}, {:.3f}, {:.3f}]}}", i ? ", " : "", 30 + 6 * u(rng), 30 + 6 * u(rng), 1.5 + 1.5 * u(rng));
    diag = Diagnostics{};
    Workcell wc = must_compile("objects:\n  - {type: " + type + ", name: R, location: [30, 30, 0]}\n"
                               "constraints:\n  - {name: r, reach: {device: R, targets: [" + targets + "]}}\n");
    const GeometryModel geometry = build_geometry(wc, diag);
    const ObjectGeometry& g = geometry.objects[wc.find_object("R")];
    const Device& d = *g.device;
    for (const CheckResult& r : check(wc, geometry).results) {
      if (r.status == Status::Pass) {
        EXPECT_FALSE(r.closest);
        continue;
      }
      ++failed;
      ASSERT_TRUE(r.closest) << r.message;
      const ClosestPose& c = *r.closest;
      ASSERT_EQ(c.joints.size(), static_cast<size_t>(d.dof()));
      Eigen::VectorXd q(d.dof());
      for (int k = 0; k < d.dof(); ++k) {
        q[k] = c.joints[k].value;
        EXPECT_EQ(c.joints[k].name, d.joint(k).name);
        EXPECT_GE(q[k], d.joint(k).lower - 1e-9) << c.joints[k].name;
        EXPECT_LE(q[k], d.joint(k).upper + 1e-9) << c.joints[k].name;
      }
      ASSERT_EQ(c.parts.size(), d.parts.size());
      const std::vector<Eigen::Isometry3d> X = d.part_poses(q);
      for (size_t p = 0; p < X.size(); ++p) EXPECT_TRUE(c.parts[p].X_object_part.isApprox(X[p], 1e-12)) << c.parts[p].name;
      EXPECT_LT((c.tool - g.X_world_object * c.parts[d.tool_part].X_object_part * d.X_part_tool.translation()).norm(), 1e-9);
      // Reached only in collision: the closest free pose when one was measured (the value), else
      // the pose that reaches it and collides.
      if (r.message.find("only in collision") == std::string::npos || r.message.find("free of collision comes") != std::string::npos)
        EXPECT_NEAR((c.tool - c.target).norm(), *r.lhs, 1e-6) << r.message;
      else
        EXPECT_LT((c.tool - c.target).norm(), 0.01) << "the pose that reaches it, and collides: " << r.message;
    }
  }
  EXPECT_GT(failed, 10);
}

TEST_F(Check, ACancelledCheckStopsWithoutAResult) {
  // sscs serve and sscs lsp stop a check a newer save or edit supersedes.
  Workcell wc = must_compile("objects:\n  - {type: drum, name: A}\nconstraints:\n  - {name: c, bound: [A.height, LT, 2 m]}\n");
  const GeometryModel geometry = build_geometry(wc, diag);
  std::atomic<bool> cancel{false};
  CheckOptions options;
  options.cancel = &cancel;
  EXPECT_EQ(check(wc, geometry, options).results.size(), 1u);
  cancel = true;
  EXPECT_THROW(check(wc, geometry, options), CheckCancelled);
}

TEST_F(Check, MirrorImageReachTargetsOfAnArmFailByTheSameMargin) {
  // arm6 at [6, 6.9, 0.8], the tool pointing down at [5.43, 8.8, 1.837] and at its mirror image
  // in the arm's plane x = 6: -1.30694 and -0.48459 before (where the solver stopped).
  Workcell wc = must_compile(
      "objects:\n  - {type: arm6, name: Arm, location: [6, 6.9, 0.8]}\n"
      "constraints:\n  - {name: down, reach: {device: Arm, targets: [{xyz: [5.43, 8.8, 1.837]}, {xyz: [6.57, 8.8, 1.837]}], "
      "orientation: match, offset: {rpy: [180, 0, 0]}}}\n"
      "  - {name: free, reach: {device: Arm, targets: [{xyz: [5.43, 8.8, 1.837]}, {xyz: [6.57, 8.8, 1.837]}]}}\n");
  CheckReport rep = check(wc, build_geometry(wc, diag));
  ASSERT_EQ(rep.results.size(), 4u);
  EXPECT_NEAR(*rep.results[0].margin, *rep.results[1].margin, 1e-6);
  EXPECT_LE(*rep.results[0].margin, -0.1886 + 1e-4);
  EXPECT_GE(*rep.results[0].margin, -0.5083 - 1e-4);
  EXPECT_NEAR(*rep.results[2].margin, -0.18858, 5e-5);
  EXPECT_NEAR(*rep.results[3].margin, -0.18858, 5e-5);
}

TEST_F(Check, AReachTargetInsideTheTargetsSolidFails) {
  // The tool may touch its target, but a point inside the target's solid is reached only by a
  // tool buried in it: that was a pass. A frame on the surface passes; a container (a type with
  // `container: true`) is a space, not a solid; a block that merely is a parent is a solid.
  options.library_dirs = {type_dir({{"slider", slider_type(0.5)},
                                    {"block", "sscs: 1\ntype: block\nframes:\n  side: {xyz: [-0.2, 0, 0]}\n"
                                              "geometry:\n  - box: {size: [0.4, 0.4, 0.4]}\n"},
                                    {"bin", "sscs: 1\ntype: bin\nextends: block\ncontainer: true\n"}})};
  Workcell wc = must_compile(
      "objects:\n  - {type: slider, name: S}\n  - {type: block, name: K, location: [2, 0, 0.5]}\n"
      "  - {type: bin, name: Box, location: [3.5, 0, 0.5]}\n  - {type: drum, name: D, parent: Box, location: [0, 0, -0.1], diameter: 0.1, height: 0.1}\n"
      "  - {type: block, name: Plinth, location: [1, 1.5, 0.5]}\n  - {type: drum, name: E, parent: Plinth, location: [0, 0, 0.2], diameter: 0.1, height: 0.1}\n"
      "constraints:\n  - {name: buried, reach: {device: S, targets: [K]}}\n"
      "  - {name: surface, reach: {device: S, targets: [K.side]}}\n"
      "  - {name: container, reach: {device: S, targets: [Box]}}\n"
      "  - {name: parent, reach: {device: S, targets: [Plinth]}}\n");
  CheckReport rep = check(wc, build_geometry(wc, diag));
  ASSERT_EQ(rep.results.size(), 4u);
  EXPECT_EQ(rep.results[0].status, Status::Fail);
  EXPECT_NEAR(*rep.results[0].margin, -0.2, 1e-12);
  EXPECT_EQ(rep.results[0].message, "K lies 0.2 m inside the solid of K: a tool reaches it only buried in the object "
                                    "(aim at a frame on its surface, such as top)");
  EXPECT_EQ(rep.results[1].status, Status::Pass) << rep.results[1].message;
  EXPECT_EQ(rep.results[2].status, Status::Pass) << rep.results[2].message;
  EXPECT_EQ(rep.results[3].status, Status::Fail);  // being a parent made it a space: a pass
  EXPECT_EQ(rep.results[3].message, "Plinth lies 0.2 m inside the solid of Plinth: a tool reaches it only buried in the object "
                                    "(aim at a frame on its surface, such as top)");
}

TEST_F(Check, AReachOnlyInCollisionFailsByTheClosestFreePoseOfASlideDevice) {
  // A new user's review: a gantry setting a drum (radius 0.286 m) between two beams 0.2 m and
  // 0.25 m from the spot (a gap 0.122 m too narrow) read -0.086, the drum's depth into the nearer
  // beam, which no move of 0.086 m fixes. By hand: free when the drum clears the far side of the
  // nearer beam, 0.3 + 0.286 = 0.586 m sideways (over the beams: 0.7 m up; the other way: 0.636
  // m); less the 1 mm a contact may be. The mirror image (the beams' distances swapped) the same.
  const char* bay = "sscs: 1\ntype: bay\nattributes:\n  near: {type: length, default: 0.2}\n  far: {type: length, default: 0.25}\n"
                    "frames:\n  spot: {xyz: [0, 0, 0.05]}\ngeometry:\n  - box: {size: [2, 2, 0.05], xyz: [0, 0, 0.025]}\n"
                    "  - box: {size: [2, 0.1, 0.1], xyz: [0, \"near + 0.05\", 0.7]}\n"
                    "  - box: {size: [2, 0.1, 0.1], xyz: [0, \"-far - 0.05\", 0.7]}\n";
  options.library_dirs = {type_dir({{"bay", bay}})};
  for (const char* gaps : {"", ", near: 0.25 m, far: 0.2 m"}) {
    Workcell wc = must_compile(fmt::format(
        "objects:\n  - {{type: room, name: Cell, length: 14 m, width: 8 m, height: 5 m, location: [-7, -4, 0]}}\n"
        "  - {{type: gantry, name: Gantry, parent: Cell, location: [7, 4, 0]}}\n"
        "  - {{type: bay, name: Bay, parent: Cell, location: [10, 6, 0]{}}}\n"
        "  - {{type: drum, name: Drum_1, parent: Cell, location: [8.5, 7.5, 0]}}\n"
        "constraints:\n  - {{name: empty, reach: {{device: Gantry, targets: Bay.spot, orientation: match, "
        "offset: {{xyz: [0, 0, 0.851], rpy: [180, 0, 0]}}}}}}\n"
        "  - {{name: carrying, reach: {{device: Gantry, targets: Bay.spot, orientation: match, "
        "offset: {{xyz: [0, 0, Drum_1.height], rpy: [180, 0, 0]}}, carrying: Drum_1}}}}\n", gaps));
    CheckReport rep = check(wc, build_geometry(wc, diag));
    ASSERT_EQ(rep.results.size(), 2u);
    EXPECT_EQ(rep.results[0].status, Status::Pass) << rep.results[0].message;
    EXPECT_EQ(rep.results[1].status, Status::Fail);
    EXPECT_NEAR(*rep.results[1].margin, -0.585, 1.1e-3) << gaps << ": " << rep.results[1].message;
    EXPECT_NE(rep.results[1].message.find("Drum_1 (carried) hits Bay by 0.086 m; the closest a pose free of collision comes is 0.58"),
              std::string::npos) << rep.results[1].message;
    // The picture shows that free pose: its tool the value from the spot.
    ASSERT_TRUE(rep.results[1].closest);
    EXPECT_NEAR((rep.results[1].closest->tool - rep.results[1].closest->target).norm(), *rep.results[1].lhs, 1e-9);
  }
}

TEST_F(Check, NoReachSolutionGoesBelowTheFloorOrIntoItsTarget) {
  // A lift: a carriage on a vertical slide. A target under the floor fails: the floor is an
  // obstacle (it passed). A carriage whose finger reaches 0.1 m below the tool point sinks 0.1 m
  // into the block it reaches: the tool may touch its target (1 mm), not enter it (it passed).
  auto lift = [](const char* tool_z) {
    return fmt::format("sscs: 1\ntype: lift\nkind: device\nparts:\n  - {{name: base}}\n"
                       "  - {{name: c, parent: base, joint: {{name: z, type: prismatic, axis: [0, 0, 1], limits: {{min: -2, max: 2}}}},\n"
                       "     geometry: [{{box: {{size: [0.02, 0.02, 0.1], xyz: [0, 0, 0.05]}}}}]}}\n"
                       "tool: {{part: c, xyz: [0, 0, {}]}}\n", tool_z);
  };
  const std::string vault =
      "objects:\n  - {type: lift, name: L}\n  - {type: block, name: K, location: [0, 0, 0.3]}\n"
      "constraints:\n  - {name: top, reach: {device: L, targets: [K.top]}}\n"
      "  - {name: under, reach: {device: L, targets: {xyz: [0, 0, -0.2]}}}\n";
  const char* block = "sscs: 1\ntype: block\nframes:\n  top: {xyz: [0, 0, 0.2]}\ngeometry:\n  - box: {size: [0.4, 0.4, 0.4]}\n";
  options.library_dirs = {type_dir({{"lift", lift("0.1")}, {"block", block}})};
  Workcell wc = must_compile(vault);
  CheckReport rep = check(wc, build_geometry(wc, diag));
  ASSERT_EQ(rep.results.size(), 2u);
  EXPECT_EQ(rep.results[0].status, Status::Fail);
  const std::string message = rep.results[0].message;
  EXPECT_EQ(message.substr(0, message.find("0.099") + 5),
            "L reaches K.top only with its tool inside K: part c enters it by 0.1 m (a tool may touch its target, by 1 mm at most); "
            "the closest a pose free of collision comes is 0.099");
  // The margin is the spec's: minus the closest a free pose comes (0.1 m up, less the 1 mm a tool
  // may touch its target), not the depth (the same here, unlike a drum between two beams).
  EXPECT_NEAR(*rep.results[0].margin, -0.099, 2e-5);
  EXPECT_EQ(rep.results[1].status, Status::Fail);
  EXPECT_NE(rep.results[1].message.find("below the floor"), std::string::npos) << rep.results[1].message;
  options.library_dirs = {type_dir({{"lift", lift("0")}, {"block", block}})};
  wc = must_compile(vault);
  rep = check(wc, build_geometry(wc, diag));
  ASSERT_EQ(rep.results.size(), 2u);
  EXPECT_EQ(rep.results[0].status, Status::Pass) << rep.results[0].message;
  EXPECT_EQ(rep.results[1].status, Status::Fail);
}

TEST_F(Check, ADevicesUnmovedPartInCollisionFailsEveryTargetAtOnce) {
  // The slide's base (no joint moves it) stands 0.1 m inside a block: every pose of the carriage
  // has that collision. The search stops at once and names it (the full search named it too,
  // after 100 attempts: seconds with meshes, and a 2 s clock then turned the same input into an
  // `error` on a loaded machine; e2e.sweep_reuse under the sanitizers caught that). A target out
  // of reach says so, as before.
  options.library_dirs = {type_dir({{"slider", "sscs: 1\ntype: slider\nkind: device\n"
                                                "parts:\n  - {name: base, geometry: [{box: {size: [0.4, 0.4, 0.2], xyz: [0, 0, 0.1]}}]}\n"
                                                "  - {name: c, parent: base, joint: {name: x, type: prismatic, axis: [1, 0, 0], limits: {min: 0, max: 4}}}\n"
                                                "tool: {part: c, xyz: [0, 0, 0.5]}\n"},
                                    {"block", "sscs: 1\ntype: block\nframes:\n  top: {xyz: [0, 0, 0.4]}\n"
                                              "geometry:\n  - box: {size: [0.4, 0.4, 0.4], xyz: [0, 0, 0.2]}\n"}})};
  Workcell wc = must_compile(
      "objects:\n  - {type: slider, name: S}\n  - {type: block, name: Wall, location: [0, 0.3, 0]}\n"
      "  - {type: block, name: K, location: [2, 0, 0.1]}\n"
      "constraints:\n  - {name: r, reach: {device: S, targets: [K.top, {xyz: [9, 0, 0.5]}]}}\n");
  CheckReport rep = check(wc, build_geometry(wc, diag));
  ASSERT_EQ(rep.results.size(), 2u);
  EXPECT_EQ(rep.results[0].status, Status::Fail);
  EXPECT_EQ(rep.results[0].message, "S reaches K.top only in collision: part base hits Wall by 0.1 m");
  EXPECT_NEAR(*rep.results[0].margin, -0.1, 1e-9);
  EXPECT_EQ(rep.results[1].status, Status::Fail);
  EXPECT_EQ(rep.results[1].message, "S cannot reach [9, 0, 0.5]: it lies beyond the device's reach; the closest its tool comes is 5 m");
  // Moved clear, the same target passes: the collision was the base's, not the search's.
  wc = must_compile("objects:\n  - {type: slider, name: S}\n  - {type: block, name: Wall, location: [0, 0.8, 0]}\n"
                    "  - {type: block, name: K, location: [2, 0, 0.1]}\n"
                    "constraints:\n  - {name: r, reach: {device: S, targets: [K.top]}}\n");
  rep = check(wc, build_geometry(wc, diag));
  ASSERT_EQ(rep.results.size(), 1u);
  EXPECT_EQ(rep.results[0].status, Status::Pass) << rep.results[0].message;
}

TEST_F(Check, EveryFrameOfTheStandardTypesLiesOnOrOutsideItsSolid) {
  // So `reach` to any standard frame is not refused as buried: every named frame of every
  // standard type (and a device's tool), at its defaults, is on or outside the type's own solids.
  // (A device's parts are frames too, at their joints, inside the links: no target for a tool.)
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(std::string(SSCS_LIBRARY_DIR) + "/types"))
    names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  size_t frames = 0;
  for (const std::string& type : names) {
    diag = Diagnostics();
    auto wc = compile_text("objects:\n  - {type: " + type + ", name: X}\n");
    if (!wc) continue;  // a type with required attributes (room): no instance at its defaults
    GeometryModel g = build_geometry(*wc, diag);
    CollisionWorld world(g);
    for (const auto& [name, X] : g.objects[0].frames_world) {
      if (g.objects[0].device && g.objects[0].device->find_part(name) >= 0) continue;
      EXPECT_LE(world.depth_inside(0, X.translation()), 1e-9) << type << "." << name;
      ++frames;
    }
  }
  EXPECT_GT(frames, 10u);
}

TEST_F(Check, AnObjectAtAFrameIsComparedWithWhatItStandsOn) {
  // `at` rests an object on its parent: no_overlap compares them (a drum run through by the
  // beams of a level 0.4 m above passed: parent and child were never compared), while a rack in
  // its room (a `parent` link) and the drum in that room stay exempt.
  Workcell wc = must_compile(
      "objects:\n  - {type: room, name: Hall, length: 10, width: 10, height: 5}\n"
      "  - {type: drum_rack, name: R, parent: Hall, location: [1, 1, 0], level_height: 0.4 m}\n"
      "  - {type: drum, name: Low, at: R.slot_1_1_2}\n"
      "  - {type: wall, name: W, parent: Hall, location: [1, 5, 0], length: 6, openings: 1, opening_width: 1, opening_height: 2.2}\n"
      "  - {type: rollup_door, name: Big, at: W.opening_1}\n"
      "constraints:\n  - {name: nothing overlaps, no_overlap: {objects: \"*\"}}\n");
  CheckReport rep = check(wc, build_geometry(wc, diag));
  std::set<std::pair<std::string, std::string>> pairs;
  for (const CheckResult& r : rep.results)
    if (r.status == Status::Fail && r.subjects.size() == 2) pairs.insert({wc.objects[r.subjects[0]].name, wc.objects[r.subjects[1]].name});
  EXPECT_TRUE(pairs.count({"R", "Low"}) || pairs.count({"Low", "R"})) << rep.results.size();
  EXPECT_TRUE(pairs.count({"W", "Big"}) || pairs.count({"Big", "W"})) << rep.results.size();
  for (const auto& [a, b] : pairs) EXPECT_TRUE(a != "Hall" && b != "Hall") << a << " " << b;
  // At a level 1.27 m up and a door the opening's size, they only touch: a pass.
  wc = must_compile(
      "objects:\n  - {type: room, name: Hall, length: 10, width: 10, height: 5}\n"
      "  - {type: drum_rack, name: R, parent: Hall, location: [1, 1, 0]}\n"
      "  - {type: drum, name: Low, at: R.slot_1_1_2}\n  - {type: drum, name: Up, at: R.slot_2_1_2}\n"
      "  - {type: wall, name: W, parent: Hall, location: [1, 5, 0], length: 6, openings: 1, opening_width: Fit.width, opening_height: Fit.height,"
      " height: 5}\n"
      "  - {type: rollup_door, name: Fit, at: W.opening_1}\n"
      "constraints:\n  - {name: nothing overlaps, no_overlap: {objects: \"*\"}}\n");
  rep = check(wc, build_geometry(wc, diag));
  ASSERT_EQ(rep.results.size(), 1u);
  EXPECT_EQ(rep.results[0].status, Status::Pass) << rep.results[0].message;
}

TEST_F(Check, OnlyAContainerLeavesItsDescendantsAlone) {
  // A `parent` link to a solid is not a room: a drum parented to a rack, placed through its
  // beams, and a cart parented to a fence it stands in, overlap (both passed: the spec's "not
  // compared along the parent chain" exempted every parent). A pallet resting on the rack's
  // beams touches it (a pass), and everything stays exempt from the room it is parented to.
  Workcell wc = must_compile(
      "objects:\n  - {type: room, name: Hall, length: 10, width: 10, height: 5}\n"
      "  - {type: drum_rack, name: R, parent: Hall, location: [1, 1, 0]}\n"
      "  - {type: drum, name: Through, parent: R, location: [0.4, 0.5, 1.0]}\n"
      "  - {type: fence, name: F, parent: Hall, location: [1, 8, 0], length: 4}\n"
      "  - {type: drum, name: InFence, parent: F, location: [1, 0, 0]}\n"
      "constraints:\n  - {name: nothing overlaps, no_overlap: {objects: \"*\"}}\n");
  CheckReport rep = check(wc, build_geometry(wc, diag));
  std::set<std::set<std::string>> pairs;
  for (const CheckResult& r : rep.results)
    if (r.status == Status::Fail && r.subjects.size() == 2) pairs.insert({wc.objects[r.subjects[0]].name, wc.objects[r.subjects[1]].name});
  EXPECT_TRUE(pairs.count({"R", "Through"})) << rep.results.size();
  EXPECT_TRUE(pairs.count({"F", "InFence"})) << rep.results.size();
  for (const auto& pair : pairs) EXPECT_FALSE(pair.count("Hall")) << *pair.begin() << " " << *pair.rbegin();
  // The drum on the rack's first level (its slot frame's height, beams below it): a pass.
  std::optional<Eigen::Isometry3d> slot = wc.named_frame(wc.find_object("R"), "slot_1_1_1");
  ASSERT_TRUE(slot);
  const Eigen::Vector3d at = slot->translation();
  wc = must_compile(fmt::format(
      "objects:\n  - {{type: room, name: Hall, length: 10, width: 10, height: 5}}\n"
      "  - {{type: drum_rack, name: R, parent: Hall, location: [1, 1, 0]}}\n"
      "  - {{type: drum, name: On, parent: R, location: [{}, {}, {}]}}\n"
      "constraints:\n  - {{name: nothing overlaps, no_overlap: {{objects: \"*\"}}}}\n",
      at.x(), at.y(), at.z()));
  rep = check(wc, build_geometry(wc, diag));
  ASSERT_EQ(rep.results.size(), 1u);
  EXPECT_EQ(rep.results[0].status, Status::Pass) << rep.results[0].message;
}

TEST_F(Check, ParentingToASolidNeverChangesTheOverlapVerdict) {
  // Over every standard type as the parent (found by listing the library, so a new type is
  // covered) and a drum, a pallet and an AGV as the child, at random offsets around the parent:
  // the child `parent:`-ed to a solid gets the verdict and margin it gets standing at the same
  // world pose with no parent; only a container (a room) leaves what stands in it alone.
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> unit(0, 1);
  int solids = 0, containers = 0, overlaps = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(SSCS_LIBRARY_DIR) + "/types")) {
    const std::string type = entry.path().stem().string();
    const std::string sizes = type == "room" ? ", length: 8, width: 6, height: 4" : "";
    for (const char* child : {"drum", "us_pallet", "agv"})
      for (int k = 0; k < 3; ++k) {
        diag = Diagnostics{};
        auto parent = compile_text(fmt::format("objects:\n  - {{type: {}, name: P, location: [10, 10, 0]{}}}\n", type, sizes));
        if (!parent) break;  // a type with no defaults for what it needs (checked by LibraryProperty)
        const Eigen::AlignedBox3d box = build_geometry(*parent, diag).objects[0].bbox_world;
        const Eigen::Vector3d at = box.min() + (box.max() - box.min()).cwiseProduct(Eigen::Vector3d(unit(rng), unit(rng), unit(rng))) -
                                   Eigen::Vector3d(10, 10, 0);
        auto verdict = [&](bool parented) {
          diag = Diagnostics{};
          const Eigen::Vector3d where = parented ? at : at + Eigen::Vector3d(10, 10, 0);
          Workcell wc = must_compile(fmt::format(
              "objects:\n  - {{type: {}, name: P, location: [10, 10, 0]{}}}\n"
              "  - {{type: {}, name: C, {}location: [{:.9f}, {:.9f}, {:.9f}]}}\n"
              "constraints:\n  - {{name: apart, no_overlap: {{objects: [P, C]}}}}\n",
              type, sizes, child, parented ? "parent: P, " : "", where.x(), where.y(), where.z()));
          CheckReport rep = check(wc, build_geometry(wc, diag));
          EXPECT_EQ(rep.results.size(), 1u) << type << " / " << child;
          return rep.results.empty() ? CheckResult{} : rep.results[0];
        };
        const CheckResult alone = verdict(false), held = verdict(true);
        if (parent->types[parent->objects[0].type].container) {
          ++containers;
          EXPECT_EQ(held.status, Status::Pass) << type << " holds " << child << ": a container's inside is a space";
          continue;
        }
        ++solids;
        overlaps += alone.status == Status::Fail;
        EXPECT_EQ(held.status, alone.status) << type << " / " << child << " at " << at.transpose() << ": " << held.message << " | " << alone.message;
        if (held.margin && alone.margin) {
          EXPECT_NEAR(*held.margin, *alone.margin, 1e-6) << type << " / " << child << " at " << at.transpose();
        }
      }
  }
  EXPECT_GT(solids, 200);       // ~ 30 solid types x 3 children x 3 offsets
  EXPECT_GT(containers, 0);     // the room
  EXPECT_GT(overlaps, solids / 4);  // offsets inside the parent's bounds overlap often: the test sees failures
}

TEST_F(Check, BoundingBoxReferencesReadTheWorldGeometry) {
  // A drum on a pallet in a rotated room: bbox values are world-frame.
  Workcell wc = must_compile(
      "objects:\n  - {type: room, name: R, length: 10, width: 6, height: 4, location: [100, 0, 0], orientation: [0, 0, 90]}\n"
      "  - {type: drum, name: D, parent: R, location: [1, 2, 0.144]}\n"
      "constraints:\n  - {name: top, bound: [D.bbox.max.z, LT, 1.5]}\n"
      "  - {name: x, expr: \"D.bbox.min.x < 100\"}\n"
      "  - {name: size, bound: [D.bbox.size.y, EQ, 0.572]}\n");
  CheckReport rep = check(wc, build_geometry(wc, diag));
  ASSERT_EQ(rep.results.size(), 3u);
  EXPECT_EQ(rep.results[0].status, Status::Pass);
  EXPECT_NEAR(*rep.results[0].lhs, 0.144 + 0.851, 1e-12);
  // Room yawed 90 deg: local (1, 2) is world (100 - 2, 1); the drum spans x 98 -/+ 0.286.
  EXPECT_EQ(rep.results[1].status, Status::Pass);
  EXPECT_NEAR(*rep.results[1].lhs, 98 - 0.286, 1e-9);
  EXPECT_EQ(rep.results[2].status, Status::Pass) << rep.results[2].message;
}

TEST_F(Check, SelectorsExpandNamesGlobsAndTypes) {
  Workcell wc = must_compile(
      "objects:\n  - {type: drum, name: D1}\n  - {type: drum, name: D2}\n  - {type: pallet, name: P1}\n"
      "constraints:\n  - {name: n1, no_overlap: {objects: [\"D*\", P1]}}\n"
      "  - {name: n2, no_overlap: {objects: \"type:drum\"}}\n"
      "  - {name: n3, no_overlap: {objects: \"X*\", allow_empty: true}}\n");
  EXPECT_EQ(wc.constraints[0].subjects, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(wc.constraints[1].subjects, (std::vector<int>{0, 1}));
  EXPECT_TRUE(wc.constraints[2].subjects.empty());
}

}  // namespace
}  // namespace sscs::testing

namespace sscs::testing {
namespace {

const char* kBlock = "sscs: 1\ntype: block\nattributes:\n  sx: {type: length, default: 1}\n"
                     "geometry:\n  - box: {size: [sx, 1, 1], xyz: [\"sx/2\", 0.5, 0.5]}\n";

/// Checks a vault (with the `block` type) and keeps its workcell for the assertions.
class SpatialRules : public VaultTest {
 public:
  CheckReport check_vault(const std::string& body, const std::string& library = "") {
    options.library_dirs = {library.empty() ? type_dir({{"block", kBlock}}) : library};
    wc = must_compile(body);
    return check(wc, build_geometry(wc, diag));
  }
  Workcell wc;
  /// Each result's status as expected, and every margin but the one at `nonzero` exactly 0.
  void expect_verdicts(const CheckReport& r, const std::vector<Status>& expected, size_t nonzero) {
    ASSERT_EQ(r.results.size(), expected.size());
    for (size_t k = 0; k < expected.size(); ++k) {
      EXPECT_EQ(r.results[k].status, expected[k]) << r.results[k].message;
      if (k != nonzero) {
        EXPECT_EQ(*r.results[k].margin, 0.0) << r.results[k].message;
      }
    }
  }
};

TEST_F(SpatialRules, AClearanceExactlyAtItsMinimumHoldsWhateverTheRounding) {
  // Property: for gaps written as sums that round in binary (0.1 + 0.2 ...), a clearance whose
  // min is the gap as written passes with margin 0, and one 1 µm larger fails.
  for (const char* gap : {"0.3", "0.1 + 0.2", "0.7 - 0.4", "3 * 0.1", "1.1 - 0.8", "0.35 - 0.05"}) {
    SCOPED_TRACE(gap);
    diag = Diagnostics{};
    CheckReport r = check_vault(fmt::format(
        "parameters: {{g: 0.3}}\nobjects:\n  - {{type: block, name: A, sx: 1.1}}\n"
        "  - {{type: block, name: B, location: [\"1.1 + {0}\", 0, 0]}}\n"
        "constraints:\n  - {{name: at, clearance: {{a: A, b: B, min: \"{0}\"}}}}\n"
        "  - {{name: above, clearance: {{a: A, b: B, min: \"{0} + 0.000001\"}}}}\n", gap));
    ASSERT_EQ(r.results.size(), 2u);
    EXPECT_EQ(r.results[0].status, Status::Pass) << r.results[0].message;
    EXPECT_EQ(*r.results[0].margin, 0.0);
    EXPECT_EQ(r.results[1].status, Status::Fail);
  }
}

TEST_F(SpatialRules, ExprComparisonsHoldUpToRounding) {
  // 0.1 + 0.2 is 0.30000000000000004 in binary: sides equal up to rounding are equal, in
  // comparisons and in the margin, as in `bound`; a strict comparison of equals fails.
  CheckReport r = check_vault(
      "objects:\n  - {type: block, name: A, sx: 0.1}\n  - {type: block, name: B, sx: 0.2}\n"
      "  - {type: block, name: C, sx: 0.3}\n"
      "constraints:\n  - {name: le, expr: \"A.sx + B.sx <= C.sx\"}\n  - {name: eq, expr: \"A.sx + B.sx == C.sx\"}\n"
      "  - {name: ge, expr: \"C.sx >= A.sx + B.sx && C.sx - B.sx >= A.sx\"}\n"
      "  - {name: lt, expr: \"A.sx + B.sx < C.sx\"}\n  - {name: ne, expr: \"A.sx + B.sx != C.sx\"}\n"
      "  - {name: above, expr: \"A.sx + B.sx <= C.sx - 0.000000001\"}\n"
      // `!` turns the verdict with rounding over, not muparser's exact one.
      "  - {name: not_eq, expr: \"!(A.sx + B.sx == C.sx)\"}\n  - {name: not_lt, expr: \"!(C.sx < A.sx + B.sx)\"}\n");
  expect_verdicts(r, {Status::Pass, Status::Pass, Status::Pass, Status::Fail, Status::Fail, Status::Fail, Status::Fail,
                      Status::Pass},
                  5);
}

TEST_F(SpatialRules, NestedComparisonsHoldUpToRounding) {
  // Comparisons inside an expression (a ternary's condition, a comparison used as a value) treat
  // 0.1 + 0.2 and 0.3 as equal, as the top-level comparison does.
  CheckReport r = check_vault(
      "objects:\n  - {type: block, name: A, sx: 0.1}\n  - {type: block, name: B, sx: 0.2}\n"
      "  - {type: block, name: C, sx: 0.3}\n"
      "constraints:\n  - {name: eq_value, expr: \"(A.sx + B.sx == C.sx) == 1\"}\n"
      "  - {name: lt_cond, expr: \"(A.sx + B.sx < C.sx) ? 0 : 1\"}\n"
      "  - {name: strict_and_not, expr: \"(A.sx + B.sx > C.sx) + (A.sx + B.sx >= C.sx) + (A.sx + B.sx != C.sx) == 1\"}\n"
      "  - {name: le_cond, expr: \"(A.sx + B.sx <= C.sx ? 1 : 0) && (C.sx >= A.sx + B.sx ? 1 : 0)\"}\n"
      // A real difference still counts, however small next to the values.
      "  - {name: apart, expr: \"(A.sx + B.sx < C.sx + 0.000000001) == 1\"}\n"
      // Only the taken branch is evaluated: a guard keeps sqrt from a negative value.
      "  - {name: guard, expr: \"(A.sx - 1 > 0 ? sqrt(A.sx - 1) : 0) == 0\"}\n");
  ASSERT_EQ(r.results.size(), 6u);
  for (const CheckResult& result : r.results) EXPECT_EQ(result.status, Status::Pass) << result.message;
}

TEST_F(SpatialRules, StrictBoundsOfValuesEqualUpToRoundingFail) {
  // 0.1 + 0.2 and 0.3 are equal as written: GT and LT fail, EQ, LE and GE hold, margins 0.
  CheckReport r = check_vault(
      "objects:\n  - {type: block, name: A, location: [\"0.1 + 0.2\", 0, 0]}\n  - {type: block, name: C, location: [0.3, 0, 0]}\n"
      "constraints:\n  - {name: gt, bound: [A.location.x, GT, C.location.x]}\n"
      "  - {name: lt, bound: [C.location.x, LT, A.location.x]}\n  - {name: eq, bound: [A.location.x, EQ, C.location.x]}\n"
      "  - {name: le, bound: [A.location.x, LE, C.location.x]}\n  - {name: ge, bound: [C.location.x, GE, A.location.x]}\n"
      "  - {name: tol, bound: {lhs: 0.1, lhs_tol: 0.2, op: GT, rhs: C.location.x}}\n");
  expect_verdicts(r, {Status::Fail, Status::Fail, Status::Pass, Status::Pass, Status::Pass, Status::Fail}, 2);
}

TEST_F(SpatialRules, NonFiniteExpressionsAreErrorsNeverVerdicts) {
  // Division by zero and 0/0: no comparison of them passes or fails; each is an error result.
  CheckReport r = check_vault(
      "objects:\n  - {type: block, name: A, sx: 2}\n"
      "constraints:\n  - {name: inf, expr: \"A.sx / 0 > 1\"}\n  - {name: nan, expr: \"0/0 == 0/0\"}\n"
      "  - {name: in_and, expr: \"A.sx > 1 && A.sx / 0 < 2\"}\n  - {name: bare, expr: \"A.sx / 0\"}\n"
      "  - {name: negated, expr: \"!(sqrt(-1) > 1)\"}\n  - {name: overflow, expr: \"1e308 * 10 > 1\"}\n"
      // Inside functions, ternaries and comparisons used as values (muparser's min(x, NaN) is x).
      "  - {name: in_min, expr: \"min(A.sx, 0/0) <= 2\"}\n  - {name: in_max, expr: \"max(A.sx, 0/0) > 1\"}\n"
      "  - {name: ternary, expr: \"(sqrt(A.sx - 3) > 1) ? 0 : 1\"}\n  - {name: as_value, expr: \"(0/0 > 1) == 0\"}\n"
      "  - {name: sign, expr: \"sign(0/0) == 0\"}\n  - {name: logic, expr: \"(A.sx / 0) && 1\"}\n"
      "  - {name: fine, expr: \"A.sx / 2 == 1 && max(A.sx, 1) == 2 && (A.sx > 1 ? 1 : 0)\"}\n");
  ASSERT_EQ(r.results.size(), 13u);
  for (size_t k = 0; k < 12; ++k) EXPECT_EQ(r.results[k].status, Status::Error) << r.results[k].message;
  EXPECT_EQ(r.results[12].status, Status::Pass) << r.results[12].message;
  // The message tells an infinite value from one that is no number.
  EXPECT_NE(r.results[3].message.find("infinite"), std::string::npos) << r.results[3].message;
  EXPECT_NE(r.results[11].message.find("infinite"), std::string::npos) << r.results[11].message;
  EXPECT_NE(r.results[9].message.find("not a number"), std::string::npos) << r.results[9].message;
}

TEST_F(SpatialRules, InsideMinAndFacesMeasureTheWallsOnly) {
  // A 1 m block on the floor of a 10 x 6 x 4 room, 0.4 m from its x- wall and 2.5 m from y-.
  CheckReport r = check_vault(
      "objects:\n  - {type: room, name: R, length: 10, width: 6, height: 4}\n"
      "  - {type: block, name: B, parent: R, location: [0.4, 2.5, 0]}\n"
      "constraints:\n"
      "  - {name: all faces, inside: {objects: B, container: R}}\n"
      "  - {name: walls, inside: {objects: B, container: R, faces: walls, min: 0.3 m}}\n"
      "  - {name: walls too close, inside: {objects: B, container: R, faces: walls, min: 0.5 m}}\n"
      "  - {name: y faces, inside: {objects: B, container: R, faces: [y-, y+], min: 2 m}}\n"
      "  - {name: floor counts, inside: {objects: B, container: R, min: 0.1}}\n");
  ASSERT_EQ(r.results.size(), 5u);
  auto margin_of = [&](int k) { return r.results[k].margin.value_or(NAN); };
  EXPECT_EQ(r.results[0].status, Status::Pass);
  EXPECT_NEAR(margin_of(0), 0.0, 1e-12);  // standing on the floor
  EXPECT_EQ(r.results[1].status, Status::Pass);
  EXPECT_NEAR(margin_of(1), 0.1, 1e-12);
  EXPECT_EQ(r.results[2].status, Status::Fail);
  EXPECT_NEAR(margin_of(2), -0.1, 1e-12);
  EXPECT_NE(r.results[2].message.find("is 0.4 m from a face of R, min 0.5 m"), std::string::npos) << r.results[2].message;
  EXPECT_EQ(r.results[3].status, Status::Pass);
  EXPECT_NEAR(margin_of(3), 0.5, 1e-12);
  EXPECT_EQ(r.results[4].status, Status::Fail);  // 0 from the floor, min 0.1
  // Sticking out through a face that is not counted still fails, as sticking out.
  CheckReport ro = check_vault(
      "objects:\n  - {type: room, name: R, length: 10, width: 6, height: 4}\n"
      "  - {type: block, name: B, parent: R, location: [2, 2, 3.5]}\n"
      "constraints:\n  - {name: walls, inside: {objects: B, container: R, faces: walls}}\n");
  ASSERT_EQ(ro.results.size(), 1u);
  EXPECT_EQ(ro.results[0].status, Status::Fail);
  EXPECT_NEAR(*ro.results[0].margin, -0.5, 1e-12);
  EXPECT_NE(ro.results[0].message.find("sticks out of R by 0.5 m through its top"), std::string::npos) << ro.results[0].message;
  // The message names the face it sticks out through, the floor by that name.
  CheckReport faces = check_vault(
      "objects:\n  - {type: room, name: R, length: 10, width: 6, height: 4}\n"
      "  - {type: block, name: East, parent: R, location: [9.3, 2, 0]}\n"
      "  - {type: block, name: South, parent: R, location: [2, -0.3, 0]}\n"
      "  - {type: block, name: Sunk, parent: R, location: [5, 3, -0.25]}\n"
      "constraints:\n  - {name: in, inside: {objects: [East, South, Sunk], container: R}}\n");
  ASSERT_EQ(faces.results.size(), 3u);
  EXPECT_NE(faces.results[0].message.find("sticks out of R by 0.3 m through its x+ face"), std::string::npos) << faces.results[0].message;
  EXPECT_NE(faces.results[1].message.find("sticks out of R by 0.3 m through its y- face"), std::string::npos) << faces.results[1].message;
  EXPECT_NE(faces.results[2].message.find("sticks out of R by 0.25 m through its floor"), std::string::npos) << faces.results[2].message;
  // With a min the margin is the min further in: the message says both, so they add up.
  CheckReport with_min = check_vault(
      "objects:\n  - {type: room, name: R, length: 10, width: 6, height: 4}\n"
      "  - {type: block, name: East, parent: R, location: [9.3, 2, 0]}\n"
      "constraints:\n  - {name: in, inside: {objects: East, container: R, min: 0.5 m, faces: walls}}\n");
  ASSERT_EQ(with_min.results.size(), 1u);
  EXPECT_NEAR(*with_min.results[0].margin, -0.8, 1e-12);
  EXPECT_NE(with_min.results[0].message.find("sticks out of R by 0.3 m through its x+ face (min 0.5 m inside: margin -0.8 m)"),
            std::string::npos) << with_min.results[0].message;
}

TEST_F(SpatialRules, ClearancePairsOfSelectorsCheckEveryPairAcross) {
  CheckReport r = check_vault(
      "parameters: {gap: 0.5 m}\nobjects:\n"
      "  - type: block\n    array: {name: \"Rack_{i}\", count: [3], pitch: [2, 0, 0], skip: [[2]]}\n"
      "  - {type: block, name: Wall_1, location: [0, 1.4, 0], sx: 6}\n"
      "  - {type: block, name: Wall_2, location: [0, -1.8, 0], sx: 6}\n"
      "constraints:\n  - {name: racks off walls, clearance: {a: \"Rack_*\", b: \"Wall_*\", min: \"gap - 0.1\"}}\n");
  EXPECT_EQ(wc.find_object("Rack_2"), -1);  // skipped
  ASSERT_GE(wc.find_object("Rack_3"), 0);
  // Rack_1 and Rack_3 are 0.4 m from Wall_1 (margin 0) and 0.8 m from Wall_2: all pass.
  ASSERT_EQ(r.results.size(), 1u);
  EXPECT_EQ(r.results[0].status, Status::Pass) << r.results[0].message;
  EXPECT_NEAR(*r.results[0].margin, 0.0, 1e-12);
}

TEST_F(SpatialRules, ATolerranceEqualToTheGapHoldsAndSelectorPairsSkipTheRoom) {
  CheckReport r = check_vault(
      "parameters: {e: 1 mm}\nobjects:\n  - {type: room, name: Hall, length: 10, width: 6, height: 4}\n"
      "  - {type: drum, name: D1, parent: Hall, location: [2, 2, 0]}\n"
      "  - {type: block, name: A, parent: Hall, location: [5, 1, 0]}\n"
      "  - {type: block, name: B, parent: Hall, location: [6.428, 1, 0]}\n"
      "constraints:\n"
      "  - {name: eq at eps, bound: {lhs: D1.diameter, op: EQ, rhs: 0.573, eps: e}}\n"
      "  - {name: le at eps, bound: {lhs: D1.diameter, op: LE, rhs: 0.571, eps: 1 mm}}\n"
      "  - {name: clearance at eps, clearance: {a: A, b: B, min: 0.429 m, eps: 1 mm}}\n"
      "  - {name: drums off everything, clearance: {a: \"D*\", b: \"*\", min: 0.1}}\n");
  ASSERT_EQ(r.results.size(), 4u);
  for (const CheckResult& x : r.results) EXPECT_EQ(x.status, Status::Pass) << wc.constraints[x.constraint].name << ": " << x.message;
  EXPECT_EQ(*r.results[2].margin, 0.0);
}

TEST_F(SpatialRules, AnOpenMeshIsNoContainerAndTheMinOfNothingIsNoVerdict) {
  auto types = std::vector<std::pair<std::string, std::string>>{
      {"shell", "sscs: 1\ntype: shell\ngeometry:\n  - mesh: {file: open.obj}\n"}};
  const std::string library = type_dir(types);
  // A unit cube without its top: a surface.
  std::ofstream(std::filesystem::path(library) / "open.obj")
      << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
         "f 1 3 2\nf 1 4 3\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
  CheckReport r = check_vault(
      "objects:\n  - {type: shell, name: S}\n  - {type: drum, name: D, location: [0.5, 0.5, 0.05], diameter: 0.2, height: 0.2}\n"
      "constraints:\n  - {name: in, inside: {objects: D, container: S}}\n"
      "  - {name: empty min, expr: \"min(Zz_*.height) >= 0\", allow_empty: true}\n",
      library);
  ASSERT_EQ(r.results.size(), 2u);
  EXPECT_EQ(r.results[0].status, Status::Error);
  EXPECT_NE(r.results[0].message.find("is open (a surface, no inside)"), std::string::npos) << r.results[0].message;
  EXPECT_EQ(r.results[1].status, Status::Error);
  EXPECT_NE(r.results[1].message.find("min(Zz_*.height) is not a number"), std::string::npos) << r.results[1].message;
}

}  // namespace
}  // namespace sscs::testing

namespace sscs::testing {
namespace {

TEST_F(Check, AnArmTurnedToMatchPastADrumComesAsCloseAsAFreePoseFoundByHand) {
  // Review 20: an arm6 whose nearest poses to a target beyond a drum collide. The search over
  // free poses read 2.62 m (then 2.03 m) where a user found a free pose, tool turned as asked,
  // 1.4637 m off by hand; its mirror-image pair read 1.54 and 1.81 m. Descending through free
  // poses with all joints at once before the one-joint pattern search finds a closer pose than
  // the hand's, and brings the mirror images within millimetres of each other (not to the same
  // number: the margin stays an upper bound of the spec's there, and the message says so).
  Workcell wc = must_compile(
      "objects:\n  - {type: room, name: Hall, length: 40 m, width: 30 m, height: 12 m}\n"
      "  - {type: arm6, name: ArmN, parent: Hall, location: [28, 16, 0]}\n"
      "  - {type: drum, name: Obst, parent: Hall, location: [29.2, 16, 0]}\n"
      "  - {type: arm6, name: A, parent: Hall, location: [10, 10, 0]}\n"
      "  - {type: drum, name: D1, parent: Hall, location: [11.0, 10.9, 0]}\n"
      "  - {type: drum, name: D2, parent: Hall, location: [11.0, 9.1, 0]}\n"
      "constraints:\n"
      "  - {name: past, reach: {device: ArmN, targets: {xyz: [30.5, 16, 0.2], rpy: [180, 0, 0]}, orientation: match}}\n"
      "  - {name: hand, reach: {device: ArmN, targets: {xyz: [29.3488, 16, 1.1039], rpy: [180, 0, 0]}, orientation: match}}\n"
      "  - {name: plus, reach: {device: A, targets: {xyz: [12.2, 11.6, 0.3], rpy: [180, 0, 0]}, orientation: match}}\n"
      "  - {name: minus, reach: {device: A, targets: {xyz: [12.2, 8.4, 0.3], rpy: [180, 0, 0]}, orientation: match}}\n");
  CheckReport rep = check(wc, build_geometry(wc, diag));
  ASSERT_EQ(rep.results.size(), 4u);
  EXPECT_EQ(rep.results[1].status, Status::Pass) << rep.results[1].message;  // the hand's pose: free, and turned as asked
  const double hand = std::hypot(30.5 - 29.3488, 0.2 - 1.1039);
  for (int k : {0, 2, 3}) {
    ASSERT_EQ(rep.results[k].status, Status::Fail) << rep.results[k].message;
    ASSERT_TRUE(rep.results[k].margin);
  }
  EXPECT_GE(*rep.results[0].margin, -hand) << rep.results[0].message;
  EXPECT_NEAR(*rep.results[2].margin, *rep.results[3].margin, 0.01) << rep.results[2].message << "\n" << rep.results[3].message;
}

}  // namespace
}  // namespace sscs::testing
