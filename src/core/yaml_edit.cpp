#include "core/yaml_edit.h"

#include <algorithm>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace sscs::yaml {

namespace {

std::string double_quoted(std::string_view s) {
  // A JSON string is a valid YAML double-quoted scalar with the same escapes.
  return nlohmann::json(std::string(s)).dump();
}

bool plain_safe(std::string_view s) {
  if (s.empty() || s.front() == ' ' || s.back() == ' ') return false;
  if (std::string_view("-?:,[]{}#&*!|>'\"%@`").find(s.front()) != std::string_view::npos) return false;
  for (char c : s)
    if (c == ',' || c == '[' || c == ']' || c == '{' || c == '}' || c == '\n' || c == '"' || c == '\'') return false;
  return s.find(": ") == std::string_view::npos && s.find(" #") == std::string_view::npos;
}

const std::optional<std::string>* change_for(const std::vector<TopLevelChange>& changes, std::string_view key) {
  for (const auto& [k, v] : changes)
    if (k == key) return &v;
  return nullptr;
}

bool blank_or_comment(std::string_view line) {
  size_t i = line.find_first_not_of(" \t\r\n");
  return i == std::string_view::npos || line[i] == '#';
}

}  // namespace

std::string flow_scalar(std::string_view s) { return plain_safe(s) ? std::string(s) : double_quoted(s); }

std::string to_flow(Node node) {
  switch (node.kind()) {
    case Kind::Null: return "null";
    case Kind::Scalar: return node.quoted() ? double_quoted(node.text()) : std::string(node.text());
    case Kind::Sequence: {
      std::vector<std::string> items;
      for (size_t i = 0; i < node.size(); ++i) items.push_back(to_flow(node.item(i)));
      return fmt::format("[{}]", fmt::join(items, ", "));
    }
    case Kind::Map: {
      std::vector<std::string> items;
      for (size_t i = 0; i < node.size(); ++i)
        items.push_back(fmt::format("{}: {}", to_flow(node.key(i)), to_flow(node.value(i))));
      return fmt::format("{{{}}}", fmt::join(items, ", "));
    }
  }
  return "null";
}

std::string replace_top_level(std::string_view text, Node root, const std::vector<TopLevelChange>& changes) {
  std::vector<std::string> added;
  for (const auto& [key, value] : changes)
    if (value && !root.find(key).valid()) added.push_back(fmt::format("{}: {}\n", key, *value));

  // Lines, each with its line break.
  std::vector<std::string_view> lines;
  for (size_t at = 0; at < text.size();) {
    size_t end = text.find('\n', at);
    end = end == std::string_view::npos ? text.size() : end + 1;
    lines.push_back(text.substr(at, end - at));
    at = end;
  }
  bool block = root.size() > 0;
  for (size_t i = 0; i < root.size() && block; ++i)
    block = root.key(i).mark().column == 1 && (i == 0 || root.key(i).mark().line > root.key(i - 1).mark().line);
  if (!block) {
    std::vector<std::string> items;
    for (size_t i = 0; i < root.size(); ++i) {
      const auto* change = change_for(changes, root.key(i).text());
      if (change && !*change) continue;
      items.push_back(fmt::format("{}: {}", to_flow(root.key(i)), change ? **change : to_flow(root.value(i))));
    }
    for (const std::string& a : added) items.push_back(a.substr(0, a.size() - 1));
    return fmt::format("{{{}}}\n", fmt::join(items, ", "));
  }

  std::string out;
  size_t first = root.key(0).mark().line - 1;
  for (size_t l = 0; l < first; ++l) out += lines[l];
  for (size_t i = 0; i < root.size(); ++i) {
    size_t begin = root.key(i).mark().line - 1;
    size_t end = i + 1 < root.size() ? root.key(i + 1).mark().line - 1 : lines.size();
    const auto* change = change_for(changes, root.key(i).text());
    if (!change) {
      for (size_t l = begin; l < end; ++l) out += lines[l];
      continue;
    }
    if (*change) out += fmt::format("{}: {}\n", root.key(i).text(), **change);
    size_t tail = end;
    while (tail > begin + 1 && blank_or_comment(lines[tail - 1])) --tail;
    for (size_t l = tail; l < end; ++l) out += lines[l];
  }
  if (!out.empty() && out.back() != '\n') out += '\n';
  for (const std::string& a : added) out += a;
  return out;
}

}  // namespace sscs::yaml
