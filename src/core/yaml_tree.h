#pragma once
/// A lean YAML tree built from yaml-cpp's event parser, with a source mark on every node.
///
/// yaml-cpp's own node tree (YAML::Load) costs about 70 bytes of heap per input byte and keeps the
/// first of two duplicate keys silently. This tree costs about 28 bytes a node, rejects duplicate
/// keys, bounds nesting depth and alias expansion, and keeps whether a scalar was quoted.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/diagnostics.h"
#include "core/source.h"

namespace sscs::yaml {

enum class Kind : uint8_t { Null, Scalar, Sequence, Map };

/// Limits that keep hostile input (alias bombs, deep nesting, huge files) from exhausting memory.
struct Limits {
  size_t max_depth = 64;
  size_t max_bytes = size_t(1) << 30;
};

class Document;

/// A handle to one node of a Document; cheap to copy, valid while the Document lives.
class Node {
 public:
  Node() = default;
  Node(const Document* doc, uint32_t index) : doc_(doc), index_(index) {}

  Kind kind() const;
  bool is_null() const { return kind() == Kind::Null; }
  bool is_scalar() const { return kind() == Kind::Scalar; }
  bool is_sequence() const { return kind() == Kind::Sequence; }
  bool is_map() const { return kind() == Kind::Map; }
  /// "a mapping", "a sequence", "a scalar 'abc'", "nothing": for "expected X, found Y" messages.
  std::string describe() const;

  SourceMark mark() const;
  /// A scalar's text ("" for null and containers).
  std::string_view text() const;
  /// True when the scalar was quoted or tagged: a string, never a number or a unit literal.
  bool quoted() const;

  /// Items of a sequence, or key/value pairs of a map.
  size_t size() const;
  Node item(size_t i) const;   ///< sequence item
  Node key(size_t i) const;    ///< map key (always a scalar)
  Node value(size_t i) const;  ///< map value
  /// The value under `key` in a map, or an invalid Node.
  Node find(std::string_view key) const;
  bool valid() const { return doc_ != nullptr; }

 private:
  const Document* doc_ = nullptr;
  uint32_t index_ = 0;
};

/// One parsed YAML document. Movable, not copyable.
class Document {
 public:
  Node root() const { return Node(this, root_); }
  bool empty() const { return nodes_.empty(); }

  struct Rec {
    Kind kind;
    bool quoted;
    uint32_t line;
    uint32_t column;
    uint32_t a;  ///< scalar: text offset; container: first kid in kids_
    uint32_t b;  ///< scalar: text length; container: number of kids
  };

 private:
  friend class Node;
  friend class Builder;
  friend Document parse(const Sources&, uint32_t, Diagnostics&, const Limits&);
  uint32_t file_ = 0;
  uint32_t root_ = 0;
  std::vector<Rec> nodes_;
  std::vector<uint32_t> kids_;
  std::string text_;
};

/// Parses one YAML document from a registered source file. Structural errors (duplicate keys,
/// keys that are not scalars) go to `diag` and parsing goes on; fatal ones (bad YAML, not UTF-8
/// text, too deep, alias bomb, several documents) are reported and stop it: then the returned
/// Document is empty.
Document parse(const Sources& sources, uint32_t file, Diagnostics& diag, const Limits& limits = {});

/// Where a mark inside a scalar really is. Stages place a problem at offset `pos` of a scalar's
/// text as its mark's column + pos (+1 past a quote or a block indicator): right for a scalar on
/// one line, but past the end of the line for one written over several (a `>-` block, a folded
/// plain or quoted scalar). Such a mark (its column beyond its line) is moved to the same text in
/// the source: the token at `pos` (an identifier, a number, else one character), at the same
/// occurrence; so is one on a line with an escape before it. Other marks are returned as they are.
SourceMark exact_mark(const Sources& sources, SourceMark mark);

}  // namespace sscs::yaml
