#include "core/selection_calls.h"
#include "core/names.h"

#include <algorithm>
#include <cctype>

#include <fmt/format.h>

namespace sscs {

namespace {

bool ident_start(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool ident_char(char c) { return ident_start(c) || (c >= '0' && c <= '9') || c == '.'; }

/// Trimmed of blanks; a quoted argument (`margin('door clear')`) loses its quotes.
std::string unquoted(std::string_view s) {
  std::string out(trim_blanks(s));
  if (out.size() >= 2 && (out.front() == '"' || out.front() == '\'') && out.back() == out.front()) out = out.substr(1, out.size() - 2);
  return out;
}

constexpr std::pair<const char*, SelectionCall::Kind> kNames[] = {
    {"count", SelectionCall::Kind::Count}, {"sum", SelectionCall::Kind::Sum},       {"min", SelectionCall::Kind::Min},
    {"max", SelectionCall::Kind::Max},     {"avg", SelectionCall::Kind::Avg},       {"min_margin", SelectionCall::Kind::MinMargin},
    {"margin", SelectionCall::Kind::Margin}};

/// Whether one of the top-level arguments of a call is a selector with an attribute (`type:drum.h`,
/// `Rack_*.levels`): not a product (`2*x`) nor a nested call (`count(R_*)`).
bool selector_argument(std::string_view args) {
  int depth = 0;
  size_t start = 0;
  for (size_t i = 0; i <= args.size(); ++i) {
    if (i < args.size() && (args[i] == '(' || args[i] == ')')) depth += args[i] == '(' ? 1 : -1;
    if (i < args.size() && !(args[i] == ',' && depth == 0)) continue;
    std::string_view arg = args.substr(start, i - start);
    start = i + 1;
    size_t a = arg.find_first_not_of(" \t");
    if (a == std::string_view::npos) continue;
    arg.remove_prefix(a);
    if (arg.starts_with("type:")) return true;
    size_t n = 0;
    while (n < arg.size() && (std::isalnum(static_cast<unsigned char>(arg[n])) || arg[n] == '_' || arg[n] == '-' || arg[n] == '*' || arg[n] == '?')) ++n;
    std::string_view head = arg.substr(0, n);
    if (n >= arg.size() || arg[n] != '.') continue;
    // A glob's star stands next to '_' or '-' of a name or ends it (Rack_*, Drum_*_1); a
    // product's stands between operands (x*D1.height).
    for (size_t k = 0; k < head.size(); ++k) {
      if (head[k] == '?') return true;
      if (head[k] != '*') continue;
      bool before = k > 0 && (head[k - 1] == '_' || head[k - 1] == '-');
      bool after = k + 1 == head.size() || head[k + 1] == '_' || head[k + 1] == '-';
      if (before || after) return true;
    }
  }
  return false;
}

}  // namespace

const char* selection_call_name(SelectionCall::Kind kind) {
  for (const auto& [name, k] : kNames)
    if (k == kind) return name;
  return "?";
}

int RewrittenExpression::call_index(std::string_view name) {
  if (!name.starts_with("_call") || name.size() == 5) return -1;
  int n = 0;
  for (char c : name.substr(5)) {
    if (c < '0' || c > '9') return -1;
    n = n * 10 + (c - '0');
  }
  return n;
}

std::string without_position(std::string message) {
  if (size_t at = message.find(" at position "); at != std::string::npos) message.resize(at);
  return message;
}

std::optional<RewrittenExpression> rewrite_selection_calls(std::string_view text, const std::vector<SelectionCall::Kind>& kinds,
                                                           Expression::Error* error) {
  RewrittenExpression out;
  auto fail = [&](size_t position, std::string message) {
    *error = {std::move(message), position};
    return std::nullopt;
  };
  for (size_t i = 0; i < text.size();) {
    if (!ident_start(text[i]) || (i > 0 && ident_char(text[i - 1]))) {
      out.text += text[i++];
      continue;
    }
    size_t end = i;
    while (end < text.size() && ident_char(text[end])) ++end;
    std::string_view word = text.substr(i, end - i);
    size_t open = end;
    while (open < text.size() && text[open] == ' ') ++open;
    auto named = std::find_if(std::begin(kNames), std::end(kNames), [&](const auto& k) { return word == k.first; });
    bool wanted = named != std::end(kNames) && std::find(kinds.begin(), kinds.end(), named->second) != kinds.end();
    if (!wanted || open >= text.size() || text[open] != '(') {
      out.text += word;
      i = end;
      continue;
    }
    int depth = 0, brackets = 0;  // a list's commas (`[A, B].x`) separate no arguments
    size_t close = open, comma = std::string_view::npos;
    for (; close < text.size(); ++close) {
      depth += text[close] == '(' ? 1 : text[close] == ')' ? -1 : 0;
      brackets += text[close] == '[' ? 1 : text[close] == ']' ? -1 : 0;
      if (depth == 1 && brackets == 0 && text[close] == ',' && comma == std::string_view::npos) comma = close;
      if (depth == 0) break;
    }
    SelectionCall::Kind kind = named->second;
    // min(a, b) and max(a, b) are the functions of every expression, not aggregates.
    if ((kind == SelectionCall::Kind::Min || kind == SelectionCall::Kind::Max) && comma != std::string_view::npos) {
      std::string_view args = text.substr(open + 1, close == text.size() ? text.size() - open - 1 : close - open - 1);
      if (selector_argument(args))
        return fail(open + 1, fmt::format("{}() with two arguments takes numbers; over a selection write {}(SELECTOR.attribute) "
                                          "alone", word, word));
      out.text += word;
      i = end;
      continue;
    }
    if (close >= text.size()) return fail(open, fmt::format("'(' of {}() is never closed", word));
    SelectionCall call;
    call.kind = kind;
    call.position = i;
    call.arg_position = open + 1 + (text.substr(open + 1, close - open - 1).find_first_not_of(" \t") == std::string_view::npos
                                        ? 0 : text.substr(open + 1, close - open - 1).find_first_not_of(" \t"));
    std::string arg = unquoted(text.substr(open + 1, close - open - 1));
    switch (kind) {
      case SelectionCall::Kind::MinMargin:
        if (!arg.empty()) return fail(call.arg_position, "min_margin() takes no argument");
        break;
      case SelectionCall::Kind::Margin:
        if (arg.empty()) return fail(call.arg_position, "margin() needs a constraint name, as margin(door clear height)");
        call.constraint = arg;
        break;
      case SelectionCall::Kind::Count:
        if (arg.empty()) return fail(call.arg_position, "count() needs a selector, as count(type:drum)");
        if (arg.find('.') != std::string::npos && !arg.starts_with("at:") && !arg.starts_with('['))
          return fail(call.arg_position, fmt::format("count() takes a selector without an attribute, as count(type:drum); found '{}'", arg));
        call.selector = arg;
        break;
      default: {
        // The selector holds no '.': the attribute is everything after the first one
        // (`Rack_*.location.z`, `type:drum.bbox.max.z`); a list's after its `]`
        // (`[Drum_1, Drum_2].gross_mass`); `at:OBJECT.FRAME`'s after the frame.
        size_t dot = arg.find('.');
        if (arg.starts_with('[')) {
          const size_t close = arg.find(']');
          dot = close == std::string::npos ? std::string::npos : arg.find('.', close);
          if (close == std::string::npos) return fail(call.arg_position, fmt::format("'[' of the selector list in {}() is never closed", word));
        } else if (arg.starts_with("at:") && dot != std::string::npos) {
          dot = arg.find('.', dot + 1);
        }
        if (dot == std::string::npos || dot == 0 || dot + 1 == arg.size())
          return fail(call.arg_position, fmt::format("{}() needs SELECTOR.attribute, as {}(type:drum.fill_mass), found '{}'", word,
                                                     word, arg));
        call.selector = arg.substr(0, dot);
        call.attribute = arg.substr(dot + 1);
      }
    }
    out.text += fmt::format("_call{}", out.calls.size());
    out.calls.push_back(std::move(call));
    i = close + 1;
    out.offsets.anchors.emplace_back(out.text.size(), i);
  }
  return out;
}

}  // namespace sscs
