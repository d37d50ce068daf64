#include "lsp/server.h"

#include <algorithm>
#include <filesystem>
#include <regex>

#include <fmt/format.h>

#include "core/files.h"
#include "core/names.h"
#include "core/units.h"
#include "load/spec.h"
#include "pipeline/type_listing.h"
#include "report/report.h"

namespace sscs::lsp {

using nlohmann::json;

namespace {

// JSON-RPC's and LSP's error codes.
constexpr int kInvalidRequest = -32600, kMethodNotFound = -32601, kInvalidParams = -32602,
              kServerNotInitialized = -32002, kInternalError = -32603;
// LSP's kinds.
constexpr int kSymbolObject = 19, kSymbolBoolean = 17;
constexpr int kItemField = 5, kItemVariable = 6, kItemClass = 7, kItemKeyword = 14, kItemReference = 18;
constexpr size_t kMostItems = 1000;  ///< completion items at once (a 10,000-object vault): the list says it is incomplete

struct RpcError {
  int code;
  std::string message;
};

std::vector<std::string_view> split_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  size_t pos = 0;
  while (true) {
    const size_t end = text.find('\n', pos);
    std::string_view line = text.substr(pos, end == std::string_view::npos ? std::string_view::npos : end - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    if (end == std::string_view::npos) break;
    pos = end + 1;
  }
  return lines;
}

size_t indent_of(std::string_view line) { return std::min(line.find_first_not_of(' '), line.size()); }
bool blank(std::string_view line) {
  const size_t i = indent_of(line);
  return i == line.size() || line[i] == '#';
}
/// Whether a byte ends a token: YAML's flow punctuation, spaces, quotes and comments.
bool token_end(char c) {
  return c == ' ' || c == '\t' || c == ',' || c == '[' || c == ']' || c == '{' || c == '}' || c == '"' || c == '\'' || c == '#' ||
         c == '(' || c == ')' || c == '+' || c == '-' || c == '/' || c == '<' || c == '>' || c == '=' || c == '&' || c == '|';
}

/// The key a line sets at its start (`  - type: drum` -> "type"), or "".
std::string line_key(std::string_view line) {
  static const std::regex key(R"(^\s*(?:-\s+)*([A-Za-z_][A-Za-z0-9_]*)\s*:(\s|$))");
  std::match_results<std::string_view::const_iterator> m;
  return std::regex_search(line.begin(), line.end(), m, key) ? m[1].str() : "";
}

/// Where the cursor is, read from the buffer's lines: the buffer may be half typed, no YAML at all.
struct Cursor {
  std::vector<std::string_view> lines;
  int line = 0;
  std::string_view token;         ///< the token around the cursor (`Rack_1.slot_2`, `type:drum`, `heig`)
  size_t start = 0, end = 0;      ///< its bytes in the line
  std::string_view prefix;        ///< its part before the cursor
  bool is_key = false;            ///< the token is a key (`height:`, or a bare word alone on its line)
  std::string key;                ///< the key whose value holds the token, "" for none
  std::string section;            ///< the top-level key whose block holds the line
  int item = -1;                  ///< the line of the section's list item holding it, or -1
  size_t list_indent = 0;         ///< the indentation of the section's items' `-`
};

/// The position of the last `[` of `s` that is not closed, or npos.
size_t unclosed_bracket(std::string_view s) {
  int depth = 0;
  for (size_t i = s.size(); i-- > 0;) {
    if (s[i] == ']' || s[i] == '}') ++depth;
    else if (s[i] == '[' || s[i] == '{') {
      if (depth == 0) return i;
      --depth;
    }
  }
  return std::string_view::npos;
}

/// The key whose value the text before a token sets: `a: [B, ` -> a; `{device: R, target: ` -> target.
std::string value_key(std::string_view before) {
  for (int guard = 0; guard < 8; ++guard) {
    while (!before.empty() && (before.back() == ' ' || before.back() == '\t' || before.back() == '!' || before.back() == '"' ||
                              before.back() == '\'')) before.remove_suffix(1);
    if (!before.empty() && before.back() == ':') {
      before.remove_suffix(1);
      size_t b = before.size();
      while (b > 0 && (std::isalnum(static_cast<unsigned char>(before[b - 1])) || before[b - 1] == '_')) --b;
      return std::string(before.substr(b));
    }
    // Inside a flow list: the key before its bracket (a flow map's key is found above).
    const size_t open = unclosed_bracket(before);
    if (open == std::string_view::npos || before[open] != '[') return "";
    before = before.substr(0, open);
  }
  return "";
}

Cursor cursor_at(std::string_view text, int line, int character, bool utf8) {
  Cursor c;
  c.lines = split_lines(text);
  if (line < 0 || line >= static_cast<int>(c.lines.size())) return c;
  c.line = line;
  const std::string_view l = c.lines[line];
  const size_t at = byte_column(l, character, utf8);
  c.start = at;
  while (c.start > 0 && !token_end(l[c.start - 1])) --c.start;
  c.end = at;
  while (c.end < l.size() && !token_end(l[c.end])) ++c.end;
  c.token = l.substr(c.start, c.end - c.start);
  c.prefix = l.substr(c.start, at - c.start);
  const std::string_view before = l.substr(0, c.start);
  const bool line_start = std::regex_match(before.begin(), before.end(), std::regex(R"(\s*(-\s+)*)"));
  const std::string_view trimmed = before.substr(0, before.find_last_not_of(" \t") + 1);
  const bool key_place = line_start || (!trimmed.empty() && (trimmed.back() == '{' || trimmed.back() == ','));
  if (!c.token.empty() && c.token.back() == ':' && key_place) {  // `height:` under the cursor: a key
    c.token.remove_suffix(1);
    if (c.prefix.size() > c.token.size()) c.prefix = c.token;
    c.is_key = true;
  } else if (line_start && c.token.find(':') == std::string_view::npos) {
    c.is_key = true;  // a word alone on its line: a key being typed (or a block list's item: its key is found below)
  } else {
    c.key = value_key(before);
    if (c.key.empty()) {  // inside an expression after its first token (`expr: "A.height <= g`): the key it is under
      static const std::regex key(R"(([A-Za-z_][A-Za-z0-9_]*)\s*:\s)");
      for (auto it = std::regex_iterator<std::string_view::const_iterator>(before.begin(), before.end(), key);
           it != std::regex_iterator<std::string_view::const_iterator>(); ++it)
        c.key = (*it)[1].str();
    }
  }
  // A block list's item (`  - Drum_1` under `objects:`): the key above it.
  if (line_start && before.find('-') != std::string_view::npos && c.key.empty()) {
    const size_t indent = indent_of(l);
    for (int k = line - 1; k >= 0; --k) {
      if (blank(c.lines[k])) continue;
      if (indent_of(c.lines[k]) < indent) {
        std::string_view above = c.lines[k];
        while (!above.empty() && above.back() == ' ') above.remove_suffix(1);
        if (!above.empty() && above.back() == ':') c.key = line_key(above);
        break;
      }
    }
  }
  // The section (a top-level key) and the list item holding the line.
  int section_line = -1;
  for (int k = line; k >= 0; --k)
    if (!blank(c.lines[k]) && indent_of(c.lines[k]) == 0 && (k < line || !c.is_key)) {
      c.section = line_key(c.lines[k]);
      section_line = k;
      break;
    }
  if (section_line < 0) return c;
  for (int k = section_line + 1; k < static_cast<int>(c.lines.size()); ++k) {
    if (blank(c.lines[k])) continue;
    const std::string_view s = c.lines[k].substr(indent_of(c.lines[k]));
    if (s.empty() || s[0] != '-') return c;  // the section is no list
    c.list_indent = indent_of(c.lines[k]);
    break;
  }
  for (int k = line; k > section_line; --k) {
    const std::string_view s = c.lines[k];
    if (indent_of(s) == c.list_indent && indent_of(s) < s.size() && s[indent_of(s)] == '-') {
      c.item = k;
      break;
    }
    if (!blank(s) && indent_of(s) < c.list_indent) break;
  }
  // A line of its own at or left of the items' dash (a top-level key being typed) is in no item.
  if (c.item >= 0 && c.item != line && c.start <= c.list_indent) c.item = -1;
  return c;
}

/// The last line of the list item starting at `item`.
int item_end(const Cursor& c, int item) {
  int last = item;
  for (int k = item + 1; k < static_cast<int>(c.lines.size()); ++k) {
    if (blank(c.lines[k])) continue;
    if (indent_of(c.lines[k]) <= c.list_indent) break;
    last = k;
  }
  return last;
}

/// Where the value of `key` of the list item at `item` is written: line and byte column, and the
/// value as written (quotes and comment removed). Block keys at the item's level, or a flow map.
struct Found {
  int line = -1;
  size_t column = 0;
  std::string value;
};
Found item_value(const Cursor& c, int item, std::string_view key) {
  if (item < 0) return {};
  const std::regex pattern(fmt::format(R"((^|[\s{{,-]){}\s*:(?:\s+("[^"]*"|'[^']*'|[^\s,}}#][^,}}#]*)|\s*$))", key));
  const int last = item_end(c, item);
  const size_t key_indent = [&] {
    const std::string_view s = c.lines[item];
    const size_t dash = indent_of(s);
    const size_t after = s.find_first_not_of(' ', dash + 1);
    return after == std::string_view::npos ? dash + 2 : after;
  }();
  for (int k = item; k <= last; ++k) {
    const std::string_view s = c.lines[k];
    if (k != item && indent_of(s) != key_indent && s.find('{') == std::string_view::npos) continue;
    std::match_results<std::string_view::const_iterator> m;
    if (!std::regex_search(s.begin(), s.end(), m, pattern)) continue;
    std::string value = m[2].matched ? m[2].str() : "";  // a block's key (`bound:` over its lines): no value here
    while (!value.empty() && value.back() == ' ') value.pop_back();
    const size_t column = m[2].matched ? static_cast<size_t>(m.position(2)) : s.size();
    if (value.size() >= 2 && (value.front() == '"' || value.front() == '\'')) value = value.substr(1, value.size() - 2);
    return {k, column, value};
  }
  return {};
}

/// The objects a name as written in a vault names: one, a glob, or an array's `Rack_{i}`.
std::vector<int> objects_named(const Workcell& wc, std::string_view name) {
  std::string pattern;
  bool braces = false;
  for (size_t i = 0; i < name.size(); ++i) {
    if (name[i] == '{') {
      const size_t close = name.find('}', i);
      if (close == std::string_view::npos) break;
      pattern += '*';
      i = close;
      braces = true;
    } else {
      pattern += name[i];
    }
  }
  if (!braces && pattern.find_first_of("*?") == std::string::npos) {
    const int o = wc.find_object(pattern);
    return o < 0 ? std::vector<int>{} : std::vector<int>{o};
  }
  std::vector<int> out;
  for (size_t o = 0; o < wc.objects.size(); ++o)
    if (glob_match(pattern, wc.objects[o].name)) out.push_back(static_cast<int>(o));
  return out;
}

std::string md_escape(std::string_view text) {
  std::string out;
  for (char ch : text) {
    if (ch == '|' || ch == '*' || ch == '_' || ch == '`' || ch == '<' || ch == '[' || ch == ']' || ch == '\\') out += '\\';
    out += ch == '\n' ? ' ' : ch;
  }
  return out;
}

std::string limits_text(const AttributeDef& a) {
  const char* unit = file_unit(a.dim);
  auto side = [&](const std::optional<double>& si, const ValueRef& expr) -> std::string {
    if (si) return number_text(stable(si_to_file(*si, a.dim)));
    return expr.present ? "(expression)" : "";
  };
  const std::string lo = side(a.min_si, a.min_expr), hi = side(a.max_si, a.max_expr);
  if (lo.empty() && hi.empty()) return a.values.empty() ? "" : fmt::format("{}", fmt::join(a.values, ", "));
  return fmt::format("{} to {}{}{}", lo.empty() ? "-inf" : lo, hi.empty() ? "inf" : hi, *unit ? " " : "", unit);
}

std::string type_markdown(const Workcell& wc, int t) {
  const ObjectType& type = wc.types[t];
  std::string md = fmt::format("**{}**", md_escape(type.name));
  if (!type.extends.empty()) md += fmt::format(" extends `{}`", type.extends);
  if (type.device) md += " · device";
  if (type.container) md += " · container";
  if (type.zone) md += " · zone";
  if (!type.description.empty()) md += "\n\n" + md_escape(type.description);
  if (!type.attributes.empty()) {
    md += "\n\n| attribute | type | unit | default | limits | description |\n|---|---|---|---|---|---|\n";
    for (const AttributeDef& a : type.attributes)
      md += fmt::format("| {}{} | {} | {} | {} | {} | {} |\n", md_escape(a.name), a.joint ? " (joint)" : "", attr_type_name(a.type),
                        file_unit(a.dim), md_escape(a.default_value.present ? a.default_value.text : "required"),
                        md_escape(limits_text(a)), md_escape(a.description));
  }
  if (!type.path.empty()) md += fmt::format("\n\nDefined in `{}`", type.path);
  return md;
}

std::string attribute_value(const Workcell& wc, int o, int attribute) {
  const Object& obj = wc.objects[o];
  const AttributeDef& a = wc.types[obj.type].attributes[attribute];
  const size_t slot = obj.first_slot + kFirstAttributeSlot + attribute;
  if (a.type == AttrType::String || a.type == AttrType::Enum) return slot < wc.texts.size() ? fmt::format("'{}'", wc.texts[slot]) : "";
  return slot < wc.values.size() ? with_unit(wc.values[slot], a.dim) : "";
}

std::string object_markdown(const Analysis& a, const std::vector<int>& objects) {
  const Workcell& wc = *a.wc;
  std::string md;
  if (objects.size() > 1) {
    std::vector<std::string> names;
    for (int o : objects) names.push_back(wc.objects[o].name);
    md = fmt::format("**{} objects**: {}\n\nThe first:\n\n", objects.size(), md_escape(name_list(names, 12)));
  }
  const int o = objects.front();
  const Object& obj = wc.objects[o];
  md += fmt::format("**{}**: `{}`", md_escape(obj.name), wc.types[obj.type].name);
  std::vector<std::optional<Eigen::Isometry3d>> known(wc.objects.size());
  const Eigen::Isometry3d X = wc.pose_in_world(o, known);
  md += fmt::format("\n\n- world position: {} m", vec_text(X.translation()));
  if (auto rpy = frame_rpy_deg(X)) md += fmt::format(", roll pitch yaw {} deg", vec_text(*rpy));
  if (static_cast<size_t>(o) < a.geometry.objects.size() && !a.geometry.objects[o].bbox_world.isEmpty()) {
    const Eigen::AlignedBox3d& b = a.geometry.objects[o].bbox_world;
    md += fmt::format("\n- bounding box: {} to {} m (size {})", vec_text(b.min()), vec_text(b.max()), vec_text(b.sizes()));
  }
  if (obj.parent >= 0)
    md += fmt::format("\n- {} `{}{}{}`", obj.at.empty() ? "parent" : "at", wc.objects[obj.parent].name, obj.at.empty() ? "" : ".", obj.at);
  return md;
}

std::string constraint_markdown(const Analysis& a, int c) {
  const Workcell& wc = *a.wc;
  const Constraint& con = wc.constraints[c];
  std::string md = fmt::format("**{}** [{}]{}", md_escape(con.name), con.kind, con.severity == Severity::Warning ? " (warning)" : "");
  if (!con.description.empty()) md += "\n\n" + md_escape(con.description);
  if (!a.report) return md + "\n\nNot checked: the vault has input errors.";
  size_t passed = 0, failed = 0, shown = 0;
  std::string lines;
  for (const CheckResult& r : a.report->results) {
    if (r.constraint != c) continue;
    (r.status == Status::Pass ? passed : failed)++;
    if (shown == 10) continue;
    ++shown;
    lines += fmt::format("\n- {}: {}{}", status_name(r.status), md_escape(r.message), margin_text(r));
  }
  md += fmt::format("\n\nLast check: {} passed, {} failed{}", passed, failed, lines);
  if (passed + failed > shown) md += fmt::format("\n- … and {} more", passed + failed - shown);
  return md;
}

json position(int line, int character) { return {{"line", line}, {"character", character}}; }
json range_json(const Range& r) { return {{"start", position(r.line, r.character)}, {"end", position(r.end_line, r.end_character)}}; }

int parameter_named(const Workcell& wc, std::string_view name) {
  for (size_t p = 0; p < wc.parameters.size(); ++p)
    if (wc.parameters[p].name == name) return static_cast<int>(p);
  return -1;
}

int constraint_named(const Workcell& wc, std::string_view name) {
  for (size_t c = 0; c < wc.constraints.size(); ++c)
    if (wc.constraints[c].name == name) return static_cast<int>(c);
  return -1;
}

/// Whether the analysis read the file `path` (absolute, lexically normal).
bool reads(const Analysis& a, const std::string& path) {
  for (uint32_t f = 1; f < a.sources.size(); ++f)
    if (std::filesystem::absolute(a.sources.path(f)).lexically_normal() == path) return true;
  return false;
}

/// Keys whose values name objects (and their frames): selectors, targets, placements.
bool names_objects(std::string_view key) {
  static const std::set<std::string, std::less<>> keys = {"at", "parent", "objects", "a", "b", "targets", "target", "device",
                                                         "container", "carrying", "grasp", "object", "orbit_target", "load",
                                                         "loads", "subjects", "to", "from", "on"};
  return keys.count(key) > 0;
}
/// Keys whose values are expressions over objects' attributes (`bound: [A.width, LT, B.width]` too).
bool holds_expression(std::string_view key) { return key == "lhs" || key == "rhs" || key == "expr" || key == "value" || key == "bound"; }

}  // namespace

std::string uri_to_path(const std::string& uri) {
  constexpr std::string_view scheme = "file://";
  if (uri.compare(0, scheme.size(), scheme) != 0) return "";
  std::string out;
  for (size_t i = scheme.size(); i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return std::filesystem::path(out).lexically_normal().string();
}

std::string path_to_uri(const std::string& path) {
  std::string out = "file://";
  for (unsigned char ch : path) {
    if (std::isalnum(ch) || ch == '/' || ch == '-' || ch == '_' || ch == '.' || ch == '~') out += static_cast<char>(ch);
    else out += fmt::format("%{:02X}", ch);
  }
  return out;
}

Server::Server(Send send, ServerOptions options) : send_(std::move(send)), options_(std::move(options)) {
  if (options_.threaded) worker_ = std::thread([this] { work(); });
}

Server::~Server() {
  bool stuck = false;
  {
    std::lock_guard lock(m_);
    stop_ = true;
    stuck = busy_;
  }
  cv_.notify_all();
  if (!worker_.joinable()) return;
  if (stuck) worker_.detach();  // a compile that never ends: the process is leaving anyway
  else worker_.join();
}

void Server::send(const json& message) {
  std::lock_guard lock(send_m_);
  send_(message);
}

bool Server::handle(const json& message) {
  if (!message.is_object() || message.value("jsonrpc", "") != "2.0") {
    send({{"jsonrpc", "2.0"}, {"id", nullptr}, {"error", {{"code", kInvalidRequest}, {"message", "not a JSON-RPC 2.0 message"}}}});
    return true;
  }
  const bool has_id = message.contains("id");
  if (!message.contains("method")) return true;  // a response to something we never ask
  if (!message["method"].is_string()) {
    if (has_id) send({{"jsonrpc", "2.0"}, {"id", message["id"]}, {"error", {{"code", kInvalidRequest}, {"message", "method is no string"}}}});
    return true;
  }
  const std::string method = message["method"];
  const json params = message.value("params", json::object());
  if (!has_id) {
    if (method == "exit") return false;
    if (initialized_ && !shutdown_) {
      try {
        notification(method, params);
      } catch (const std::exception& e) {  // a notification has no answer: say it in the log
        send({{"jsonrpc", "2.0"}, {"method", "window/logMessage"}, {"params", {{"type", 1}, {"message", fmt::format("sscs: {}: {}", method, e.what())}}}});
      }
    }
    return true;
  }
  json reply = {{"jsonrpc", "2.0"}, {"id", message["id"]}};
  try {
    if (method != "initialize" && !initialized_) throw RpcError{kServerNotInitialized, "initialize first"};
    if (shutdown_ && method != "shutdown") throw RpcError{kInvalidRequest, "the server is shutting down"};
    reply["result"] = request(method, params);
  } catch (const RpcError& e) {
    reply["error"] = {{"code", e.code}, {"message", e.message}};
  } catch (const json::exception& e) {
    reply["error"] = {{"code", kInvalidParams}, {"message", fmt::format("{}: invalid params: {}", method, e.what())}};
  } catch (const std::exception& e) {
    reply["error"] = {{"code", kInternalError}, {"message", fmt::format("{}: {}", method, e.what())}};
  }
  send(reply);
  return true;
}

json Server::request(const std::string& method, const json& params) {
  if (method == "initialize") {
    if (initialized_) throw RpcError{kInvalidRequest, "initialize came twice"};
    initialized_ = true;
    for (const json& e : params.value("/capabilities/general/positionEncodings"_json_pointer, json::array()))
      if (e == "utf-8") utf8_ = true;
    // (The workspace's folders are not needed: each file reads within its own project root.)
    return {{"capabilities",
             {{"positionEncoding", utf8_ ? "utf-8" : "utf-16"},
              {"textDocumentSync", {{"openClose", true}, {"change", 2}, {"save", {{"includeText", false}}}}},
              {"hoverProvider", true},
              {"definitionProvider", true},
              {"completionProvider", {{"triggerCharacters", {".", ":", " ", "["}}}},
              {"documentSymbolProvider", true}}},
            {"serverInfo", {{"name", "sscs"}, {"version", SSCS_VERSION}}}};
  }
  if (method == "shutdown") {
    shutdown_ = true;
    return nullptr;
  }
  if (method.rfind("textDocument/", 0) == 0) {
    const std::string path = uri_to_path(params.at("textDocument").at("uri").get<std::string>());
    auto doc = docs_.find(path);
    if (doc == docs_.end()) throw RpcError{kInvalidParams, fmt::format("{} is not open", params["textDocument"]["uri"].get<std::string>())};
    if (method == "textDocument/documentSymbol") return symbols(doc->second);
    const int line = params.at("position").at("line"), character = params.at("position").at("character");
    if (method == "textDocument/hover") return hover(doc->second, line, character);
    if (method == "textDocument/definition") return definition(doc->second, line, character);
    if (method == "textDocument/completion") return completion(doc->second, line, character);
  }
  throw RpcError{kMethodNotFound, fmt::format("sscs lsp does not answer '{}'", method)};
}

void Server::notification(const std::string& method, const json& params) {
  if (method.rfind("textDocument/did", 0) != 0) return;  // initialized, $/cancelRequest, workspace/...: nothing to do
  const std::string uri = params.at("textDocument").at("uri");
  const std::string path = uri_to_path(uri);
  if (path.empty()) return;  // an untitled buffer: no file its references could be relative to
  if (method == "textDocument/didOpen") {
    Doc& d = docs_[path];
    d.uri = uri;
    d.text = params["textDocument"].at("text");
  } else if (method == "textDocument/didChange") {
    auto it = docs_.find(path);
    if (it == docs_.end()) return;
    std::string& text = it->second.text;
    for (const json& change : params.at("contentChanges")) {
      if (!change.contains("range")) {
        text = change.at("text");
        continue;
      }
      // An edit of a range: its positions to byte offsets, in the client's encoding.
      auto offset = [&](const json& p) {
        const int want = p.at("line");
        size_t pos = 0;
        for (int l = 0; l < want; ++l) {
          const size_t nl = text.find('\n', pos);
          if (nl == std::string::npos) return text.size();
          pos = nl + 1;
        }
        const size_t end = std::min(text.find('\n', pos), text.size());
        return pos + byte_column(std::string_view(text).substr(pos, end - pos), p.at("character"), utf8_);
      };
      const size_t from = offset(change["range"].at("start")), to = std::max(from, offset(change["range"].at("end")));
      text.replace(from, to - from, change.at("text").get<std::string>());
    }
  } else if (method == "textDocument/didClose") {
    docs_.erase(path);
  } else if (method != "textDocument/didSave") {
    return;
  }
  auto doc = docs_.find(path);
  if (doc != docs_.end()) {
    // A file that no longer says what it is (emptied, half deleted) is still what it was: its
    // errors show, and the old ones go.
    const FileKind kind = file_kind(doc->second.text);
    if (kind != FileKind::Other || method == "textDocument/didOpen") doc->second.kind = kind;
    if (params["textDocument"].contains("version")) doc->second.version = params["textDocument"]["version"];
  }
  {
    std::lock_guard lock(m_);
    auto texts = std::make_shared<Sources::Unsaved>();
    for (const auto& [p, d] : docs_) texts->emplace(p, d.text);
    unsaved_ = std::move(texts);
    if (doc != docs_.end()) {
      open_[path] = doc->second.kind;
      versions_[path] = doc->second.version;
    } else {  // closed: what it published goes, and the files that read it read the disk again
      open_.erase(path);
      analyses_.erase(path);
      good_.erase(path);
      publish(path, {});
      published_.erase(path);
    }
  }
  changed(path);
}

void Server::changed(const std::string& path) {
  {
    std::lock_guard lock(m_);
    if (auto it = open_.find(path); it != open_.end() && it->second != FileKind::Other) pending_.insert(path);
    for (const auto& [p, a] : analyses_)
      if (p != path && open_.count(p) && reads(*a, path)) pending_.insert(p);
    if (busy_ && pending_.count(compiling_)) cancel_ = true;  // its check is of older text: it stops, and runs again
  }
  if (options_.threaded) {
    cv_.notify_all();
    return;
  }
  while (true) {
    std::string next;
    {
      std::lock_guard lock(m_);
      if (pending_.empty()) return;
      next = *pending_.begin();
      pending_.erase(pending_.begin());
    }
    compile_one(next);
  }
}

void Server::work() {
  std::unique_lock lock(m_);
  while (true) {
    cv_.wait(lock, [&] { return stop_ || !pending_.empty(); });
    if (stop_) return;
    const std::string path = *pending_.begin();
    pending_.erase(pending_.begin());
    busy_ = true;
    compiling_ = path;
    cancel_ = false;
    lock.unlock();
    compile_one(path);
    lock.lock();
    busy_ = false;
    cv_.notify_all();
  }
}

void Server::settle() {
  std::unique_lock lock(m_);
  cv_.wait(lock, [&] { return pending_.empty() && !busy_; });
}

void Server::compile_one(const std::string& path) {
  std::shared_ptr<const Sources::Unsaved> unsaved;
  FileKind kind;
  long version = -1;
  {
    std::lock_guard lock(m_);
    auto it = open_.find(path);
    if (it == open_.end()) return;
    kind = it->second;
    unsaved = unsaved_;
    // What files named inside it may read: its own project root, as `sscs check` of it reads
    // (not the roots of other open files: a verdict must not depend on which tabs are open).
    if (options_.confine) options_.confine({project_root_of(path)});
    version = versions_.count(path) ? versions_[path] : -1;
  }
  std::map<std::string, std::vector<Problem>> found;
  std::shared_ptr<const Analysis> a;
  try {
    a = analyze(path, kind, unsaved, options_.compile, libraries_[path], options_.threaded ? &cancel_ : nullptr);
    found = problems(*a, utf8_);
  } catch (const CheckCancelled&) {
    return;  // an edit came: the file is pending again, its newer text checked next
  } catch (const std::exception& e) {  // a plugin that throws, a bug: said at the file's first line
    found[path].push_back({Range{}, 1, fmt::format("sscs could not check this file: {}", e.what())});
  }
  std::lock_guard lock(m_);
  if (!open_.count(path)) return;
  if (a) analyses_[path] = a;
  if (a && a->wc) good_[path] = a;
  found[path];  // the file itself is published even when clean (its earlier problems go)
  published_version_[path] = version;
  publish(path, std::move(found));
}

void Server::publish(const std::string& root, std::map<std::string, std::vector<Problem>> found) {
  std::map<std::string, std::vector<Problem>>& mine = published_[root];
  std::set<std::string> touched;
  for (const auto& [file, _] : mine) touched.insert(file);
  for (const auto& [file, _] : found) touched.insert(file);
  mine = std::move(found);
  for (const std::string& file : touched) {
    json diagnostics = json::array();
    std::set<std::string> seen;  // a type file's error found by its own check and by a vault's: once
    for (const auto& [_, by_file] : published_)
      if (auto it = by_file.find(file); it != by_file.end())
        for (const Problem& p : it->second) {
          json d = {{"range", range_json(p.range)}, {"severity", p.severity}, {"source", "sscs"}, {"message", p.message}};
          if (seen.insert(d.dump()).second) diagnostics.push_back(std::move(d));
        }
    json params = {{"uri", path_to_uri(file)}, {"diagnostics", diagnostics}};
    // The version of the text they are for, when it is that of the open file's last analysis.
    if (auto v = published_version_.find(file); v != published_version_.end() && v->second >= 0 && published_.count(file))
      params["version"] = v->second;
    send({{"jsonrpc", "2.0"}, {"method", "textDocument/publishDiagnostics"}, {"params", params}});
  }
}

std::shared_ptr<const Analysis> Server::analysis_of(const std::string& path) const {
  std::lock_guard lock(m_);
  auto it = good_.find(path);
  return it == good_.end() ? nullptr : it->second;
}

json Server::hover(const Doc& doc, int line, int character) const {
  const Cursor c = cursor_at(doc.text, line, character, utf8_);
  const auto a = analysis_of(uri_to_path(doc.uri));
  if (c.token.empty() || !a || !a->wc) return nullptr;
  const Workcell& wc = *a->wc;
  std::string_view word = c.token;
  if (!word.empty() && word[0] == '!') word.remove_prefix(1);
  std::string md;
  if (c.key == "name" && c.item >= 0 && (c.section == "constraints" || c.section == "objects")) {  // a name being defined
    const std::string name = item_value(c, c.item, "name").value;
    if (c.section == "constraints") {
      if (const int k = constraint_named(wc, name); k >= 0) md = constraint_markdown(*a, k);
    } else if (const std::vector<int> objects = objects_named(wc, name); !objects.empty()) {
      md = object_markdown(*a, objects);
    }
  } else if (c.is_key && c.section == "objects" && c.item >= 0) {  // an attribute of the object being written
    const int t = wc.find_type(item_value(c, c.item, "type").value);
    const int attribute = t < 0 ? -1 : wc.types[t].find_attribute(word);
    if (attribute >= 0) {
      const AttributeDef& def = wc.types[t].attributes[attribute];
      md = fmt::format("**{}**{}: {}{}{}", md_escape(def.name), def.joint ? " (joint)" : "", attr_type_name(def.type),
                       *file_unit(def.dim) ? fmt::format(" in {}", file_unit(def.dim)) : "",
                       def.default_value.present ? fmt::format(", default `{}`", def.default_value.text) : ", required");
      if (const std::string limits = limits_text(def); !limits.empty()) md += fmt::format(", limits {}", md_escape(limits));
      if (!def.description.empty()) md += "\n\n" + md_escape(def.description);
      const std::vector<int> objects = objects_named(wc, item_value(c, c.item, "name").value);
      for (size_t k = 0; k < objects.size() && k < 12; ++k)
        md += fmt::format("\n- {}: {}", md_escape(wc.objects[objects[k]].name), attribute_value(wc, objects[k], attribute));
    }
  } else if ((c.key == "type" && !c.is_key) || word.rfind("type:", 0) == 0) {
    if (word.rfind("type:", 0) == 0) word.remove_prefix(5);
    word = word.substr(0, word.find('.'));  // `max(type:drum.gross_mass)`: the type
    if (const int t = wc.find_type(word); t >= 0) md = type_markdown(wc, t);
  } else if (const int p = parameter_named(wc, word); p >= 0) {
    const Parameter& param = wc.parameters[p];
    md = fmt::format("**{}**: a parameter, {}", md_escape(param.name),
                     param.type == AttrType::String || param.type == AttrType::Enum
                         ? fmt::format("'{}'", param.slot < wc.texts.size() ? wc.texts[param.slot] : "")
                         : with_unit(wc.values[param.slot], param.dim));
  } else {
    if (word.rfind("at:", 0) == 0) word.remove_prefix(3);
    const size_t dot = word.find('.');
    const std::vector<int> objects = objects_named(wc, word.substr(0, dot));
    const size_t skipped = c.token.size() - word.size();  // `!`, `at:`
    if (!objects.empty() && dot != std::string_view::npos && c.prefix.size() > skipped + dot) {  // on the member or frame
      const std::string frame(word.substr(dot + 1));
      const int o = objects.front();
      std::vector<std::optional<Eigen::Isometry3d>> known(wc.objects.size());
      const Eigen::Isometry3d X_world = wc.pose_in_world(o, known);
      const std::vector<std::string> frames = wc.frame_names(o);
      std::string why;
      const ObjectType& type = wc.types[wc.objects[o].type];
      const int at = type.find_attribute(frame);
      if (std::optional<Operand> member = member_operand(wc, o, frame, /*allow_bbox=*/true, &why)) {  // `Rack_1.height`, `.bbox.max.z`
        const bool text = at >= 0 && (type.attributes[at].type == AttrType::String || type.attributes[at].type == AttrType::Enum);
        md = fmt::format("**{}.{}** = {}", md_escape(wc.objects[o].name), md_escape(frame),
                         text ? attribute_value(wc, o, at) : with_unit(operand_value(*member, wc.values, a->geometry), member->dim));
        if (at >= 0 && !type.attributes[at].description.empty()) md += "\n\n" + md_escape(type.attributes[at].description);
      } else if (std::find(frames.begin(), frames.end(), frame) != frames.end() && !wc.named_frame(o, frame)) {
        md = fmt::format("**{}.{}**: a part of the device `{}` (it moves with the joints: where it is depends on the pose)",
                         md_escape(wc.objects[o].name), md_escape(frame), wc.types[wc.objects[o].type].name);
      } else if (auto X = wc.named_frame(o, frame)) {
        const Eigen::Isometry3d W = X_world * *X;
        md = fmt::format("**{}.{}**: a frame of `{}`\n\n- world position: {} m", md_escape(wc.objects[o].name), md_escape(frame),
                         wc.types[wc.objects[o].type].name, vec_text(W.translation()));
        if (auto rpy = frame_rpy_deg(W)) md += fmt::format(", roll pitch yaw {} deg", vec_text(*rpy));
      } else {
        md = fmt::format("`{}` has no attribute or frame '{}'; its frames: {}", md_escape(wc.objects[o].name), md_escape(frame),
                         md_escape(name_list(frames, 24)));
      }
    } else if (!objects.empty()) {
      md = object_markdown(*a, objects);
    } else if (const int t = wc.find_type(word); t >= 0) {
      md = type_markdown(wc, t);
    } else if (c.section == "constraints" && c.item >= 0) {
      if (const int k = constraint_named(wc, item_value(c, c.item, "name").value); k >= 0) md = constraint_markdown(*a, k);
    }
  }
  if (md.empty()) return nullptr;
  const std::string_view l = c.lines[c.line];
  return {{"contents", {{"kind", "markdown"}, {"value", md}}},
          {"range", range_json({c.line, client_column(l, c.start, utf8_), c.line, client_column(l, c.start + c.token.size(), utf8_)})}};
}

json Server::definition(const Doc& doc, int line, int character) const {
  const Cursor c = cursor_at(doc.text, line, character, utf8_);
  const auto a = analysis_of(uri_to_path(doc.uri));
  if (c.token.empty() || !a || !a->wc) return nullptr;
  const Workcell& wc = *a->wc;
  auto at_mark = [&](SourceMark mark) -> json {
    if (!mark.valid()) return nullptr;
    return {{"uri", path_to_uri(std::filesystem::absolute(a->sources.path(mark.file)).lexically_normal().string())},
            {"range", range_json(token_range(a->sources, mark, utf8_))}};
  };
  auto type_file = [&](int t) -> json {
    if (t < 0 || wc.types[t].path.empty() || wc.types[t].path.front() == '<') return nullptr;
    return {{"uri", path_to_uri(std::filesystem::absolute(wc.types[t].path).lexically_normal().string())}, {"range", range_json({})}};
  };
  std::string_view word = c.token;
  if (!word.empty() && word[0] == '!') word.remove_prefix(1);
  if (c.is_key && c.section == "objects" && c.item >= 0) {
    const int t = wc.find_type(item_value(c, c.item, "type").value);
    const int attribute = t < 0 ? -1 : wc.types[t].find_attribute(word);
    return attribute < 0 ? json(nullptr) : at_mark(wc.types[t].attributes[attribute].mark);
  }
  if ((c.key == "type" && !c.is_key) || word.rfind("type:", 0) == 0) {
    if (word.rfind("type:", 0) == 0) word.remove_prefix(5);
    return type_file(wc.find_type(word.substr(0, word.find('.'))));  // `sum(type:drum.gross_mass)`: the type
  }
  if (word.rfind("at:", 0) == 0) word.remove_prefix(3);
  if (parameter_named(wc, word) >= 0) {  // a parameter: its line under `parameters:` in this file
    bool in_parameters = false;
    for (size_t k = 0; k < c.lines.size(); ++k) {
      const std::string_view l = c.lines[k];
      if (!blank(l) && indent_of(l) == 0) in_parameters = line_key(l) == "parameters";
      else if (in_parameters && line_key(l) == word) {
        const int at = client_column(l, indent_of(l), utf8_);
        return {{"uri", doc.uri}, {"range", range_json({static_cast<int>(k), at, static_cast<int>(k), at + static_cast<int>(word.size())})}};
      }
    }
    return nullptr;
  }
  const size_t skipped = c.token.size() - word.size();
  const size_t dot = word.find('.');
  const std::vector<int> objects = objects_named(wc, word.substr(0, dot));
  if (objects.empty()) return type_file(wc.find_type(word));
  const int o = objects.front();
  if (dot != std::string_view::npos && c.prefix.size() > skipped + dot) {  // on the member or frame: where its type writes it
    const std::string frame(word.substr(dot + 1));
    const ObjectType& type = wc.types[wc.objects[o].type];
    if (const int at = type.find_attribute(frame.substr(0, frame.find('.'))); at >= 0) return at_mark(type.attributes[at].mark);
    for (int t : wc.lineage(wc.objects[o].type))
      for (const FrameTemplate& f : wc.types[t].templates.frames) {
        std::string pattern;
        for (size_t i = 0; i < f.name.size(); ++i) {
          if (f.name[i] == '{' && f.name.find('}', i) != std::string::npos) {
            pattern += '*';
            i = f.name.find('}', i);
          } else {
            pattern += f.name[i];
          }
        }
        if (glob_match(pattern, frame) && f.mark.valid()) return at_mark(f.mark);
      }
    return type_file(wc.objects[o].type);
  }
  return at_mark(wc.objects[o].mark);
}

json Server::completion(const Doc& doc, int line, int character) const {
  const Cursor c = cursor_at(doc.text, line, character, utf8_);
  const auto a = analysis_of(uri_to_path(doc.uri));
  json items = json::array();
  bool incomplete = false;
  if (!a || !a->wc || c.lines.empty()) return {{"isIncomplete", false}, {"items", items}};
  const Workcell& wc = *a->wc;
  const std::string_view l = c.lines[c.line];
  const size_t cursor = c.start + c.prefix.size();
  // Items replace the token's part from `from` to the cursor.
  auto add = [&](const std::string& label, int kind, const std::string& detail, size_t from, std::string_view typed) {
    if (label.compare(0, typed.size(), typed) != 0) return;
    if (items.size() >= kMostItems) {
      incomplete = true;
      return;
    }
    items.push_back({{"label", label}, {"kind", kind}, {"detail", detail},
                     {"textEdit", {{"newText", label}, {"range", range_json({c.line, client_column(l, from, utf8_), c.line, client_column(l, cursor, utf8_)})}}}});
  };
  std::string_view typed = c.prefix;
  size_t from = c.start;
  auto skip = [&](std::string_view p) {
    if (typed.rfind(p, 0) != 0) return false;
    typed.remove_prefix(p.size());
    from += p.size();
    return true;
  };
  skip("!");
  const bool in_list_item = l.substr(0, c.start).find('-') != std::string_view::npos;
  // An expression: a bound's sides, an `expr`, and an object's attribute values.
  const bool expression = holds_expression(c.key) || (c.section == "objects" && !c.key.empty() && !c.is_key && !is_object_key(c.key) &&
                                                      c.key != "count" && c.key != "pitch");
  if (c.is_key && !(in_list_item && names_objects(c.key)) && c.section == "objects" && c.item >= 0) {
    // A key of an object: its type's attributes and the keys every object has, those not written yet.
    const int t = wc.find_type(item_value(c, c.item, "type").value);
    const bool placed = item_value(c, c.item, "at").line >= 0 || item_value(c, c.item, "parent").line >= 0;  // one or the other
    for (const char* key : kObjectKeys)
      if (item_value(c, c.item, key).line < 0 && !(placed && (std::string_view(key) == "at" || std::string_view(key) == "parent")))
        add(key, kItemKeyword, "object key", from, typed);
    if (t >= 0)
      for (const AttributeDef& def : wc.types[t].attributes)
        if (item_value(c, c.item, def.name).line < 0)
          add(def.name, kItemField,
              fmt::format("{}{}{}", attr_type_name(def.type), *file_unit(def.dim) ? fmt::format(" ({})", file_unit(def.dim)) : "",
                          def.default_value.present ? fmt::format(", default {}", def.default_value.text) : ", required"),
              from, typed);
  } else if (c.key == "type" || c.key == "extends" || typed.rfind("type:", 0) == 0) {
    skip("type:");
    for (const ObjectType& t : wc.types) add(t.name, kItemClass, t.description, from, typed);
  } else if (names_objects(c.key) || expression) {
    skip("at:");
    const size_t dot = typed.rfind('.');
    if (dot != std::string_view::npos) {  // after `Rack_1.`: its frames, or in an expression its attributes
      const std::vector<int> objects = objects_named(wc, typed.substr(0, typed.find('.')));
      const size_t after = from + dot + 1;
      const std::string_view rest = typed.substr(dot + 1);
      if (!objects.empty() && expression) {
        const ObjectType& type = wc.types[wc.objects[objects.front()].type];
        for (const AttributeDef& def : type.attributes) add(def.name, kItemField, attr_type_name(def.type), after, rest);
        for (const char* member : kPoseSlotNames) add(member, kItemField, "pose", after, rest);
      } else if (!objects.empty()) {
        for (const std::string& f : wc.frame_names(objects.front())) add(f, kItemReference, "frame", after, rest);
      }
    } else {
      // `device:` takes a device, `container:` a container; the rest any object.
      for (size_t o = 0; o < wc.objects.size(); ++o) {
        const ObjectType& type = wc.types[wc.objects[o].type];
        if ((c.key == "device" && !type.device) || (c.key == "container" && !type.container)) continue;
        add(wc.objects[o].name, kItemVariable, type.name, from, typed);
      }
      const bool one_object = c.key == "at" || c.key == "parent" || c.key == "device" || c.key == "container" || c.key == "carrying";
      if (!expression && !one_object)
        for (const ObjectType& t : wc.types) add("type:" + t.name, kItemClass, "every object of the type", from, typed);
      if (expression)
        for (const Parameter& p : wc.parameters) add(p.name, kItemVariable, "parameter", from, typed);
    }
  }
  return {{"isIncomplete", incomplete}, {"items", items}};
}

json Server::symbols(const Doc& doc) const {
  json out = json::array();
  Cursor c = cursor_at(doc.text, 0, 0, utf8_);
  const int n = static_cast<int>(c.lines.size());
  for (int s = 0; s < n; ++s) {
    if (blank(c.lines[s]) || indent_of(c.lines[s]) != 0) continue;
    const std::string section = line_key(c.lines[s]);
    if (section != "objects" && section != "constraints") continue;
    // Its items: the lines at the first item's indentation that start with `-`.
    int first = s + 1;
    while (first < n && blank(c.lines[first])) ++first;
    if (first >= n || indent_of(c.lines[first]) == 0 || c.lines[first][indent_of(c.lines[first])] != '-') continue;
    c.list_indent = indent_of(c.lines[first]);
    for (int k = first; k < n; ++k) {
      const std::string_view l = c.lines[k];
      if (blank(l)) continue;
      if (indent_of(l) < c.list_indent) break;
      if (indent_of(l) != c.list_indent || l[indent_of(l)] != '-') continue;
      const Found name = item_value(c, k, "name");
      if (name.line < 0 || name.value.empty()) continue;
      const int last = item_end(c, k);
      const std::string_view name_line = c.lines[name.line];
      const Range whole{k, 0, last, client_column(c.lines[last], c.lines[last].size(), utf8_)};
      const Range selection{name.line, client_column(name_line, name.column, utf8_), name.line,
                            client_column(name_line, std::min(name.column + name.value.size(), name_line.size()), utf8_)};
      json symbol = {{"name", name.value}, {"kind", section == "objects" ? kSymbolObject : kSymbolBoolean},
                     {"range", range_json(whole)}, {"selectionRange", range_json(selection)}};
      if (section == "objects") {
        if (const Found type = item_value(c, k, "type"); type.line >= 0) symbol["detail"] = type.value;
      } else {
        for (const char* kind : kConstraintKindNames)
          if (item_value(c, k, kind).line >= 0) symbol["detail"] = kind;
      }
      out.push_back(symbol);
    }
  }
  return out;
}

}  // namespace sscs::lsp
