#include <gtest/gtest.h>

#include "core/yaml_tree.h"

namespace sscs {
namespace {

struct Parsed {
  Sources sources;
  Diagnostics diag;
  yaml::Document doc;
};

std::unique_ptr<Parsed> parse(const std::string& text) {
  auto p = std::make_unique<Parsed>();
  uint32_t file = p->sources.add("t.yaml", text);
  p->doc = yaml::parse(p->sources, file, p->diag);
  return p;
}

TEST(YamlTree, MarksAreOneBasedLineAndColumn) {
  auto p = parse("a: 1\nb:\n  - x\n  - {c: \"q\"}\n");
  ASSERT_FALSE(p->diag.has_errors());
  yaml::Node root = p->doc.root();
  ASSERT_TRUE(root.is_map());
  EXPECT_EQ(root.size(), 2u);
  yaml::Node b = root.find("b");
  ASSERT_TRUE(b.is_sequence());
  EXPECT_EQ(b.item(0).text(), "x");
  EXPECT_EQ(b.item(0).mark().line, 3u);
  EXPECT_EQ(b.item(0).mark().column, 5u);
  yaml::Node c = b.item(1).find("c");
  EXPECT_EQ(c.text(), "q");
  EXPECT_TRUE(c.quoted());
  EXPECT_FALSE(b.item(0).quoted());
  EXPECT_EQ(c.mark().line, 4u);
  EXPECT_EQ(c.mark().column, 9u);  // a quoted scalar's mark is its opening quote
}

TEST(YamlTree, NullsAreNodes) {
  auto p = parse("a: ~\nb:\nc: null\n");
  ASSERT_FALSE(p->diag.has_errors());
  for (const char* k : {"a", "b", "c"}) EXPECT_TRUE(p->doc.root().find(k).is_null()) << k;
}

TEST(YamlTree, DuplicateKeysAreErrors) {
  auto p = parse("a: 1\nb: 2\na: 3\n");
  ASSERT_EQ(p->diag.count(), 1u);
  EXPECT_EQ(p->diag.errors()[0].message, "duplicate key 'a' (first given at line 1)");
  EXPECT_EQ(p->diag.errors()[0].mark.line, 3u);
}

TEST(YamlTree, AliasesShareNodesAndBombsAreStopped) {
  auto p = parse("a: &x [1, 2]\nb: *x\n");
  ASSERT_FALSE(p->diag.has_errors());
  EXPECT_EQ(p->doc.root().find("b").item(1).text(), "2");
  std::string bomb = "a: &a [x, x, x, x, x, x, x, x, x, x]\n";
  std::string prev = "a";
  for (char n = 'b'; n <= 'h'; ++n) {
    bomb += std::string(1, n) + ": &" + n + " [";
    for (int i = 0; i < 10; ++i) bomb += (i ? ", *" : "*") + prev;
    bomb += "]\n";
    prev = std::string(1, n);
  }
  auto q = parse(bomb);
  ASSERT_TRUE(q->diag.has_errors());
  EXPECT_NE(q->diag.errors()[0].message.find("alias bomb"), std::string::npos);
  EXPECT_TRUE(q->doc.empty());
}

TEST(YamlTree, DeepNestingStops) {
  auto p = parse("a: " + std::string(100, '[') + std::string(100, ']') + "\n");
  ASSERT_TRUE(p->diag.has_errors());
  EXPECT_EQ(p->diag.errors()[0].message, "nesting deeper than 64 levels");
}

TEST(YamlTree, BinaryIsRejectedWithItsPosition) {
  auto p = parse(std::string("a: 1\nb: x\x01y\n"));
  ASSERT_TRUE(p->diag.has_errors());
  EXPECT_EQ(p->diag.errors()[0].mark.line, 2u);
  EXPECT_EQ(p->diag.errors()[0].mark.column, 5u);
  auto q = parse(std::string("a: caf\xc3\xa9\n"));  // valid UTF-8 passes
  EXPECT_FALSE(q->diag.has_errors());
}

TEST(YamlTree, DiagnosticsQuoteTheLineWithACaret) {
  auto p = parse("a: 1\nbb: 2\n  # note\nbb: 3\n");
  ASSERT_TRUE(p->diag.has_errors());
  EXPECT_EQ(p->diag.format(p->sources),
            "t.yaml:4:1: error: duplicate key 'bb' (first given at line 2)\n"
            "  bb: 3\n"
            "  ^\n");
  auto q = parse("a: 1\nb: [1, 2\n");
  ASSERT_TRUE(q->diag.has_errors());
  EXPECT_EQ(q->diag.format(q->sources).rfind("t.yaml:", 0), 0u);
  EXPECT_NE(q->diag.format(q->sources).find("error: invalid YAML"), std::string::npos);
}

TEST(YamlTree, AColumnAfterCharactersOfManyBytesCountsCharacters) {
  // "Größe → " is 8 characters in 12 bytes: the duplicate key is at character 20, byte 24, and
  // the caret stands under it, as an editor counts (a tab before it stays a tab).
  auto p = parse("a: {\"Größe → \": 1, \"Größe → \": 2}\n");
  ASSERT_TRUE(p->diag.has_errors());
  EXPECT_EQ(p->diag.errors()[0].mark.column, 24u);  // bytes, as the YAML reader counts
  EXPECT_EQ(p->sources.character_column(p->diag.errors()[0].mark), 20u);
  EXPECT_EQ(p->diag.format(p->sources),
            "t.yaml:1:20: error: duplicate key 'Größe → ' (first given at line 1)\n"
            "  a: {\"Größe → \": 1, \"Größe → \": 2}\n"
            "                     ^\n");
  EXPECT_EQ(characters("a\tb\xc3\xa9" "c", 5), 4u);  // a, tab, b, é
  EXPECT_EQ(characters("\xe2\x86\x92x", 3), 1u);     // → is one character of three bytes
}

/// Where yaml::exact_mark puts offset `pos` of the scalar at (line, column), placed as the
/// stages place it (column + pos, +1 past a quote or a block indicator): "line:column".
std::string exact(const std::string& text, uint32_t line, uint32_t column, bool quoted, size_t pos) {
  Sources sources;
  const uint32_t file = sources.add("f.yaml", text);
  const SourceMark m = yaml::exact_mark(sources, {file, line, static_cast<uint32_t>(column + pos + (quoted ? 1 : 0))});
  return std::to_string(m.line) + ":" + std::to_string(m.column);
}

TEST(ExactMark, AnOffsetInAScalarOverSeveralLinesIsMovedToItsWord) {  // review 18 and 19
  // `expr: >-` then two lines: the first word, a later one, and a word repeated.
  const std::string block = "a:\n  expr: >-\n    Rack_1.height + 0.5\n    <= Romm1.height + Rack_1.height\n";
  // The scalar's mark is its indicator, 2:9 ('>'); its text "Rack_1.height + 0.5 <= Romm1.height + Rack_1.height".
  EXPECT_EQ(exact(block, 2, 9, true, 0), "3:5");    // Rack_1 (the first word: it was left on the key's line)
  EXPECT_EQ(exact(block, 2, 9, true, 23), "4:8");   // Romm1
  EXPECT_EQ(exact(block, 2, 9, true, 38), "4:23");  // the second Rack_1
  // A plain scalar folded over two lines: its first line's words stay where they are.
  const std::string plain = "expr: Rack_1.height + 0.25\n  <= Rooom1.height\n";
  EXPECT_EQ(exact(plain, 1, 7, false, 0), "1:7");
  EXPECT_EQ(exact(plain, 1, 7, false, 24), "2:6");  // Rooom1
  // A double-quoted scalar over two lines.
  const std::string quoted = "expr: \"Rack_1.height\n  <= Rooom1.height\"\n";
  EXPECT_EQ(exact(quoted, 1, 7, true, 17), "2:6");
  // On one line: as placed.
  EXPECT_EQ(exact("expr: \"a <= Rooom1.height\"\n", 1, 7, true, 5), "1:13");
}

}  // namespace
}  // namespace sscs
