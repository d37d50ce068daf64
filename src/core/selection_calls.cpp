#include "core/selection_calls.h"

#include <algorithm>

#include <fmt/format.h>

namespace sscs {

namespace {

bool ident_start(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool ident_char(char c) { return ident_start(c) || (c >= '0' && c <= '9') || c == '.'; }

/// Trimmed of blanks; a quoted argument (`margin('door clear')`) loses its quotes.
std::string trim(std::string_view s) {
  size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  if (a == std::string_view::npos) return {};
  std::string out(s.substr(a, b - a + 1));
  if (out.size() >= 2 && (out.front() == '"' || out.front() == '\'') && out.back() == out.front()) out = out.substr(1, out.size() - 2);
  return out;
}

constexpr std::pair<const char*, SelectionCall::Kind> kNames[] = {
    {"count", SelectionCall::Kind::Count}, {"sum", SelectionCall::Kind::Sum},       {"min", SelectionCall::Kind::Min},
    {"max", SelectionCall::Kind::Max},     {"avg", SelectionCall::Kind::Avg},       {"min_margin", SelectionCall::Kind::MinMargin},
    {"margin", SelectionCall::Kind::Margin}};

}  // namespace

const char* selection_call_name(SelectionCall::Kind kind) {
  for (const auto& [name, k] : kNames)
    if (k == kind) return name;
  return "?";
}

size_t RewrittenExpression::original(size_t pos) const {
  size_t shift_text = 0, shift_original = 0;
  for (const auto& [t, o] : anchors) {
    if (t > pos) break;
    shift_text = t;
    shift_original = o;
  }
  return shift_original + (pos - shift_text);
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
    int depth = 0;
    size_t close = open, comma = std::string_view::npos;
    for (; close < text.size(); ++close) {
      depth += text[close] == '(' ? 1 : text[close] == ')' ? -1 : 0;
      if (depth == 1 && text[close] == ',' && comma == std::string_view::npos) comma = close;
      if (depth == 0) break;
    }
    SelectionCall::Kind kind = named->second;
    // min(a, b) and max(a, b) are the functions of every expression, not aggregates.
    if ((kind == SelectionCall::Kind::Min || kind == SelectionCall::Kind::Max) && comma != std::string_view::npos) {
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
    std::string arg = trim(text.substr(open + 1, close - open - 1));
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
        call.selector = arg;
        break;
      default: {
        // The selector holds no '.': the attribute is everything after the first one
        // (`Rack_*.location.z`, `type:drum.bbox.max.z`).
        size_t dot = arg.find('.');
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
    out.anchors.emplace_back(out.text.size(), i);
  }
  return out;
}

}  // namespace sscs
