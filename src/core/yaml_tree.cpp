#include "core/yaml_tree.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/exceptions.h>
#include <yaml-cpp/mark.h>
#include <yaml-cpp/parser.h>

#include <algorithm>
#include <optional>
#include <istream>
#include <streambuf>
#include <unordered_map>

#include <fmt/format.h>

namespace sscs::yaml {

// ---- Node --------------------------------------------------------------------------------------

// An absent node (a key not in the file: !valid()) reads as null, with no mark, text or items,
// so a reader that forgets to ask valid() gets "nothing", never a crash.
Kind Node::kind() const { return doc_ ? doc_->nodes_[index_].kind : Kind::Null; }

SourceMark Node::mark() const {
  if (!doc_) return {};
  const auto& r = doc_->nodes_[index_];
  return {doc_->file_, r.line, r.column};
}

std::string_view Node::text() const {
  if (!doc_) return {};
  const auto& r = doc_->nodes_[index_];
  if (r.kind != Kind::Scalar) return {};
  return std::string_view(doc_->text_).substr(r.a, r.b);
}

bool Node::quoted() const { return doc_ && doc_->nodes_[index_].quoted; }

size_t Node::size() const {
  if (!doc_) return 0;
  const auto& r = doc_->nodes_[index_];
  if (r.kind == Kind::Sequence) return r.b;
  if (r.kind == Kind::Map) return r.b / 2;
  return 0;
}

// Out of range (or on an absent node): an absent node.
Node Node::item(size_t i) const { return i < size() && is_sequence() ? Node(doc_, doc_->kids_[doc_->nodes_[index_].a + i]) : Node(); }
Node Node::key(size_t i) const { return i < size() && is_map() ? Node(doc_, doc_->kids_[doc_->nodes_[index_].a + 2 * i]) : Node(); }
Node Node::value(size_t i) const { return i < size() && is_map() ? Node(doc_, doc_->kids_[doc_->nodes_[index_].a + 2 * i + 1]) : Node(); }

Node Node::find(std::string_view k) const {
  if (!is_map()) return {};
  for (size_t i = 0, n = size(); i < n; ++i)
    if (key(i).text() == k) return value(i);
  return {};
}

std::string Node::describe() const {
  switch (kind()) {
    case Kind::Null: return "nothing";
    case Kind::Map: return size() == 0 ? "an empty mapping" : "a mapping";
    case Kind::Sequence: return size() == 0 ? "an empty sequence" : "a sequence";
    case Kind::Scalar: {
      std::string_view t = text();
      if (t.size() > 40) return fmt::format("'{}...'", t.substr(0, 37));
      return fmt::format("'{}'", t);
    }
  }
  return "?";
}

// ---- Builder -----------------------------------------------------------------------------------

namespace {

/// A read-only streambuf over text we already hold, so the parser reads it without a copy.
struct MemoryBuf : std::streambuf {
  MemoryBuf(const char* begin, size_t size) {
    char* b = const_cast<char*>(begin);  // never written through: get area only
    setg(b, b, b + size);
  }
};

/// The first byte that is not UTF-8 text (a NUL or a bad sequence), as a mark; or line 0.
SourceMark find_binary(const std::string& text, uint32_t file) {
  uint32_t line = 1, col = 1;
  const auto* s = reinterpret_cast<const unsigned char*>(text.data());
  size_t n = text.size();
  for (size_t i = 0; i < n;) {
    unsigned char c = s[i];
    size_t len = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    bool bad = len == 0 || c == 0 || i + len > n;
    for (size_t k = 1; !bad && k < len; ++k) bad = (s[i + k] & 0xC0) != 0x80;
    bool control = c < 0x20 && c != '\n' && c != '\r' && c != '\t';
    if (bad || control) return {file, line, col};
    if (c == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
    i += len;
  }
  return {file, 0, 0};
}

}  // namespace

class Builder : public YAML::EventHandler {
 public:
  Builder(Document& doc, std::string_view text, Diagnostics& diag, const Limits& limits)
      : doc_(doc), text_(text), diag_(diag), limits_(limits) {}

  void OnDocumentStart(const YAML::Mark& mark) override {
    if (documents_++ > 0)
      throw InputError{to_mark(mark), "expected one YAML document in the file, found a second ('---')"};
  }
  void OnDocumentEnd() override {}

  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    const auto [l, c] = empty_value_place(mark);
    add_leaf({Kind::Null, false, l, c, 0, 0}, anchor);
  }

  static constexpr uint32_t kBytesPerWeight = 64;

  void OnAlias(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    auto it = anchors_.find(anchor);
    if (it == anchors_.end() || open_.end() != std::find_if(open_.begin(), open_.end(), [&](const Open& o) {
          return o.index == it->second;
        }))
      throw InputError{to_mark(mark), "alias refers to an anchor that is not complete here"};
    // The alias shares the anchored node: no copy, but its expanded size counts.
    attach(it->second);
  }

  void OnScalar(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                const std::string& value) override {
    auto offset = static_cast<uint32_t>(doc_.text_.size());
    doc_.text_ += value;
    bool quoted = tag != "?";
    add_leaf({Kind::Scalar, quoted, line(mark), col(mark), offset, static_cast<uint32_t>(value.size())}, anchor);
  }

  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value) override {
    open(Kind::Sequence, mark, anchor);
  }
  void OnSequenceEnd() override { close(); }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value) override {
    open(Kind::Map, mark, anchor);
  }
  void OnMapEnd() override { close(); }

  uint32_t root() const { return root_; }

 private:
  struct Open {
    uint32_t index;
    size_t kids_begin;  // into pending_
  };

  /// Where a null is. An empty value (`a:` with nothing after it, a `-` alone) has no text of its
  /// own: yaml-cpp marks it at the next token, on the next key's line or past the end of the file.
  /// Such a value is placed at its key (a mapping's value), else at its `-`. A `~` or `null` stays.
  std::pair<uint32_t, uint32_t> empty_value_place(const YAML::Mark& m) const {
    const std::pair<uint32_t, uint32_t> as_marked{line(m), col(m)};
    size_t pos = std::min<size_t>(m.pos < 0 ? 0 : static_cast<size_t>(m.pos), text_.size());
    const std::string_view rest = text_.substr(pos);
    for (std::string_view word : {"~", "null", "Null", "NULL"})
      if (rest.starts_with(word)) return as_marked;
    // Back over blank lines and comments to the ':' or '-' the empty value follows.
    uint32_t l = line(m);
    for (size_t end = pos;; --l) {
      const size_t nl = end == 0 ? std::string_view::npos : text_.rfind('\n', end - 1);
      const size_t start = nl == std::string_view::npos ? 0 : nl + 1;
      std::string_view content = text_.substr(start, end - start);
      for (size_t hash = content.find('#'); hash != std::string_view::npos; hash = content.find('#', hash + 1))
        if (hash == 0 || content[hash - 1] == ' ' || content[hash - 1] == '\t') {
          content = content.substr(0, hash);
          break;
        }
      while (!content.empty() && (content.back() == ' ' || content.back() == '\t' || content.back() == '\r')) content.remove_suffix(1);
      if (!content.empty()) {
        if (content.back() == '-') return {l, static_cast<uint32_t>(content.size())};
        if (content.back() != ':') return as_marked;
        // The key just attached to the innermost open mapping.
        if (!open_.empty() && doc_.nodes_[open_.back().index].kind == Kind::Map && (pending_.size() - open_.back().kids_begin) % 2 == 1) {
          const Document::Rec& key = doc_.nodes_[pending_.back()];
          return {key.line, key.column};
        }
        return {l, static_cast<uint32_t>(content.size())};
      }
      if (start == 0 || l <= 1) return as_marked;
      end = start - 1;
    }
  }

  static uint32_t line(const YAML::Mark& m) { return static_cast<uint32_t>(m.line + 1); }
  static uint32_t col(const YAML::Mark& m) { return static_cast<uint32_t>(m.column + 1); }
  SourceMark to_mark(const YAML::Mark& m) const { return {doc_.file_, line(m), col(m)}; }

  uint32_t new_node(const Document::Rec& rec) {
    doc_.nodes_.push_back(rec);
    // A node weighs 1, and a scalar 1 more for every 64 bytes of its text: a 10 MB string
    // aliased 2,000 times is as much an alias bomb as 2,000 aliased mappings.
    weight_.push_back(1 + (rec.kind == Kind::Scalar ? rec.b / kBytesPerWeight : 0));
    return static_cast<uint32_t>(doc_.nodes_.size() - 1);
  }

  void add_leaf(const Document::Rec& rec, YAML::anchor_t anchor) {
    uint32_t index = new_node(rec);
    if (anchor) anchors_[anchor] = index;
    attach(index);
  }

  void attach(uint32_t index) {
    if (open_.empty()) {
      root_ = index;
      return;
    }
    pending_.push_back(index);
  }

  void open(Kind kind, const YAML::Mark& mark, YAML::anchor_t anchor) {
    if (open_.size() >= limits_.max_depth)
      throw InputError{to_mark(mark), fmt::format("nesting deeper than {} levels", limits_.max_depth)};
    uint32_t index = new_node({kind, false, line(mark), col(mark), 0, 0});
    if (anchor) anchors_[anchor] = index;
    open_.push_back({index, pending_.size()});
  }

  void close() {
    Open o = open_.back();
    open_.pop_back();
    auto& rec = doc_.nodes_[o.index];
    rec.a = static_cast<uint32_t>(doc_.kids_.size());
    rec.b = static_cast<uint32_t>(pending_.size() - o.kids_begin);
    uint64_t weight = 1;
    for (size_t i = o.kids_begin; i < pending_.size(); ++i) {
      doc_.kids_.push_back(pending_[i]);
      weight += weight_[pending_[i]];
    }
    pending_.resize(o.kids_begin);
    weight_[o.index] = weight;
    // Aliases share nodes; a document whose expansion is far larger than its text is an alias bomb.
    const uint64_t allowed = 4 * (doc_.nodes_.size() + doc_.text_.size() / kBytesPerWeight) + 100000;
    if (weight > allowed)
      throw InputError{SourceMark{doc_.file_, rec.line, rec.column},
                       fmt::format("YAML aliases here expand to more than four times the document ({} nodes and "
                                   "{} MB of text; an alias bomb?)", doc_.nodes_.size(), doc_.text_.size() / 1e6)};
    if (rec.kind == Kind::Map) check_keys(o.index);
    attach(o.index);
  }

  void check_keys(uint32_t map_index) {
    Node map(&doc_, map_index);
    size_t n = map.size();
    for (size_t i = 0; i < n; ++i) {
      Node k = map.key(i);
      if (!k.is_scalar()) {
        diag_.error(k.mark(), fmt::format("expected a plain key, found {}", k.describe()));
        return;
      }
    }
    // Duplicate keys: yaml-cpp keeps the first silently, a reviewer would miss the second.
    std::vector<uint32_t> order(n);
    for (size_t i = 0; i < n; ++i) order[i] = static_cast<uint32_t>(i);
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t x, uint32_t y) { return map.key(x).text() < map.key(y).text(); });
    for (size_t i = 1; i < n; ++i) {
      Node a = map.key(order[i - 1]);
      Node b = map.key(order[i]);
      if (a.text() == b.text())
        diag_.error(b.mark(), fmt::format("duplicate key '{}' (first given at line {})", b.text(), a.mark().line));
    }
  }

  Document& doc_;
  std::string_view text_;
  Diagnostics& diag_;
  Limits limits_;
  int documents_ = 0;
  uint32_t root_ = 0;
  std::vector<Open> open_;
  std::vector<uint32_t> pending_;
  std::vector<uint64_t> weight_;
  std::unordered_map<YAML::anchor_t, uint32_t> anchors_;
};

namespace {

/// The innermost flow collection (`{` or `[`) still open where a parse error was found, if any:
/// its line and column (1-based) and the bracket that would close it. yaml-cpp reports a missing
/// `}` at the next line as "illegal block entry"; this names what is missing and where.
struct Unclosed {
  uint32_t line = 0, column = 0, line_end = 0;
  char closer = 0;
};
std::optional<Unclosed> unclosed_flow(const std::string& text, uint32_t error_line, uint32_t error_column) {
  std::vector<Unclosed> open;
  uint32_t line = 1, column = 0;
  char quote = 0;
  bool comment = false;
  std::vector<uint32_t> line_ends;
  for (size_t i = 0; i < text.size(); ++i) {
    char c = text[i];
    ++column;
    if (line > error_line || (line == error_line && column >= error_column)) break;
    if (c == '\n') {
      ++line;
      column = 0;
      comment = false;
      if (quote == '\'') quote = 0;  // a single-quoted scalar may span lines; be lenient
      continue;
    }
    if (comment) continue;
    if (quote) {
      if (c == '\\' && quote == '"') ++i, ++column;
      else if (c == quote) quote = 0;
      continue;
    }
    if (c == '#' && (column == 1 || text[i - 1] == ' ' || text[i - 1] == '\t')) comment = true;
    else if (c == '"' || c == '\'') quote = c;
    else if (c == '{' || c == '[') open.push_back({line, column, 0, c == '{' ? '}' : ']'});
    else if ((c == '}' || c == ']') && !open.empty()) open.pop_back();
  }
  if (open.empty()) return std::nullopt;
  Unclosed u = open.back();
  // Where the closer belongs: the end of the opening line's content (before a comment).
  size_t start = 0;
  for (uint32_t l = 1; l < u.line && start != std::string::npos; ++l) start = text.find('\n', start) + 1;
  std::string_view rest(text.data() + start, text.find('\n', start) == std::string::npos ? text.size() - start : text.find('\n', start) - start);
  size_t hash = rest.find(" #");
  std::string_view content = rest.substr(0, hash == std::string_view::npos ? rest.size() : hash);
  while (!content.empty() && (content.back() == ' ' || content.back() == '\r')) content.remove_suffix(1);
  u.line_end = static_cast<uint32_t>(content.size() + 1);
  return u;
}

}  // namespace

Document parse(const Sources& sources, uint32_t file, Diagnostics& diag, const Limits& limits) {
  Document doc;
  doc.file_ = file;
  const std::string& text = sources.text(file);
  try {
    if (text.size() > limits.max_bytes)
      throw InputError{{file, 1, 1}, fmt::format("file is larger than {} bytes", limits.max_bytes)};
    SourceMark binary = find_binary(text, file);
    if (binary.line != 0)
      throw InputError{binary, "expected UTF-8 YAML text, found a binary byte (NUL, control or invalid UTF-8)"};
    MemoryBuf buf(text.data(), text.size());
    std::istream in(&buf);
    YAML::Parser parser(in);
    Builder builder(doc, text, diag, limits);
    parser.HandleNextDocument(builder);
    if (doc.nodes_.empty()) throw InputError{{file, 1, 1}, "expected a YAML document, found an empty file"};
    doc.root_ = builder.root();
    // A second document ends the parse with an error from OnDocumentStart.
    parser.HandleNextDocument(builder);
  } catch (const InputError& e) {
    diag.error(e.mark, e.message);
    return Document{};
  } catch (const YAML::Exception& e) {
    const auto line = static_cast<uint32_t>(e.mark.line + 1), column = static_cast<uint32_t>(e.mark.column + 1);
    if (auto u = unclosed_flow(text, line, column); u && u->line < line) {
      const auto lines = static_cast<uint32_t>(std::count(text.begin(), text.end(), '\n') + (text.empty() || text.back() == '\n' ? 0 : 1));
      std::string where = line > lines ? "at the end of the file" : fmt::format("at line {}", line);
      diag.error({file, u->line, u->line_end},
                 fmt::format("invalid YAML: expected '{}' here to close the '{}' opened at column {} (the parser stopped {}: {})",
                             u->closer, u->closer == '}' ? '{' : '[', u->column, where, e.msg));
    } else {
      diag.error({file, line, column}, "invalid YAML: " + e.msg);
    }
    return Document{};
  }
  return doc;
}

namespace {

/// The scalar of `node`'s tree that starts on `line` at the greatest column below `column`.
Node scalar_before(Node node, uint32_t line, uint32_t column, Node best = {}) {
  if (!node.valid()) return best;
  if (node.is_scalar()) {
    const SourceMark m = node.mark();
    if (m.line == line && m.column < column && (!best.valid() || m.column > best.mark().column)) return node;
    return best;
  }
  for (size_t i = 0; i < node.size(); ++i) best = scalar_before(node.is_map() ? node.value(i) : node.item(i), line, column, best);
  return best;
}

bool word_byte(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

}  // namespace

SourceMark exact_mark(const Sources& sources, SourceMark mark) {
  if (!mark.valid() || mark.line == 0) return mark;
  const std::string_view line = sources.line(mark);
  // On its line (or just past its end): as placed; unless the line ends in a block scalar's
  // indicator (`expr: >-`) left of the mark: its text starts on the next line.
  const size_t indicator = line.find_last_of(">|");
  const bool block = indicator != std::string_view::npos && mark.column - 1 > indicator &&
                     line.find_first_not_of("-+0123456789 \t", indicator + 1) == std::string_view::npos;
  // And unless an escape precedes it (`\u0020`, a `\` ending the line): a double-quoted
  // scalar's text is then shorter than its source.
  const bool escaped = line.substr(0, std::min<size_t>(mark.column, line.size())).find('\\') != std::string_view::npos;
  if (mark.column <= line.size() + 1 && !block && !escaped) return mark;
  Diagnostics quiet;
  const Document doc = parse(sources, mark.file, quiet);
  if (quiet.has_errors()) return mark;  // invalid YAML (the mark is the parser's): no scalars to look in
  const Node scalar = scalar_before(doc.root(), mark.line, mark.column);
  if (!scalar.valid()) return mark;
  const SourceMark start = scalar.mark();
  const size_t skip = scalar.quoted() ? 1 : 0;
  if (mark.column < start.column + skip) return mark;
  const std::string_view source = sources.text(mark.file);
  auto offset_of = [&](SourceMark m) {  // a mark's byte in the source
    size_t at = 0;
    for (uint32_t l = 1; l < m.line && at != std::string_view::npos; ++l) at = source.find('\n', at) + 1;
    return at + m.column - 1;
  };
  if (!block && mark.column <= line.size() + 1) {
    // On its line, after an escape: moved only when inside that quoted scalar (an error later on
    // the line, `heigth` after `color: "a\u0020b", `, is where it is).
    const size_t open = offset_of(start), at = offset_of(mark);
    if (open >= source.size() || source[open] != '"') return mark;
    size_t close = open + 1;
    while (close < source.size() && source[close] != '"') close += source[close] == '\\' ? 2 : 1;
    if (at > close) return mark;
  }
  const size_t pos = mark.column - start.column - skip;
  const std::string_view text = scalar.text();
  if (pos >= text.size()) return start;
  // The token at pos, and how many times it occurs in the text before.
  size_t from = pos, to = pos + 1;
  if (word_byte(text[pos])) {
    while (from > 0 && word_byte(text[from - 1])) --from;
    while (to < text.size() && word_byte(text[to])) ++to;
  }
  const std::string_view token = text.substr(from, to - from);
  auto whole = [&](std::string_view in, size_t at) {
    if (!word_byte(token.front())) return true;
    return (at == 0 || !word_byte(in[at - 1])) && (at + token.size() >= in.size() || !word_byte(in[at + token.size()]));
  };
  size_t before = 0;
  for (size_t at = text.find(token); at != std::string_view::npos && at < from; at = text.find(token, at + 1))
    if (whole(text, at)) ++before;
  // The same occurrence in the source, from the scalar's start.
  for (size_t at = source.find(token, offset_of(start)); at != std::string_view::npos; at = source.find(token, at + 1)) {
    if (!whole(source, at)) continue;
    if (before-- > 0) continue;
    SourceMark out{mark.file, 1, 1};
    const size_t line_start = source.rfind('\n', at == 0 ? 0 : at - 1);
    for (size_t k = source.find('\n'); k != std::string_view::npos && k < at; k = source.find('\n', k + 1)) ++out.line;
    out.column = static_cast<uint32_t>(at - (line_start == std::string_view::npos || at == 0 ? 0 : line_start + 1) + 1);
    if (at == 0) out.column = 1;
    return out;
  }
  return start;
}

}  // namespace sscs::yaml
