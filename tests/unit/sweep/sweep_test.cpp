// Sweeps: expanding variants (grid, random, units, ranges), metrics against hand counts, the
// progress text, and results tables.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "load/sweep.h"
#include "sweep/dealer.h"
#include "sweep/metrics.h"
#include "sweep/progress.h"
#include "sweep/results.h"
#include "sweep/variants.h"
#include "vault_fixture.h"

namespace sscs {
namespace {

TEST(Dealer, EachWorkerWalksItsOwnStretchThenSplitsTheLongestLeft) {
  Dealer d(10, 2);
  // Worker 0 starts at 0, worker 1 at 5; each goes on from where it was.
  EXPECT_EQ(d.next(0), 0u);
  EXPECT_EQ(d.next(1), 5u);
  EXPECT_EQ(d.next(1), 6u);
  EXPECT_EQ(d.next(1), 7u);
  EXPECT_EQ(d.next(1), 8u);
  EXPECT_EQ(d.next(1), 9u);
  // Worker 1's stretch is done: it takes the middle of the longest left (1..4), from 3 on.
  EXPECT_EQ(d.next(1), 3u);
  EXPECT_EQ(d.next(0), 1u);
  EXPECT_EQ(d.next(1), 4u);
  EXPECT_EQ(d.next(0), 2u);
  EXPECT_EQ(d.left(), 0u);
  EXPECT_EQ(d.next(0), std::nullopt);
  EXPECT_EQ(d.next(1), std::nullopt);
}

TEST(Dealer, EveryTaskOnceWhateverTheOrderOfAsking) {
  for (size_t workers : {1u, 2u, 3u, 7u})
    for (size_t tasks : {0u, 1u, 2u, 5u, 100u}) {
      Dealer d(tasks, workers);
      std::multiset<size_t> got;
      uint64_t state = 12345;
      for (std::optional<size_t> t; ;) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        if (!(t = d.next(static_cast<size_t>(state >> 33) % workers))) break;
        got.insert(*t);
      }
      ASSERT_EQ(got.size(), tasks) << workers << " workers";
      for (size_t k = 0; k < tasks; ++k) EXPECT_EQ(got.count(k), 1u) << k;
    }
}

class SweepTest : public ::testing::Test {
 public:
  Sources sources;
  Diagnostics diag;
  void TearDown() override { testing::expect_examined(diag, sources); }

  std::optional<SweepSpec> spec_of(const std::string& body) {
    uint32_t file = sources.add("study/sweep.yaml", "sscs: 1\nsweep: s\nvault: v.yaml\n" + body);
    return load_sweep(file, sources, diag);
  }
  VariantSet expand(const std::string& body) {
    spec = spec_of(body);
    EXPECT_TRUE(spec && !diag.has_errors()) << diag.format(sources);
    auto set = spec ? expand_variants(*spec, diag) : std::nullopt;
    EXPECT_TRUE(set) << diag.format(sources);
    return set ? std::move(*set) : VariantSet{};
  }
  std::string first_error(const std::string& body) {
    diag = Diagnostics();
    spec = spec_of(body);
    if (spec && !diag.has_errors()) expand_variants(*spec, diag);
    EXPECT_TRUE(diag.has_errors());
    return diag.errors().empty() ? "" : diag.errors()[0].message;
  }
  std::optional<SweepSpec> spec;
};

TEST(SweepRange, EndIncludedWhenOnAStepDespiteRounding) {
  // 1.0 + 10 * 0.1 is 2.0000000000000004 in binary; the end is included and printed as 2.
  auto v = range_values(1.0, 2.0, 0.1);
  ASSERT_EQ(v.size(), 11u);
  EXPECT_EQ(v[3], 1.3);
  EXPECT_EQ(v.back(), 2.0);
  EXPECT_EQ(range_values(0, 1, 0.3).size(), 4u);  // 0, 0.3, 0.6, 0.9: 1 is not on a step
  EXPECT_EQ(range_values(5, 5, 1).size(), 1u);
}

TEST_F(SweepTest, GridIsEveryCombinationLastEntryFastest) {
  VariantSet set = expand("vary:\n  aisle: {from: 1.0 m, to: 2.0 m, step: 0.5 m}\n  rows: {values: [3, 4]}\n");
  ASSERT_EQ(set.variants.size(), 6u);
  ASSERT_EQ(set.axes.size(), 2u);
  EXPECT_EQ(set.axes[0].dim, Dim::Length);
  std::vector<std::string> seen;
  for (const Variant& v : set.variants) seen.push_back(set.value(v, 0).set_text + "/" + set.value(v, 1).set_text);
  EXPECT_EQ(seen, (std::vector<std::string>{"1 m/3", "1 m/4", "1.5 m/3", "1.5 m/4", "2 m/3", "2 m/4"}));
  EXPECT_EQ(set.folder(set.variants[3]), "3-aisle=1.5m-rows=4");
  EXPECT_EQ(set.value(set.variants[3], 0).column, "1.5");
}

TEST_F(SweepTest, UnitsConvertToTheFirstUnitsDimension) {
  VariantSet set = expand("vary:\n  aisle: {from: 1000 mm, to: 2 m, step: 50 cm}\n");
  ASSERT_EQ(set.variants.size(), 3u);
  EXPECT_DOUBLE_EQ(set.axes[0].values[1].si, 1.5);
  EXPECT_EQ(set.axes[0].values[1].set_text, "1.5 m");  // in the file unit, as --set takes it
  VariantSet angles = expand("vary:\n  yaw: {from: 0 deg, to: 90 deg, step: 45}\n");
  ASSERT_EQ(angles.variants.size(), 3u);  // a plain step is in the ends' unit (degrees)
  EXPECT_EQ(angles.axes[0].values[2].set_text, "90 deg");
  // A plain step takes the unit written on the ends, whatever that unit is (not the file unit).
  VariantSet mm = expand("vary:\n  gap: {from: 100 mm, to: 300 mm, step: 100}\n");
  ASSERT_EQ(mm.variants.size(), 3u);
  EXPECT_DOUBLE_EQ(mm.axes[0].values[1].si, 0.2);
  EXPECT_EQ(mm.axes[0].values[2].set_text, "0.3 m");
  // Plain ends with a step in a unit: the ends are in that unit too.
  VariantSet ft = expand("vary:\n  gap: {from: 1, to: 3, step: 1 ft}\n");
  ASSERT_EQ(ft.variants.size(), 3u);
  EXPECT_NEAR(ft.axes[0].values[2].si, 3 * 0.3048, 1e-12);
}

TEST_F(SweepTest, FolderNamesAreStableAndPadded) {
  VariantSet set = expand("vary:\n  n: {from: 1, to: 12, step: 1}\n  kind: {values: [\"a b\", x/y]}\n");
  ASSERT_EQ(set.variants.size(), 24u);
  EXPECT_EQ(set.folder(set.variants[0]), "00-n=1-kind=ab");
  EXPECT_EQ(set.folder(set.variants[23]), "23-n=12-kind=x_y");
}

TEST_F(SweepTest, RandomDrawsDistinctGridPointsDeterministically) {
  std::string body = "vary:\n  a: {from: 0, to: 99, step: 1}\n  b: {from: 0, to: 99, step: 1}\nmode: {random: {n: 25, seed: 7}}\n";
  VariantSet one = expand(body), two = expand(body);
  ASSERT_EQ(one.variants.size(), 25u);
  std::set<std::pair<uint32_t, uint32_t>> points;
  uint64_t previous = 0;
  for (size_t i = 0; i < one.variants.size(); ++i) {
    const Variant& v = one.variants[i];
    EXPECT_EQ(v.index, i);
    EXPECT_EQ(v.choice, two.variants[i].choice);  // the same seed draws the same points
    points.insert({v.choice[0], v.choice[1]});
    uint64_t g = v.choice[0] * 100ull + v.choice[1];
    if (i) {
      EXPECT_GT(g, previous);  // listed in grid order
    }
    previous = g;
  }
  EXPECT_EQ(points.size(), 25u);
  VariantSet other = expand("vary:\n  a: {from: 0, to: 99, step: 1}\n  b: {from: 0, to: 99, step: 1}\nmode: {random: {n: 25, seed: 8}}\n");
  bool differs = false;
  for (size_t i = 0; i < 25; ++i) differs |= other.variants[i].choice != one.variants[i].choice;
  EXPECT_TRUE(differs);
}

TEST_F(SweepTest, BadRangesAndModesSayWhere) {
  EXPECT_EQ(first_error("vary:\n  a: {from: 1 m, to: 2 kg, step: 0.1 m}\n"),
            "'2 kg' is a mass, but '1 m' is a length: the range of 'a' mixes dimensions");
  EXPECT_EQ(first_error("vary:\n  a: {from: 2, to: 1, step: 0.1}\n"), "the range of 'a' ends ('1') before it starts ('2')");
  EXPECT_EQ(first_error("vary:\n  a: {from: 1, to: 2, step: 0}\n"), "the step of 'a' must be greater than 0, found '0'");
  EXPECT_EQ(first_error("vary:\n  a: {values: [1, 2]}\nmode: {random: {n: 3, seed: 1}}\n"),
            "random n = 3 is more than the 2 variants of the grid; use mode: grid");
  EXPECT_EQ(first_error("vary:\n  a: {values: [1, 1]}\n"), "'1' is listed twice in the values of 'a'");
  EXPECT_EQ(first_error("vary:\n  a: {from: 1, to: 2}\n"), "vary 'a' is missing the required key 'step'");
  EXPECT_EQ(diag.errors()[0].mark.line, 5u);  // the entry of 'a'
}

class MetricTest : public testing::VaultTest {};

TEST_F(MetricTest, CountsSumsAndMarginsMatchHandCounts) {
  Workcell wc = must_compile(
      "parameters:\n  rows: {value: 3, type: integer}\nobjects:\n"
      "  - {type: rack, array: {name: \"R_{i}\", count: [rows], pitch: [3, 0, 0]}, levels: 4}\n"
      "  - {type: drum, name: D1}\n  - {type: drum, name: D2, location: [0, 5, 0]}\n"
      "constraints:\n  - {name: short, bound: [D1.height, LE, 2 m]}\n  - {name: tall, bound: [D2.height, GE, 1 m]}\n");
  GeometryModel g = build_geometry(wc, diag);
  CheckReport report = check(wc, g);
  auto eval = [&](const std::string& text) {
    MetricSpec spec;
    spec.name = "m";
    spec.expr.text = text;
    auto m = Metric::parse(spec, diag);
    EXPECT_TRUE(m) << diag.format(sources);
    Diagnostics check_diag;
    m->validate(wc, false, false, check_diag);
    EXPECT_FALSE(check_diag.has_errors()) << check_diag.format(sources);
    Expected<double> v = m->evaluate(wc, g, report, nullptr);
    EXPECT_TRUE(v) << v.error();
    return v ? *v : NAN;
  };
  EXPECT_EQ(eval("count(type:rack)"), 3);
  EXPECT_EQ(eval("count(type:drum) + count(R_*)"), 5);
  EXPECT_EQ(eval("4 * sum(type:rack.levels)"), 48);
  EXPECT_EQ(eval("count(D1)"), 1);
  double height = value(wc, "D1.height");
  EXPECT_NEAR(eval("margin(short)"), 2 - height, 1e-12);
  EXPECT_NEAR(eval("margin(tall)"), height - 1, 1e-12);
  EXPECT_NEAR(eval("min_margin()"), std::min(2 - height, height - 1), 1e-12);
  EXPECT_EQ(eval("rows * 10 + passed"), 30.0 + static_cast<double>(report.passed));
  // min, max, avg over a selection (one implementation with expr constraints); min(a, b) stays a function.
  EXPECT_EQ(eval("min(type:rack.levels) + max(type:rack.levels)"), 8);
  EXPECT_EQ(eval("avg(type:rack.levels)"), 4);
  EXPECT_EQ(eval("min(2, 3) + max(count(R_*), 1)"), 5);
  // Selecting nothing: count is 0; the others are undefined, an empty cell with the reason.
  EXPECT_EQ(eval("count(Nothing_*)"), 0);
  MetricSpec spec;
  spec.name = "m";
  spec.expr.text = "sum(Nothing_*.levels)";
  auto m = Metric::parse(spec, diag);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->evaluate(wc, g, report, nullptr).error(), "metric 'm': sum(Nothing_*.levels) selects no object in this variant");
  // A value that is not finite is no value: an empty cell with the reason, never a silent one.
  spec.expr.text = "1 / (count(type:rack) - 3)";
  m = Metric::parse(spec, diag);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->evaluate(wc, g, report, nullptr).error(), "metric 'm' is infinite in this variant (a division by zero?)");
}

TEST_F(MetricTest, UnknownNamesAreInputErrors) {
  Workcell wc = must_compile("objects:\n  - {type: drum, name: D1}\nconstraints:\n  - {name: short, bound: [D1.height, LE, 2 m]}\n");
  auto errors_of = [&](const std::string& text, bool simulated = false) {
    MetricSpec spec;
    spec.name = "m";
    spec.expr.text = text;
    Diagnostics d;
    auto m = Metric::parse(spec, d);
    if (m) m->validate(wc, simulated, false, d);
    return d.errors().empty() ? std::string() : d.errors()[0].message;
  };
  EXPECT_EQ(errors_of("margin(shrot)"), "metric 'm': vault 'T' has no constraint 'shrot' (did you mean 'short'?)");
  EXPECT_EQ(errors_of("count(type:drun)"), "metric 'm': unknown type 'drun' (did you mean 'drum'?)");
  EXPECT_EQ(errors_of("sum(type:drum.hieght)"), "metric 'm': no type has an attribute 'hieght'");
  EXPECT_EQ(errors_of("cycle_time"), "metric 'm' reads 'cycle_time', which only a simulated sweep has (add scenario:)");
  EXPECT_EQ(errors_of("cycle_time", true), "");
  EXPECT_EQ(errors_of("count(type:drum"), "metric 'm': '(' of count() is never closed");
  EXPECT_EQ(errors_of("sum(D1)"), "metric 'm': sum() needs SELECTOR.attribute, as sum(type:drum.fill_mass), found 'D1'");
  EXPECT_EQ(errors_of("max(type:drum.bbox.max.w)"), "metric 'm': expected bbox.min|max|size.x|y|z in reference 'D1.bbox.max.w'");
  EXPECT_EQ(errors_of("max(type:drum.bbox.max.y) + 2 kg"),
            "metric 'm': the two sides of '+' differ in dimension: 'max(type:drum.bbox.max.y)' is a length, '2 kg' is a mass "
            "in 'max(type:drum.bbox.max.y) + 2 kg'");
  EXPECT_EQ(errors_of("cycle_time > 2 m", true),
            "metric 'm': the two sides of '>' differ in dimension: 'cycle_time' is a time, '2 m' is a length in 'cycle_time > 2 m'");
  EXPECT_EQ(errors_of("cycle_time / (1 min) + count(type:drum)", true), "");
}

// One reading of `SELECTOR.member` for sweep metrics and vault expressions (issue 35: a metric
// `max(Shelf_*.bbox.max.y)` was refused that an `expr` took): every aggregate of every member
// over every selector form gives the metric the value the vault's check computes.
TEST_F(MetricTest, AggregatesReadWhatAVaultExpressionReads) {
  const std::vector<std::string> aggregates = {"sum", "min", "max", "avg"};
  const std::vector<std::string> members = {"height", "location.x", "location.y", "bbox.max.y", "bbox.min.z", "bbox.size.x"};
  const std::vector<std::string> selectors = {"type:rack", "R_*", "[R_1, D1]", "[\"*\", \"!type:drum\"]", "D2", "[D1, D2]"};
  std::string vault =
      "objects:\n  - {type: room, name: Hall, length: 30 m, width: 20 m, height: 6 m}\n"
      "  - {type: rack, array: {name: \"R_{i}\", count: [3], pitch: [2.5, 0, 0]}, parent: Hall, location: [1, 2, 0], levels: 3}\n"
      "  - {type: drum, name: D1, parent: Hall, location: [4, 9.5, 0]}\n"
      "  - {type: drum, name: D2, parent: Hall, location: [7.25, 12, 0.5], orientation: [0, 0, 30]}\nconstraints:\n";
  std::vector<std::string> calls;
  for (const std::string& a : aggregates)
    for (const std::string& m : members)
      for (const std::string& sel : selectors) {
        calls.push_back(fmt::format("{}({}.{})", a, sel, m));
        vault += fmt::format("  - {{name: c{}, expr: '{} <= 1000'}}\n", calls.size() - 1, calls.back());
      }
  Workcell wc = must_compile(vault);
  GeometryModel g = build_geometry(wc, diag);
  CheckReport report = check(wc, g);
  ASSERT_EQ(report.results.size(), calls.size());
  for (size_t k = 0; k < calls.size(); ++k) {
    MetricSpec spec;
    spec.name = "m";
    spec.expr.text = calls[k];
    Diagnostics d;
    auto m = Metric::parse(spec, d);
    ASSERT_TRUE(m) << d.format(sources);
    m->validate(wc, false, false, d);
    ASSERT_FALSE(d.has_errors()) << calls[k] << ": " << d.format(sources);
    Expected<double> v = m->evaluate(wc, g, report, nullptr);
    ASSERT_TRUE(v) << calls[k] << ": " << v.error();
    const CheckResult& r = report.results[k];
    ASSERT_TRUE(r.margin) << calls[k];
    EXPECT_NEAR(*v, 1000 - *r.margin, 1e-9) << calls[k];
  }
}

TEST(SweepProgress, RateAndEta) {
  EXPECT_EQ(progress_text(0, 500, 0), "0/500 variants");
  EXPECT_EQ(progress_text(100, 500, 4), "100/500 variants, 25/s, ETA 16 s");
  EXPECT_EQ(progress_text(3, 10, 2), "3/10 variants, 1.5/s, ETA 5 s");
  EXPECT_EQ(progress_text(10, 10, 2), "10/10 variants, 5/s");
  EXPECT_EQ(human_duration(200), "3 min 20 s");
  EXPECT_EQ(human_duration(7500), "2 h 05 min");
}

TEST(SweepResults, CsvQuotesAndLeavesUndefinedEmpty) {
  TableHeader h;
  h.sweep = "s";
  h.parameters = {{"aisle", "m"}, {"kind", ""}};
  h.metrics = {"capacity"};
  VariantRow r;
  r.index = 0;
  r.folder = "0-aisle=1m-kind=a_b";
  r.values = {"1", "a,b"};
  r.status = "error";
  r.metrics = {std::nullopt};
  r.message = "said \"no\"";
  EXPECT_EQ(results_csv(h, {r}),
            "variant,folder,aisle,kind,status,passed,failed,warnings,capacity,message\n"
            "0,0-aisle=1m-kind=a_b,1,\"a,b\",error,0,0,0,,\"said \"\"no\"\"\"\n");
  std::string error;
  r.metrics = {1.0 / 3};
  EXPECT_NE(result_json(r, h).find("\"capacity\": 0.333333333333"), std::string::npos);
}

}  // namespace
}  // namespace sscs
