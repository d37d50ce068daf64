#include "core/diagnostics.h"

#include <fmt/format.h>

#include "core/yaml_tree.h"

namespace sscs {

std::string printable(std::string_view line, bool keep_newlines) {
  std::string out(line);
  auto* s = reinterpret_cast<unsigned char*>(out.data());
  for (size_t i = 0; i < out.size();) {
    unsigned char c = s[i];
    size_t len = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    bool ok = len != 0 && i + len <= out.size() && c != 0x7F && (c >= 0x20 || c == '\t' || (keep_newlines && c == '\n'));
    for (size_t k = 1; ok && k < len; ++k) ok = (s[i + k] & 0xC0) == 0x80;
    // Bidirectional controls reorder what a terminal draws after them (a constraint named with a
    // right-to-left override printed the rest of its line backwards): U+061C, U+200E/F,
    // U+202A..E, U+2066..9 become '?' too.
    if (ok && len == 2 && c == 0xD8 && s[i + 1] == 0x9C) ok = false;
    if (ok && len == 3 && c == 0xE2 && s[i + 1] == 0x80 && (s[i + 2] == 0x8E || s[i + 2] == 0x8F || (s[i + 2] >= 0xAA && s[i + 2] <= 0xAE)))
      ok = false;
    if (ok && len == 3 && c == 0xE2 && s[i + 1] == 0x81 && s[i + 2] >= 0xA6 && s[i + 2] <= 0xA9) ok = false;
    if (!ok && len > 1 && i + len <= out.size()) {
      for (size_t k = 0; k < len; ++k) s[i + k] = '?';  // one '?' a byte: columns stay
      i += len;
      continue;
    }
    if (!ok) {
      s[i++] = '?';
      continue;
    }
    i += len;
  }
  return out;
}

std::string within_window(std::string_view text, size_t max) {
  if (text.size() <= max) return std::string(text);
  size_t head = max / 2, tail = max / 4;
  while (head > 0 && (static_cast<unsigned char>(text[head]) & 0xC0) == 0x80) --head;  // whole UTF-8 characters
  size_t from = text.size() - tail;
  while (from < text.size() && (static_cast<unsigned char>(text[from]) & 0xC0) == 0x80) ++from;
  return fmt::format("{} … ({} bytes not shown) … {}", text.substr(0, head), from - head, text.substr(from));
}


void Diagnostics::error(SourceMark mark, std::string message) {
  // Once each: the same mistake at the same place, met again (one line that makes forty objects,
  // a campaign's forty loads), is one error.
  for (const Diagnostic& e : errors_)
    if (e.mark.file == mark.file && e.mark.line == mark.line && e.mark.column == mark.column && e.message == message) return;
  ++count_;
  if (errors_.size() < limit_) errors_.push_back({mark, std::move(message)});
}

void Diagnostics::warning(SourceMark mark, std::string message) {
  if (strict_) {
    if (!strict_note_.empty()) message += " " + strict_note_;
    for (const Diagnostic& e : errors_)  // once each, as a warning is
      if (e.mark.file == mark.file && e.mark.line == mark.line && e.mark.column == mark.column && e.message == message) return;
    error(mark, std::move(message));
    return;
  }
  for (const Diagnostic& w : warnings_)  // a type used by many objects warns once
    if (w.mark.file == mark.file && w.mark.line == mark.line && w.mark.column == mark.column && w.message == message) return;
  if (warnings_.size() < limit_) warnings_.push_back({mark, std::move(message), true});
}

namespace {

/// Longer source lines are shown as this many bytes around the column.
constexpr size_t kLongLine = 160;

/// One diagnostic: `file:line:col: error: message`, the source line and a caret under the column.
std::string format_one(const Diagnostic& d, const Sources& sources, bool color) {
  const char* bold = color ? "\033[1m" : "";
  const char* word_colour = color ? (d.warning ? "\033[1;33m" : "\033[1;31m") : "";
  const char* green = color ? "\033[1;32m" : "";
  const char* reset = color ? "\033[0m" : "";
  const char* word = d.warning ? "warning" : "error";
  std::string out;
  const SourceMark mark = yaml::exact_mark(sources, d.mark);  // inside a scalar written over several lines
  if (mark.valid()) {
    out += fmt::format("{}{}:{}:{}:{} {}{}:{} {}\n", bold, sources.path(mark.file), mark.line, sources.character_column(mark), reset, word_colour,
                       word, reset, printable(within_window(d.message), true));
    std::string_view line = sources.line(mark);
    size_t at = mark.column > 0 ? mark.column - 1 : 0;  // the caret's byte in `line`
    // A long line (a vault written as one flow mapping) shows the stretch around the column.
    std::string before, after;
    if (line.size() > kLongLine) {
      size_t from = at > kLongLine / 2 ? at - kLongLine / 2 : 0;
      while (from > 0 && from < line.size() && (static_cast<unsigned char>(line[from]) & 0xC0) == 0x80) --from;  // a character's start
      size_t to = std::min(line.size(), from + kLongLine);
      while (to < line.size() && (static_cast<unsigned char>(line[to]) & 0xC0) == 0x80) ++to;
      if (from > 0) before = "...";
      if (to < line.size()) after = "...";
      line = line.substr(from, to - from);
      at = at - from + before.size();
    }
    if (!line.empty()) {
      out += fmt::format("  {}{}{}\n", before, printable(line), after);
      // Under the column's character: a space for each character before it (a tab for a tab).
      std::string caret(before.size(), ' ');
      for (size_t i = 0; i + before.size() < at; ++i) {
        if (i >= line.size()) caret += ' ';
        else if (line[i] == '\t') caret += '\t';
        else if ((static_cast<unsigned char>(line[i]) & 0xC0) != 0x80) caret += ' ';
      }
      out += fmt::format("  {}{}^{}\n", caret, green, reset);
    }
  } else {
    out += fmt::format("{}sscs:{} {}{}:{} {}\n", bold, reset, word_colour, word, reset, printable(within_window(d.message), true));
  }
  return out;
}

}  // namespace

std::string Diagnostics::format_errors(const Sources& sources, bool color) const {
  examined_errors_ = errors_.size();
  std::string out;
  for (const Diagnostic& d : errors_) out += format_one(d, sources, color);
  if (count_ > errors_.size())
    out += fmt::format("sscs: {} more errors not shown (limit {})\n", count_ - errors_.size(), limit_);
  return out;
}

std::string Diagnostics::format(const Sources& sources, bool color) const {
  examined_warnings_ = warnings_.size();
  std::string out;
  for (const Diagnostic& d : warnings_) out += format_one(d, sources, color);
  return out + format_errors(sources, color);
}

}  // namespace sscs
