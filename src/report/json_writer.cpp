#include "report/json_writer.h"

#include "core/units.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iterator>

#include <fmt/compile.h>
#include <fmt/format.h>

namespace sscs {

namespace {

/// The length of the valid UTF-8 sequence at s[i], or 0 when it is not one.
size_t utf8_length(std::string_view s, size_t i) {
  auto c = static_cast<unsigned char>(s[i]);
  size_t n = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  for (size_t k = 1; k < n; ++k)
    if ((static_cast<unsigned char>(s[i + k]) >> 6) != 0x2) return 0;
  if (n == 2 && c < 0xC2) return 0;  // overlong
  if (n == 3) {
    auto c1 = static_cast<unsigned char>(s[i + 1]);
    if ((c == 0xE0 && c1 < 0xA0) || (c == 0xED && c1 >= 0xA0)) return 0;  // overlong, surrogate
  }
  if (n == 4) {
    auto c1 = static_cast<unsigned char>(s[i + 1]);
    if ((c == 0xF0 && c1 < 0x90) || c > 0xF4 || (c == 0xF4 && c1 >= 0x90)) return 0;
  }
  return n;
}

}  // namespace

void append_json_string(std::string& out, std::string_view s) {
  out += '"';
  // Most report text is plain ASCII with nothing to escape: copy it whole.
  bool plain = std::all_of(s.begin(), s.end(), [](char c) {
    auto u = static_cast<unsigned char>(c);
    return u >= 0x20 && u < 0x80 && c != '"' && c != '\\';
  });
  if (plain) {
    out.append(s);
    out.push_back('"');
    return;
  }
  for (size_t i = 0; i < s.size();) {
    char c = s[i];
    switch (c) {
      case '"': out += "\\\""; ++i; continue;
      case '\\': out += "\\\\"; ++i; continue;
      case '\b': out += "\\b"; ++i; continue;
      case '\f': out += "\\f"; ++i; continue;
      case '\n': out += "\\n"; ++i; continue;
      case '\r': out += "\\r"; ++i; continue;
      case '\t': out += "\\t"; ++i; continue;
      default: break;
    }
    auto u = static_cast<unsigned char>(c);
    if (u < 0x20) {
      fmt::format_to(std::back_inserter(out), "\\u{:04x}", u);
      ++i;
      continue;
    }
    size_t n = utf8_length(s, i);
    if (n == 0) {
      out += "\xEF\xBF\xBD";  // U+FFFD for a byte that is no UTF-8
      ++i;
      continue;
    }
    out.append(s.data() + i, n);
    i += n;
  }
  out += '"';
}

void append_json_number(std::string& out, double v) {
  if (!std::isfinite(v)) {
    out += "null";
    return;
  }
  // nlohmann's own conversion (grisu2, the shortest digits it picks, its layout: "750.0",
  // "1e-09"), so the bytes are those of dump() by construction; the property test holds it.
  char text[64];
  char* end = nlohmann::detail::to_chars(text, text + sizeof text, v);
  out.append(text, static_cast<size_t>(end - text));
}

void append_json_stable_number(std::string& out, double v) {
  // nlohmann's grisu2 does not always pick the shortest digits (0.0210993645455 prints as
  // 0.021099364545500002), so no shortcut through "%.12g": the rounded value, converted as dump().
  append_json_number(out, stable(v));
}

void JsonWriter::stable_number(double v) {
  before_value();
  append_json_stable_number(buffer_, v);
}

namespace {
// ",\n" and the indentation of up to 60 levels, appended in one piece.
constexpr size_t kMaxIndent = 120;
const std::string kBreak = ",\n" + std::string(kMaxIndent, ' ');
}  // namespace

void JsonWriter::newline_indent() {
  size_t n = 2 * stack_.size();
  if (n <= kMaxIndent) {
    buffer_.append(kBreak.data() + 1, n + 1);
  } else {
    buffer_ += '\n';
    buffer_.append(n, ' ');
  }
}

void JsonWriter::before_value() {
  if (after_key_) {
    after_key_ = false;
    return;
  }
  if (stack_.empty()) return;
  if (stack_.back().count++ > 0) buffer_ += ',';
  newline_indent();
}

void JsonWriter::key(std::string_view k) {
  size_t n = 2 * stack_.size();
  bool first = stack_.back().count++ == 0;
  if (n <= kMaxIndent) {
    buffer_.append(kBreak.data() + (first ? 1 : 0), n + (first ? 1 : 2));
  } else {
    if (!first) buffer_ += ',';
    newline_indent();
  }
  append_json_string(buffer_, k);
  buffer_.append(": ", 2);
  after_key_ = true;
}

void JsonWriter::open(char bracket) {
  before_value();
  buffer_ += bracket;
  stack_.push_back({bracket == '{' ? '}' : ']'});
}

void JsonWriter::close(char bracket) {
  size_t count = stack_.back().count;
  stack_.pop_back();
  if (count > 0) newline_indent();
  buffer_ += bracket;
  if (stack_.empty()) {
    buffer_ += '\n';
    flush();
  } else {
    maybe_flush();
  }
}

void JsonWriter::string(std::string_view s) {
  before_value();
  append_json_string(buffer_, s);
}

void JsonWriter::literal(std::string_view json) {
  before_value();
  buffer_.append(json);
}

void JsonWriter::number(double v) {
  before_value();
  append_json_number(buffer_, v);
}

void JsonWriter::integer(int64_t v) {
  before_value();
  fmt::format_int text(v);
  buffer_.append(text.data(), text.size());
}

void JsonWriter::unsigned_integer(uint64_t v) {
  before_value();
  fmt::format_int text(v);
  buffer_.append(text.data(), text.size());
}

void JsonWriter::boolean(bool v) {
  before_value();
  buffer_ += v ? "true" : "false";
}

void JsonWriter::null() {
  before_value();
  buffer_ += "null";
}

void JsonWriter::json(const nlohmann::ordered_json& j) {
  before_value();
  // nlohmann's layout at depth 0, indented to this depth; invalid UTF-8 replaced, never thrown.
  std::string text = j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
  for (char c : text) {
    buffer_ += c;
    if (c == '\n') buffer_.append(2 * stack_.size(), ' ');
  }
  maybe_flush();
}

nlohmann::ordered_json number_or_null(const std::optional<double>& v) {
  if (!v || !std::isfinite(*v)) return nullptr;
  return stable(*v);
}

}  // namespace sscs
