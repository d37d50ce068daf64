#pragma once
// Compiles vaults from strings against the standard library (and optional extra type folders).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "check/check.h"
#include "pipeline/compile_vault.h"
#include "load/load.h"

namespace sscs::testing {

/// Every device type of the standard library (found by reading the files, so a new device is
/// covered without editing a test), sorted.
inline std::vector<std::string> standard_devices() {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(SSCS_TEST_DATA) / "../../library/types")) {
    std::ifstream in(e.path());
    std::stringstream text;
    text << in.rdbuf();
    if (text.str().find("\nkind: device") != std::string::npos) out.push_back(e.path().stem().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// Fails the running test when `diag` holds an error or warning no assertion looked at (its
/// message compared, or shown on a failure): a diagnostic nobody checked is behaviour no test pins.
inline void expect_examined(const Diagnostics& diag, const Sources& sources) {
  if (diag.unexamined()) ADD_FAILURE() << "diagnostics no assertion looked at:\n" << diag.format(sources);
}

class VaultTest : public ::testing::Test {
 public:
  Sources sources;
  Diagnostics diag;
  CompileOptions options;

  void TearDown() override { expect_examined(diag, sources); }

  std::optional<Workcell> compile_text(const std::string& body) {
    uint32_t file = sources.add("vault.yaml", "sscs: 1\nvault: T\n" + body);
    auto spec = load_vault(file, sources, diag);
    if (!spec || diag.has_errors()) return std::nullopt;
    return compile_vault(*spec, options, sources, diag);
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
  /// A type folder holding `rx6.urdf`, the vendor URDF of tests/data/vendor (its DAE references
  /// made absolute) after `edit`, and type `rx6` of it with the lines `type_extra`.
  std::string rx6_dir(const std::function<void(std::string&)>& edit, const std::string& type_extra = "tool: {part: tool0}\n") {
    const std::string vendor = std::string(SSCS_TEST_DATA) + "/vendor/acme_rx6_support";
    std::string text;
    {
      std::ifstream in(vendor + "/urdf/rx6.urdf");
      text.assign(std::istreambuf_iterator<char>(in), {});
    }
    for (const std::string link : {"link_2", "link_3"}) {
      const std::string dae = "../meshes/visual/" + link + ".dae";  // relative to the vendor's urdf/ folder
      text.replace(text.find(dae), dae.size(), vendor + "/meshes/visual/" + link + ".dae");
    }
    edit(text);
    auto dir = std::filesystem::path(type_dir({}));
    std::ofstream(dir / "rx6.urdf") << text;
    std::ofstream(dir / "rx6.yaml") << "sscs: 1\ntype: rx6\nkind: device\nurdf: rx6.urdf\n" + type_extra;
    return dir.string();
  }
};

}  // namespace sscs::testing
