#pragma once
// Compiles vaults from strings against the standard library (and optional extra type folders).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "check/check.h"
#include "compile/compile.h"
#include "load/load.h"

namespace sscs::testing {

class VaultTest : public ::testing::Test {
 public:
  Sources sources;
  Diagnostics diag;
  CompileOptions options;

  std::optional<Workcell> compile_text(const std::string& body) {
    uint32_t file = sources.add("vault.yaml", "sscs: 1\nvault: T\n" + body);
    auto spec = load_vault(file, sources, diag);
    if (!spec || diag.has_errors()) return std::nullopt;
    return compile(*spec, options, sources, diag);
  }
  Workcell must_compile(const std::string& body) {
    auto wc = compile_text(body);
    EXPECT_TRUE(wc) << diag.format(sources);
    return wc ? std::move(*wc) : Workcell{};
  }
  /// The first error message, for tests of bad input.
  std::string first_error(const std::string& body) {
    auto wc = compile_text(body);
    EXPECT_FALSE(wc) << "expected an input error";
    return diag.errors().empty() ? "" : diag.errors()[0].message;
  }
  double value(const Workcell& wc, const std::string& ref) {
    auto dot = ref.find('.');
    int o = wc.find_object(ref.substr(0, dot));
    EXPECT_GE(o, 0) << ref;
    if (o < 0) return NAN;
    const Object& obj = wc.objects[o];
    std::string member = ref.substr(dot + 1);
    static const char* kPose[] = {"location.x", "location.y", "location.z", "orientation.roll", "orientation.pitch",
                                  "orientation.yaw"};
    for (int k = 0; k < 6; ++k)
      if (member == kPose[k]) return wc.values[obj.first_slot + k];
    int a = wc.types[obj.type].find_attribute(member);
    EXPECT_GE(a, 0) << ref;
    return wc.values[obj.first_slot + kFirstAttributeSlot + a];
  }
  /// A folder of type files for one test.
  std::string type_dir(const std::vector<std::pair<std::string, std::string>>& files) {
    auto dir = std::filesystem::temp_directory_path() /
               ("sscs_types_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    for (const auto& [name, text] : files) std::ofstream(dir / (name + ".yaml")) << text;
    return dir.string();
  }
};

}  // namespace sscs::testing
