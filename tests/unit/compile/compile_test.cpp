#include <cctype>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "vault_fixture.h"

namespace sscs::testing {
namespace {

using Compile = VaultTest;

TEST_F(Compile, UnitsConvertToSiAndDefaultsApply) {
  Workcell wc = must_compile(
      "objects:\n"
      "  - {type: room, name: R, length: 30 ft, width: 5000 mm, height: 4, orientation: [0, 0, 90]}\n"
      "  - {type: drum, name: D}\n");
  EXPECT_NEAR(value(wc, "R.length"), 9.144, 1e-12);
  EXPECT_NEAR(value(wc, "R.width"), 5.0, 1e-12);
  EXPECT_NEAR(value(wc, "R.orientation.yaw"), std::numbers::pi / 2, 1e-12);  // plain angles are degrees
  EXPECT_NEAR(value(wc, "D.diameter"), 0.572, 1e-12);
  EXPECT_NEAR(value(wc, "D.height"), 0.851, 1e-12);
}

TEST_F(Compile, ExpressionsEvaluateInDependencyOrder) {
  // C depends on B which depends on A, written in reverse order.
  Workcell wc = must_compile(
      "parameters:\n  gap: 250 mm\n  double_gap: \"2 * gap\"\n"
      "objects:\n"
      "  - {type: drum, name: C, location: [\"B.location.x + double_gap\", 0, 0]}\n"
      "  - {type: drum, name: B, location: [\"A.location.x + A.diameter\", 0, 0], height: \"A.height * 2\"}\n"
      "  - {type: drum, name: A, location: [1, 0, 0], diameter: 0.6}\n");
  EXPECT_NEAR(value(wc, "B.location.x"), 1.6, 1e-12);
  EXPECT_NEAR(value(wc, "C.location.x"), 2.1, 1e-12);
  EXPECT_NEAR(value(wc, "B.height"), 1.702, 1e-12);
}

TEST_F(Compile, CyclesAreReportedWithTheirPath) {
  std::string msg = first_error(
      "objects:\n"
      "  - {type: drum, name: A, height: \"B.height\"}\n"
      "  - {type: drum, name: B, height: \"C.height\"}\n"
      "  - {type: drum, name: C, height: \"A.height + 1\"}\n");
  EXPECT_EQ(msg, "values depend on each other in a cycle: A.height -> B.height -> C.height -> A.height");
}

TEST_F(Compile, ParametersAndOverrides) {
  const std::string body =
      "parameters:\n  aisle: 1.5 m\n  rows: {value: 4, type: integer, min: 1, max: 40}\n"
      "objects:\n  - type: drum\n    array: {name: \"D{i}\", count: [rows], pitch: [\"0.6 + aisle\", 0, 0]}\n";
  Workcell wc = must_compile(body);
  EXPECT_EQ(wc.objects.size(), 4u);
  EXPECT_NEAR(value(wc, "D4.location.x"), 3 * 2.1, 1e-12);
  options.overrides = {{"aisle", "500 mm"}, {"rows", "2"}};
  Workcell wc2 = must_compile(body);
  EXPECT_EQ(wc2.objects.size(), 2u);
  EXPECT_NEAR(value(wc2, "D2.location.x"), 1.1, 1e-12);
  options.overrides = {{"rows", "41"}};
  EXPECT_EQ(first_error(body), "parameter 'rows' is 41, above its max 40 (from --set rows=41)");
}

TEST_F(Compile, ArraysExpandNamesAndLocations) {
  Workcell wc = must_compile(
      "objects:\n  - {type: room, name: R, length: 20, width: 20, height: 5}\n"
      "  - type: rack\n    parent: R\n    location: [2, 1, 0]\n"
      "    array: {name: \"Rack_{i}_{j}\", count: [2, 3], pitch: [3, 1.2, 0]}\n"
      "    levels: \"i + j\"\n");
  ASSERT_EQ(wc.objects.size(), 7u);
  EXPECT_EQ(wc.objects[1].name, "Rack_1_1");
  EXPECT_EQ(wc.objects[6].name, "Rack_2_3");
  EXPECT_NEAR(value(wc, "Rack_2_3.location.x"), 5.0, 1e-12);
  EXPECT_NEAR(value(wc, "Rack_2_3.location.y"), 1 + 2 * 1.2, 1e-12);
  EXPECT_EQ(value(wc, "Rack_2_3.levels"), 5);  // i and j are usable in member expressions
  EXPECT_EQ(wc.objects[wc.find_object("Rack_1_2")].parent, 0);
}

TEST_F(Compile, ArrayNamesMustStayUnique) {
  std::string msg = first_error(
      "objects:\n  - type: drum\n    array: {name: \"D{i}\", count: [2, 2]}\n");
  EXPECT_EQ(msg, "object name 'D1' is used twice (first at line 5)");
}

TEST_F(Compile, InheritanceMergesAndOverridesAttributes) {
  options.library_dirs = {type_dir({
      {"base_box", "sscs: 1\ntype: base_box\nattributes:\n  size: {type: length, default: 1, min: 0.5}\n"
                   "  label: {type: string, default: none}\n"},
      {"big_box", "sscs: 1\ntype: big_box\nextends: base_box\nattributes:\n  size: {type: length, default: 3}\n"
                  "  count: {type: integer, default: \"size * 2\"}\n"},
  })};
  Workcell wc = must_compile("objects:\n  - {type: big_box, name: B}\n  - {type: base_box, name: S, label: small}\n");
  const Object& b = wc.objects[wc.find_object("B")];
  const ObjectType& t = wc.types[b.type];
  ASSERT_EQ(t.attributes.size(), 3u);  // size, label inherited; count own
  EXPECT_EQ(t.attributes[0].name, "size");
  EXPECT_NEAR(value(wc, "B.size"), 3, 1e-12);
  EXPECT_EQ(value(wc, "B.count"), 6);  // a type default may use the object's own attributes
  EXPECT_EQ(wc.texts[wc.objects[wc.find_object("S")].first_slot + kFirstAttributeSlot + 1], "small");
  EXPECT_TRUE(wc.is_a(b.type, wc.objects[wc.find_object("S")].type));
}

TEST_F(Compile, InheritanceCyclesAndUnknownBasesAreErrors) {
  options.library_dirs = {type_dir({
      {"a_type", "sscs: 1\ntype: a_type\nextends: b_type\n"},
      {"b_type", "sscs: 1\ntype: b_type\nextends: a_type\n"},
      {"c_type", "sscs: 1\ntype: c_type\nextends: drun\n"},
  })};
  // Reported where a vault uses them (a type that closes the cycle reports it; one extending it
  // is broken too); a vault of the same folder that does not use them compiles.
  must_compile("objects:\n  - {type: drum, name: D}\n");
  compile_text("objects:\n  - {type: a_type, name: A}\n  - {type: c_type, name: C}\n");
  std::string all = diag.format(sources);
  EXPECT_NE(all.find("type 'b_type' extends itself through a cycle"), std::string::npos) << all;
  EXPECT_NE(all.find("type 'c_type' extends unknown type 'drun' (did you mean 'drum'?)"), std::string::npos) << all;
}

TEST_F(Compile, ABrokenTypeFileBreaksOnlyTheVaultsThatUseIt) {
  // A typo in one type file (an unknown key, a bad value, YAML that does not parse) is an error
  // where a vault uses the type, or a type extending it, not in every vault of its folder.
  options.library_dirs = {type_dir({
      {"good", "sscs: 1\ntype: good\ngeometry:\n  - box: {size: [1, 1, 1]}\n"},
      {"typo", "sscs: 1\ntype: typo\ncolour: \"#ff0000\"\n"},
      {"child", "sscs: 1\ntype: child\nextends: typo\n"},
      {"garbled", "sscs: 1\ntype: garbled\nattributes: {a: [\n"},
  })};
  must_compile("objects:\n  - {type: good, name: G}\n");
  EXPECT_EQ(first_error("objects:\n  - {type: child, name: C}\n"),
            "unknown key 'colour' in a type file (did you mean 'color'?) (in type 'typo', which 'child' extends)");
  diag = Diagnostics();
  EXPECT_FALSE(compile_text("objects:\n  - {type: garbled, name: X}\n"));
  ASSERT_FALSE(diag.errors().empty());
  EXPECT_NE(sources.path(diag.errors()[0].mark.file).find("garbled.yaml"), std::string::npos);
}

TEST_F(Compile, IntegerRangeIsChecked) {
  // The range a user can act on: the type's (rack levels 1 to 10), not the int32 one.
  EXPECT_EQ(first_error("objects:\n  - {type: rack, name: R, levels: -2147483649}\n"),
            "integer attribute 'levels' of 'R' is -2147483649, outside the range of type 'rack': 1 to 10");
  // Without a range in the type, the 32-bit one.
  diag = Diagnostics{};
  options.library_dirs = {type_dir({{"counter", "sscs: 1\ntype: counter\nattributes:\n  n: {type: integer, default: 0}\n"}})};
  EXPECT_EQ(first_error("objects:\n  - {type: counter, name: C, n: 3000000000}\n"),
            "integer attribute 'n' of 'C' is 3000000000, outside the 32-bit range -2147483648 to 2147483647");
}

TEST_F(Compile, LimitsPrintEnoughDigitsToTellValuesApart) {
  // A URDF limit of -0.4 rad is -22.918311805232928 deg: the value written from a 6-digit listing
  // must not be refused as "-22.9183 deg, above the max -22.9183 deg" (issue 19).
  options.library_dirs = {type_dir({{"hinge", "sscs: 1\ntype: hinge\nattributes:\n"
                                               "  a: {type: angle, default: -0.5 rad, min: -1 rad, max: -0.4 rad}\n"}})};
  EXPECT_EQ(first_error("objects:\n  - {type: hinge, name: H, a: -22.9183 deg}\n"),
            "'a' of 'H' is -22.9183 deg, above the max -22.9183118052 deg of type 'hinge'");
  // The 12 digits printed are accepted as the limit itself.
  diag = Diagnostics{};
  EXPECT_TRUE(compile_text("objects:\n  - {type: hinge, name: H, a: -22.9183118052 deg}\n")) << diag.format(sources);
}

TEST_F(Compile, ABrokenTypeFailsOnlyTheVaultsThatUseIt) {
  // One folder, a good type and one whose mesh is missing (issue 19): vaults that do not use the
  // broken type compile; a vault using it, or a type extending it, gets the error once.
  options.library_dirs = {type_dir({{"good", "sscs: 1\ntype: good\ngeometry:\n  - box: {size: [1, 1, 1]}\n"},
                                    {"broken", "sscs: 1\ntype: broken\ngeometry:\n  - mesh: {file: nowhere.stl}\n"},
                                    {"derived", "sscs: 1\ntype: derived\nextends: broken\n"}})};
  EXPECT_TRUE(compile_text("objects:\n  - {type: good, name: G}\n")) << diag.format(sources);
  diag = Diagnostics{};
  EXPECT_EQ(first_error("objects:\n  - {type: broken, name: B}\n  - {type: broken, name: B2}\n"),
            "mesh file 'nowhere.stl' does not exist");
  EXPECT_EQ(diag.count(), 1u) << diag.format(sources);
  diag = Diagnostics{};
  // A base's error says which type used extends it.
  EXPECT_EQ(first_error("objects:\n  - {type: derived, name: D}\n"),
            "mesh file 'nowhere.stl' does not exist (in type 'broken', which 'derived' extends)");
  EXPECT_EQ(diag.count(), 1u) << diag.format(sources);
}

TEST_F(Compile, ARobotWhoseUrdfOrSrdfIsBrokenFailsOnlyTheVaultsThatUseIt) {
  // A vendor robot whose URDF names a mesh that is not there, and one whose SRDF is not XML,
  // beside a good type: the good type's vaults compile; the robots' errors come where used.
  std::string dir = type_dir({{"good", "sscs: 1\ntype: good\ngeometry:\n  - box: {size: [1, 1, 1]}\n"},
                              {"nomesh", "sscs: 1\ntype: nomesh\nkind: device\nurdf: nomesh.urdf\ntool: {part: tool0}\n"},
                              {"badsrdf", "sscs: 1\ntype: badsrdf\nkind: device\nurdf: box.urdf\nsrdf: bad.srdf\n"}});
  std::ofstream(dir + "/nomesh.urdf") << "<robot name=\"r\"><link name=\"base\"><collision><geometry><mesh filename=\"base.stl\"/>"
                                         "</geometry></collision></link></robot>\n";
  std::ofstream(dir + "/box.urdf") << "<robot name=\"r\"><link name=\"base\"><collision><geometry><box size=\"1 1 1\"/>"
                                      "</geometry></collision></link></robot>\n";
  std::ofstream(dir + "/bad.srdf") << "<robot name=\"r\">\n  <disable_collisions link1=\"a\"\n</robot>\n";
  options.library_dirs = {dir};
  EXPECT_TRUE(compile_text("objects:\n  - {type: good, name: G}\n")) << diag.format(sources);
  diag = Diagnostics{};
  std::string e = first_error("objects:\n  - {type: nomesh, name: R}\n");
  EXPECT_NE(sources.path(diag.errors()[0].mark.file).find("nomesh.urdf"), std::string::npos);  // at the mesh in the URDF
  EXPECT_NE(e.find("link 'base': mesh 'base.stl' does not exist"), std::string::npos) << e;
  diag = Diagnostics{};
  e = first_error("objects:\n  - {type: badsrdf, name: R}\n");
  EXPECT_NE(e.find("cannot read SRDF file 'bad.srdf': "), std::string::npos) << e;
}

TEST_F(Compile, ManyErrorsAreReportedInOnePass) {
  compile_text(
      "objects:\n  - {type: drumm, name: A}\n  - {type: drum, name: B, diamter: 1}\n  - {type: room, name: C}\n");
  ASSERT_EQ(diag.count(), 5u) << diag.format(sources);  // and no range errors for the missing values
  // Both hints: a typo, or a plugin's type without --plugins.
  EXPECT_EQ(diag.errors()[0].message,
            "unknown type 'drumm' (did you mean 'drum'?) (no plugins are loaded: a plugin's type needs --plugins DIR)");
  EXPECT_EQ(diag.errors()[1].message, "type 'drum' has no attribute 'diamter' (did you mean 'diameter'?)");
  EXPECT_EQ(diag.errors()[2].message, "object 'C' (a room) needs a value for 'length', which has no default");
}

TEST_F(Compile, DeviceJointsAreAttributesWithLimits) {
  options.library_dirs = {type_dir({
      {"slider", "sscs: 1\ntype: slider\nkind: device\nparts:\n  - {name: base}\n"
                 "  - name: carriage\n    parent: base\n"
                 "    joint: {name: x, type: prismatic, axis: [1, 0, 0], limits: {min: 0, max: 2 m}}\n"
                 "  - name: arm\n    parent: carriage\n"
                 "    joint: {name: turn, type: revolute, axis: [0, 0, 1], limits: {min: -90, max: 90}}\n"
                 "tool: {part: arm, xyz: [0, 0, 0.1]}\nhome: {turn: 45}\n"},
  })};
  Workcell wc = must_compile("objects:\n  - {type: slider, name: S, x: 1.5}\n  - {type: slider, name: T}\n");
  EXPECT_NEAR(value(wc, "S.x"), 1.5, 1e-12);
  EXPECT_NEAR(value(wc, "T.turn"), std::numbers::pi / 4, 1e-12);  // home value is the default
  EXPECT_EQ(first_error("objects:\n  - {type: slider, name: S, x: 3}\n"),
            "'x' of 'S' is 3 m, above the max 2 m of type 'slider'");
}

}  // namespace
}  // namespace sscs::testing

namespace sscs::testing {
namespace {

/// A frame of a repeat is found by its name read back (its counters parsed from it) where the
/// pattern allows, else by making every copy's name: the two must agree on every name, a copy's
/// or not (leading zeros, counters out of range, patterns whose names do not give the counters:
/// counters side by side, a digit after one).
TEST_F(Compile, ANamedFrameOfARepeatIsTheCopyOfThatName) {
  options.library_dirs.push_back(type_dir({{"grid", R"(sscs: 1
type: grid
attributes:
  rows: {type: integer, default: 3}
  cols: {type: integer, default: 12}
frames:
  slot_{row}_{col}:
    xyz: ["col * 0.1", "row * 0.2", 0]
    repeat: {row: rows, col: cols}
  a{row}b{col}: {xyz: ["row + col", 0, 0], repeat: {row: rows, col: {count: cols, pitch: [0, 0.5, 0]}}}
  x{row}{col}: {xyz: ["row", "col", 1], repeat: {row: rows, col: cols}}
  n{row}7{col}: {xyz: ["row", "col", 2], repeat: {row: rows, col: cols}}
  plain: {xyz: [1, 2, 3]}
)"}}));
  Workcell wc = must_compile("objects:\n  - {type: grid, name: G}\n  - {type: grid, name: H, rows: 0}\n");
  for (const char* object : {"G", "H"}) {
    const int o = wc.find_object(object);
    ASSERT_GE(o, 0);
    const double* attributes = &wc.values[wc.objects[o].first_slot + kFirstAttributeSlot];
    // Every copy's name, each way it could be mistyped, and names of no copy.
    std::vector<std::string> names = {"plain", "slot_", "slot_1", "slot__1", "slot_-1_1", "slot_1_1x", "x", "n171"};
    for (const FrameTemplate& f : wc.types[wc.objects[o].type].templates.frames)
      f.each(attributes, [&](const std::string& copy, const Eigen::Isometry3d&) {
        names.push_back(copy);
        names.push_back(copy + "0");
        names.push_back("0" + copy);
        for (size_t i = 0; i < copy.size(); ++i)
          if (std::isdigit(static_cast<unsigned char>(copy[i]))) names.push_back(copy.substr(0, i) + "0" + copy.substr(i));
      });
    names.insert(names.end(), {"slot_4_1", "slot_3_13", "slot_0_1", "a4b1", "x113", "n37130"});
    for (const std::string& name : names) {
      std::optional<Eigen::Isometry3d> made;  // by making every copy: the last of that name
      for (const FrameTemplate& f : wc.types[wc.objects[o].type].templates.frames)
        f.each(attributes, [&](const std::string& copy, const Eigen::Isometry3d& X) {
          if (copy == name) made = X;
        });
      const std::optional<Eigen::Isometry3d> found = wc.named_frame(o, name);
      ASSERT_EQ(found.has_value(), made.has_value()) << object << " " << name;
      if (found) {
        EXPECT_TRUE(found->matrix() == made->matrix()) << object << " " << name << "\n" << found->matrix() << "\n" << made->matrix();
      }
    }
  }
}

}  // namespace
}  // namespace sscs::testing
