// A type library kept between compiles (sscs lsp, sscs serve): reused only while its folders and
// every file it was read from are the same (on disk or in an editor's buffer), and a vault
// compiled with it checks exactly as one compiled from scratch, its type files' problems quoted
// at their lines.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "check/check.h"
#include "load/load.h"
#include "pipeline/prepare.h"

namespace sscs {
namespace {

namespace fs = std::filesystem;

class LibraryCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() / fmt::format("sscs-library-cache-{}-{}", ::getpid(), ::testing::UnitTest::GetInstance()->random_seed());
    fs::create_directories(dir / "lib/types");
    write("lib/types/crate.yaml", kCrate);
    write("v.yaml", "sscs: 1\nvault: V\nlibrary: [lib]\nobjects:\n  - {type: crate, name: C1}\n  - {type: drum, name: D1, location: [2, 0, 0]}\n"
                    "constraints:\n  - {name: crate low, bound: [C1.height, LT, 2 m]}\n");
  }
  void TearDown() override { fs::remove_all(dir); }
  void write(const std::string& name, const std::string& text) { std::ofstream(dir / name) << text; }
  std::string path(const std::string& name) const { return (dir / name).string(); }

  /// Whether the cache holds for the vault, read with `unsaved` texts.
  bool holds(const LibraryCache& cache, std::shared_ptr<const Sources::Unsaved> unsaved = nullptr) const {
    Sources s;
    s.set_unsaved(std::move(unsaved));
    cache.seed(s);
    Diagnostics d;
    auto spec = load_vault(path("v.yaml"), s, d);
    EXPECT_TRUE(spec) << d.format(s);
    return spec && cache.find(*spec, {}, s) != nullptr;
  }

  static constexpr const char* kCrate =
      "sscs: 1\ntype: crate\nattributes:\n  height: {type: length, default: 1.2}\ngeometry:\n  - box: {size: [1, 1, height], xyz: [0.5, 0.5, \"height/2\"]}\n";
  fs::path dir;
};

TEST_F(LibraryCacheTest, IsKeptWhileItsFilesAreTheSameAndDroppedWhenOneChanges) {
  LibraryCache cache;
  EXPECT_FALSE(holds(cache));  // nothing kept yet
  Sources s;
  Diagnostics d;
  PreparedVault v = prepare_vault(path("v.yaml"), {}, s, d, {}, cache);
  ASSERT_TRUE(v.wc) << d.format(s);
  EXPECT_TRUE(holds(cache));
  // The vault itself may change: the library holds.
  write("v.yaml", "sscs: 1\nvault: V\nlibrary: [lib]\nobjects:\n  - {type: crate, name: C2}\n");
  EXPECT_TRUE(holds(cache));
  // A type file's text in an editor's buffer, unsaved: not the kept one.
  auto unsaved = std::make_shared<Sources::Unsaved>();
  (*unsaved)[fs::absolute(path("lib/types/crate.yaml")).lexically_normal().string()] = std::string(kCrate) + "# edited\n";
  EXPECT_FALSE(holds(cache, unsaved));
  // The same text in the buffer as on disk: it holds.
  (*unsaved)[fs::absolute(path("lib/types/crate.yaml")).lexically_normal().string()] = kCrate;
  EXPECT_TRUE(holds(cache, unsaved));
  // A type file saved with another text, a type file added, another library folder: not.
  write("lib/types/crate.yaml", std::string(kCrate) + "description: a crate\n");
  EXPECT_FALSE(holds(cache));
  write("lib/types/crate.yaml", kCrate);
  EXPECT_TRUE(holds(cache));
  write("lib/types/box2.yaml", "sscs: 1\ntype: box2\n");
  EXPECT_FALSE(holds(cache));
  fs::remove(path("lib/types/box2.yaml"));
  EXPECT_TRUE(holds(cache));
  write("v.yaml", "sscs: 1\nvault: V\nobjects:\n  - {type: drum, name: D1}\n");  // the standard library alone
  EXPECT_FALSE(holds(cache));
}

TEST_F(LibraryCacheTest, AVaultWithPluginsKeepsNothing) {
  CompileOptions options;
  options.plugin_dirs = {dir.string()};
  LibraryCache cache;
  Sources s;
  Diagnostics d;
  PreparedVault v = prepare_vault(path("v.yaml"), options, s, d, {}, cache);
  ASSERT_TRUE(v.wc) << d.format(s);
  Sources again;
  cache.seed(again);
  EXPECT_EQ(again.size(), 1u);  // nothing seeded: nothing kept
}

TEST_F(LibraryCacheTest, ATypeFilesProblemIsQuotedAtItsLineWhenTheLibraryIsReused) {
  write("lib/types/crate.yaml", "sscs: 1\ntype: crate\nattributes:\n  height: {type: length, default: 1.2}\ngeometry:\n"
                                "  - box: {size: [1, 1, heigth], xyz: [0.5, 0.5, 0]}\n");
  LibraryCache cache;
  std::string first;
  for (int k = 0; k < 2; ++k) {
    Sources s;
    Diagnostics d;
    PreparedVault v = prepare_vault(path("v.yaml"), {}, s, d, {}, cache);
    EXPECT_FALSE(v.wc);
    const std::string told = d.format(s);
    EXPECT_NE(told.find("crate.yaml:6:"), std::string::npos) << told;
    EXPECT_NE(told.find("size: [1, 1, heigth]"), std::string::npos) << told;  // the source line quoted
    if (k == 0) first = told;
    else EXPECT_EQ(told, first);
    EXPECT_EQ(k == 0, !holds(cache) || k == 0);
  }
}

TEST(LibraryCache, TheReferenceStoreChecksTheSameWithTheKeptLibrary) {
  const std::string store = std::string(SSCS_SOURCE_DIR) + "/scenarios/drum-store/store.yaml";
  LibraryCache cache;
  std::vector<std::string> reports;
  for (int k = 0; k < 3; ++k) {  // 0: from scratch, kept; 1, 2: with the kept library
    Sources s;
    Diagnostics d;
    PreparedVault v = prepare_vault(store, {}, s, d, {}, cache);
    ASSERT_TRUE(v.wc) << d.format(s);
    std::string report;
    for (const CheckResult& r : check(*v.wc, v.geometry).results)
      report += fmt::format("{} {} {:.12g}\n", v.wc->constraints[r.constraint].name, status_name(r.status), r.margin.value_or(NAN));
    reports.push_back(report);
  }
  Sources plain;
  Diagnostics d;
  PreparedVault v = prepare_vault(store, {}, plain, d);
  ASSERT_TRUE(v.wc);
  std::string report;
  for (const CheckResult& r : check(*v.wc, v.geometry).results)
    report += fmt::format("{} {} {:.12g}\n", v.wc->constraints[r.constraint].name, status_name(r.status), r.margin.value_or(NAN));
  EXPECT_EQ(reports[0], report);
  EXPECT_EQ(reports[1], report);
  EXPECT_EQ(reports[2], report);
}

}  // namespace
}  // namespace sscs
