// What runs write besides their logs: edited YAML in resolved/, digests of inputs, zip bundles.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include <fmt/format.h>

#include "core/archive.h"
#include "core/digest.h"
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
  std::string error;
  EXPECT_EQ(read_zip_entry((dir / "1.zip").string(), "sub/b.csv", &error), std::string(10000, 'x'));
  EXPECT_EQ(read_zip_entry((dir / "1.zip").string(), "a.txt", &error), "alpha\n");
  EXPECT_FALSE(read_zip_entry((dir / "1.zip").string(), "missing", &error));
  EXPECT_NE(error.find("no missing in this archive"), std::string::npos) << error;
  EXPECT_LT(fs::file_size(dir / "1.zip"), 1000u);  // deflated
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sscs
