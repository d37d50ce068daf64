// What runs write besides their logs: edited YAML in resolved/, digests of inputs, zip bundles.
#include <algorithm>
#include <functional>
#include <random>
#include <sstream>

#include <nlohmann/json.hpp>

#include "report/json_writer.h"
#include "core/units.h"
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include <fmt/format.h>

#include "core/archive.h"
#include "core/digest.h"
#include "core/files.h"
#include "core/yaml_edit.h"

namespace sscs {
namespace {

namespace fs = std::filesystem;

std::string edit(const std::string& text, const std::vector<yaml::TopLevelChange>& changes) {
  Sources sources;
  Diagnostics diag;
  yaml::Document doc = yaml::parse(sources, sources.add("t.yaml", text), diag);
  EXPECT_FALSE(diag.has_errors());
  return yaml::replace_top_level(text, doc.root(), changes);
}

TEST(YamlEdit, ReplacesAKeysEntryAndKeepsEverythingElse) {
  std::string text =
      "# header\nsscs: 1\nvault: ../v.yaml   # the vault\n# about set\nset:\n  a: 1   # one\n  b: 2 m\n\n"
      "steps:\n  - {wait: 1 s}\n";
  EXPECT_EQ(edit(text, {{"vault", "vault.yaml"}, {"set", "{a: 3}"}}),
            "# header\nsscs: 1\nvault: vault.yaml\n# about set\nset: {a: 3}\n\nsteps:\n  - {wait: 1 s}\n");
}

TEST(YamlEdit, AddsMissingKeysAtTheEndAndDropsOthers) {
  EXPECT_EQ(edit("sscs: 1\nlibrary: [../lib]\nvault: V", {{"library", "[library]"}, {"standard_library", "false"}}),
            "sscs: 1\nlibrary: [library]\nvault: V\nstandard_library: false\n");
  EXPECT_EQ(edit("sscs: 1\nset: {a: 1}\nvault: V\n", {{"set", std::nullopt}}), "sscs: 1\nvault: V\n");
}

TEST(YamlEdit, FlowRootIsWrittenAgainInFlowStyle) {
  EXPECT_EQ(edit("{sscs: 1, vault: \"a b\", set: {x: 1 m}, steps: [{wait: 1}]}", {{"vault", "v.yaml"}}),
            "{sscs: 1, vault: v.yaml, set: {x: 1 m}, steps: [{wait: 1}]}\n");
}

TEST(YamlEdit, FlowScalarsQuoteOnlyWhatNeedsIt) {
  EXPECT_EQ(yaml::flow_scalar("1.5 m"), "1.5 m");
  EXPECT_EQ(yaml::flow_scalar("a, b"), "\"a, b\"");
  EXPECT_EQ(yaml::flow_scalar("x: y"), "\"x: y\"");
  EXPECT_EQ(yaml::flow_scalar("say \"hi\""), "\"say \\\"hi\\\"\"");
}

TEST(Digest, Sha256OfKnownMessages) {
  // FIPS 180-2, appendix B.1, and the empty message.
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

TEST(Archive, ZipRoundTripIsReproducible) {
  fs::path dir = fs::temp_directory_path() / fmt::format("sscs-zip-{}", ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir / "in" / "sub");
  std::ofstream(dir / "in" / "a.txt") << "alpha\n";
  std::ofstream(dir / "in" / "sub" / "b.csv") << std::string(10000, 'x');
  ASSERT_EQ(zip_folder((dir / "in").string(), (dir / "1.zip").string()), "");
  ASSERT_EQ(zip_folder((dir / "in").string(), (dir / "2.zip").string()), "");
  EXPECT_EQ(read_file_bytes((dir / "1.zip").string()), read_file_bytes((dir / "2.zip").string()));
  EXPECT_EQ(*read_zip_entry((dir / "1.zip").string(), "sub/b.csv"), std::string(10000, 'x'));
  EXPECT_EQ(*read_zip_entry((dir / "1.zip").string(), "a.txt"), "alpha\n");
  EXPECT_EQ(read_zip_entry((dir / "1.zip").string(), "missing").error(), (dir / "1.zip").string() + ": no missing in this archive");
  EXPECT_LT(fs::file_size(dir / "1.zip"), 1000u);  // deflated
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sscs

namespace sscs {
namespace {

// Property: the streaming writer's text is nlohmann's dump(2) of the same tree, for random trees
// of random strings (control characters, quotes, UTF-8), numbers (whole, tiny, huge, negative)
// and nesting, empty containers included. The report goldens rest on this.
TEST(JsonWriterProperty, WritesWhatNlohmannDumps) {
  std::mt19937_64 rng(42);
  auto random_string = [&] {
    static const std::vector<std::string> pieces = {"a", "Rack_1", " ", "\"", "\\", "\n", "\t", "\x01", "\x1b[2J", "é", "日本",
                                                    "/", "\x7f", "margin -0.6", "{", "}", ":"};
    std::string s;
    for (int n = std::uniform_int_distribution<int>(0, 5)(rng); n > 0; --n)
      s += pieces[std::uniform_int_distribution<size_t>(0, pieces.size() - 1)(rng)];
    return s;
  };
  auto random_number = [&] {
    switch (std::uniform_int_distribution<int>(0, 5)(rng)) {
      case 0: return static_cast<double>(std::uniform_int_distribution<int>(-1000, 1000)(rng));
      case 1: return std::uniform_real_distribution<double>(-1, 1)(rng) * 1e-12;
      case 2: return std::uniform_real_distribution<double>(-1, 1)(rng) * 1e20;
      case 3: return stable(std::uniform_real_distribution<double>(-100, 100)(rng));
      case 4: return 1e-9;
      default: return std::uniform_real_distribution<double>(-1e6, 1e6)(rng);
    }
  };
  std::function<void(nlohmann::ordered_json&, JsonWriter&, int)> build = [&](nlohmann::ordered_json& j, JsonWriter& w, int depth) {
    int kind = depth > 3 ? std::uniform_int_distribution<int>(0, 3)(rng) : std::uniform_int_distribution<int>(0, 5)(rng);
    switch (kind) {
      case 0: { std::string s = random_string(); j = s; w.string(s); break; }
      case 1: { double d = random_number(); j = d; w.number(d); break; }
      case 2: { int64_t n = std::uniform_int_distribution<int64_t>(-100000, 100000)(rng); j = n; w.integer(n); break; }
      case 3: { if (rng() % 2) { j = true; w.boolean(true); } else { j = nullptr; w.null(); } break; }
      case 4: {
        j = nlohmann::ordered_json::array();
        w.begin_array();
        for (int n = std::uniform_int_distribution<int>(0, 4)(rng); n > 0; --n) {
          nlohmann::ordered_json child;
          build(child, w, depth + 1);
          j.push_back(std::move(child));
        }
        w.end_array();
        break;
      }
      default: {
        j = nlohmann::ordered_json::object();
        w.begin_object();
        for (int n = std::uniform_int_distribution<int>(0, 4)(rng); n > 0; --n) {
          std::string k = "k" + std::to_string(n) + random_string();
          if (j.contains(k)) continue;
          w.key(k);
          nlohmann::ordered_json child;
          build(child, w, depth + 1);
          j[k] = std::move(child);
        }
        w.end_object();
      }
    }
  };
  for (int i = 0; i < 500; ++i) {
    std::ostringstream out;
    JsonWriter w(out);
    nlohmann::ordered_json j = nlohmann::ordered_json::object();
    w.begin_object();
    w.key("root");
    nlohmann::ordered_json child;
    build(child, w, 0);
    j["root"] = std::move(child);
    // A small tree written through json() sits at depth like the rest.
    nlohmann::ordered_json small = {{"a", {1, 2.5, "x"}}, {"b", nlohmann::ordered_json::object()}};
    w.field("small", small);
    j["small"] = small;
    w.end_object();
    ASSERT_EQ(out.str(), j.dump(2) + "\n") << "case " << i;
  }
  // Every double as nlohmann writes it: all magnitudes, whole numbers, rounded ones.
  for (int i = 0; i < 200000; ++i) {
    double v = std::ldexp(std::uniform_real_distribution<double>(-1, 1)(rng), std::uniform_int_distribution<int>(-80, 80)(rng));
    if (i % 4 == 0) v = std::round(v);
    if (i % 4 == 1) v = stable(v);
    std::string mine;
    append_json_number(mine, v);
    ASSERT_EQ(mine, nlohmann::ordered_json(v).dump()) << v;
  }
  // The fast path for rounded numbers writes what the exact one does.
  for (int i = 0; i < 200000; ++i) {
    double v = std::ldexp(std::uniform_real_distribution<double>(-1, 1)(rng), std::uniform_int_distribution<int>(-70, 70)(rng));
    if (i % 5 == 0) v = std::round(v * 1000) / 1000;
    std::string exact, fast;
    append_json_number(exact, stable(v));
    append_json_stable_number(fast, v);
    ASSERT_EQ(fast, exact) << v;
  }
  // Bytes that are no UTF-8 become U+FFFD instead of an exception.
  std::string text;
  append_json_string(text, "a\xff" "b");
  EXPECT_EQ(text, "\"a\xEF\xBF\xBD" "b\"");
}

/// The disk, but renaming `refused` fails (as across devices, or when another process holds it).
class RefusingRenames : public FileSystem {
 public:
  std::string refused;
  std::error_code rename(const std::string& from, const std::string& to) override {
    if (from == refused) return std::make_error_code(std::errc::cross_device_link);
    return FileSystem::rename(from, to);
  }
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(StagedDir, AFolderAppearsWholeOrNotAtAllAndAFailedCommitKeepsTheEarlierOutput) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("sscs-staged-{}", getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string target = (dir / "run").string();
  {
    StagedDir staged(target);
    std::ofstream(fs::path(staged.path()) / "summary.json") << "first";
    EXPECT_FALSE(fs::exists(target));  // nothing under the name until committed
    EXPECT_EQ(staged.commit(), "");
  }
  EXPECT_EQ(slurp(fs::path(target) / "summary.json"), "first");
  // A second output whose rename fails: the first stays, the staging folder goes.
  RefusingRenames disk;
  std::string staging;
  {
    StagedDir staged(target, disk);
    staging = disk.refused = staged.path();
    std::ofstream(fs::path(staged.path()) / "summary.json") << "second";
    std::string err = staged.commit();
    EXPECT_NE(err.find("cannot move the output into '" + target + "'"), std::string::npos) << err;
  }
  EXPECT_EQ(slurp(fs::path(target) / "summary.json"), "first");
  EXPECT_FALSE(fs::exists(staging));
  // Not committed (an error or an exception on the way): nothing is left, the target unchanged.
  try {
    StagedDir staged(target);
    staging = staged.path();
    std::ofstream(fs::path(staged.path()) / "summary.json") << "third";
    throw std::runtime_error("a render failed");
  } catch (const std::runtime_error&) {
  }
  EXPECT_FALSE(fs::exists(staging));
  EXPECT_EQ(slurp(fs::path(target) / "summary.json"), "first");
  // A staging folder a killed process left beside the same target is removed by the next one;
  // a live process's is not.
  const fs::path dead = dir / ".run.tmp-999999999", live = dir / fmt::format(".run.tmp-{}", getppid());
  fs::create_directories(dead);
  fs::create_directories(live);
  { StagedDir staged(target); }
  EXPECT_FALSE(fs::exists(dead));
  EXPECT_TRUE(fs::exists(live));
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir)) left.push_back(e.path().filename().string());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{live.filename().string(), "run"}));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sscs
