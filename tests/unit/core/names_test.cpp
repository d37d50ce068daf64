#include <gtest/gtest.h>

#include "core/diagnostics.h"
#include "core/names.h"

namespace sscs {
namespace {

TEST(Names, Validity) {
  for (const char* good : {"Room1", "a", "Rack_1_2", "door-east", "Z9_-"}) EXPECT_TRUE(is_valid_name(good)) << good;
  for (const char* bad : {"", "1Room", "_x", "-x", "Room.1", "Room 1", "Räck"}) EXPECT_FALSE(is_valid_name(bad)) << bad;
}

TEST(Names, EditDistance) {
  EXPECT_EQ(edit_distance("", ""), 0u);
  EXPECT_EQ(edit_distance("Door1", "Door1"), 0u);
  EXPECT_EQ(edit_distance("Dor1", "Door1"), 1u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  // A transposition of neighbours is one edit.
  EXPECT_EQ(edit_distance("heigth", "height"), 1u);
  EXPECT_EQ(edit_distance("ab", "ba"), 1u);
  EXPECT_EQ(edit_distance("ca", "abc"), 3u);  // optimal string alignment: no edit of a moved pair
}

TEST(Names, DidYouMeanPicksTheClosePlausibleName) {
  std::vector<std::string> names = {"Door1", "Room1", "Rack_1_1"};
  EXPECT_EQ(did_you_mean("Dor1", names), " (did you mean 'Door1'?)");
  EXPECT_EQ(closest_name("Rack_11", names), "Rack_1_1");
  EXPECT_EQ(did_you_mean("Conveyor", names), "");  // nothing close: no suggestion
  EXPECT_EQ(closest_name("heigth", {"diameter", "length", "height"}), "height");
  EXPECT_EQ(closest_name("heigth", {"length", "height"}), "height");
}

TEST(Names, Glob) {
  EXPECT_TRUE(glob_match("Rack_*", "Rack_1_2"));
  EXPECT_TRUE(glob_match("Drum_?_3", "Drum_2_3"));
  EXPECT_FALSE(glob_match("Drum_?_3", "Drum_12_3"));
  EXPECT_TRUE(glob_match("*", "anything"));
  EXPECT_TRUE(glob_match("*_1", "Rack_1_1"));
  EXPECT_FALSE(glob_match("Rack_*", "Room1"));
  EXPECT_TRUE(glob_match("a*b*c", "aXXbYYc"));
  EXPECT_FALSE(glob_match("a*b*c", "aXXbYY"));
}

}  // namespace
}  // namespace sscs

namespace sscs::testing {
namespace {

TEST(Printable, ControlCharactersAndLongTextNeverReachATerminalWhole) {
  EXPECT_EQ(printable("V\x1b[2J\x07"), "V?[2J?");
  EXPECT_EQ(printable("a\nb\tc\x7f"), "a?b\tc?");
  EXPECT_EQ(printable("a\nb", true), "a\nb");
  EXPECT_EQ(printable("caf\xc3\xa9 \xff"), "caf\xc3\xa9 ?");  // UTF-8 kept, a stray byte replaced
  // A right-to-left override (U+202E), an isolate (U+2066) and a mark (U+200F): one '?' a byte.
  EXPECT_EQ(printable("Keg\xe2\x80\xae_2 \xe2\x81\xa6x\xe2\x80\x8f"), "Keg???_2 ???x???");
  EXPECT_EQ(printable("\xd7\xa9\xd7\x9c\xd7\x95\xd7\x9d \xe2\x80\x94"), "\xd7\xa9\xd7\x9c\xd7\x95\xd7\x9d \xe2\x80\x94");  // Hebrew, a dash kept
  const std::string expr(1'000'000, 'x');
  std::string shown = within_window(expr);
  EXPECT_LT(shown.size(), 2100u);
  EXPECT_NE(shown.find("(998500 bytes not shown)"), std::string::npos) << shown.substr(990, 60);
  EXPECT_EQ(within_window("short"), "short");
}

}  // namespace
}  // namespace sscs::testing

namespace sscs {
namespace {

TEST(Names, NaturalOrderComparesRunsOfDigitsAsNumbers) {
  std::vector<std::string> names = {"slot_10_1", "slot_2_1", "slot_1_10", "slot_1_2", "slot_1_1", "top", "slot_01_3", "slot"};
  std::sort(names.begin(), names.end(), [](const std::string& a, const std::string& b) { return natural_less(a, b); });
  EXPECT_EQ(names, (std::vector<std::string>{"slot", "slot_1_1", "slot_1_2", "slot_01_3", "slot_1_10", "slot_2_1", "slot_10_1", "top"}));
  EXPECT_FALSE(natural_less("a1", "a1"));
  EXPECT_TRUE(natural_less("a9", "a10"));
  EXPECT_FALSE(natural_less("a10", "a9"));
}

}  // namespace
}  // namespace sscs
