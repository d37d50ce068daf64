#include "lsp/analysis.h"

#include <filesystem>
#include <regex>

#include <fmt/format.h>

#include "core/yaml_tree.h"
#include "load/load.h"
#include "pipeline/prepare.h"
#include "report/report.h"

namespace sscs::lsp {

FileKind file_kind(std::string_view text) {
  // The first top-level key that says what the file is (a line scan: a 50 MB buffer takes no regex).
  for (size_t pos = 0; pos < text.size();) {
    const std::string_view line = text.substr(pos, text.find('\n', pos) - pos);
    for (const auto& [key, kind] : {std::pair{"vault", FileKind::Vault}, std::pair{"scenario", FileKind::Scenario},
                                    std::pair{"campaign", FileKind::Scenario}, std::pair{"type", FileKind::Type}}) {
      const std::string_view k = key;
      if (line.substr(0, k.size()) != k) continue;
      const size_t colon = line.find_first_not_of(" \t", k.size());
      if (colon != std::string_view::npos && line[colon] == ':') return kind;
    }
    const size_t next = text.find('\n', pos);
    if (next == std::string_view::npos) break;
    pos = next + 1;
  }
  // A document written as one flow mapping (`{sscs: 1, vault: V, objects: [...]}`): its keys, in its start.
  const size_t first = text.find_first_not_of(" \t\r\n");
  if (first != std::string_view::npos && text[first] == '{') {
    static const std::regex key(R"([{,]\s*(vault|scenario|campaign|type)\s*:)");
    const std::string_view head = text.substr(first, 65536);
    std::match_results<std::string_view::const_iterator> m;
    if (std::regex_search(head.begin(), head.end(), m, key))
      return m[1] == "vault" ? FileKind::Vault : m[1] == "type" ? FileKind::Type : FileKind::Scenario;
  }
  return FileKind::Other;
}

std::shared_ptr<const Analysis> analyze(const std::string& path, FileKind kind, std::shared_ptr<const Sources::Unsaved> unsaved,
                                        const CompileOptions& options, LibraryCache& library, const std::atomic<bool>* cancel) {
  auto a = std::make_shared<Analysis>();
  a->path = path;
  a->kind = kind;
  a->sources.set_unsaved(unsaved);
  switch (kind) {
    case FileKind::Vault: {
      PreparedVault vault = prepare_vault(path, options, a->sources, a->diag, {.visuals = false, .contacts = nullptr}, library);
      if (vault.wc && !a->diag.has_errors()) {
        CheckOptions check_options;
        check_options.describe_passes = true;  // hover shows a constraint's last result, passing too
        check_options.cancel = cancel;
        a->report = check(*vault.wc, vault.geometry, check_options);
      }
      a->wc = std::move(vault.wc);
      a->geometry = std::move(vault.geometry);
      break;
    }
    case FileKind::Scenario: {
      PreparedScenario s;
      s.sources.set_unsaved(unsaved);
      s.prepare(path, options);
      a->sources = std::move(s.sources);
      a->diag = std::move(s.diag);
      a->wc = std::move(s.wc);
      a->geometry = std::move(s.geometry);
      break;
    }
    case FileKind::Type:
      load_type(path, a->sources, a->diag);
      break;
    case FileKind::Other:
      break;
  }
  a->file = a->sources.find(path);
  return a;
}

int client_column(std::string_view line, size_t byte, bool utf8) {
  byte = std::min(byte, line.size());
  if (utf8) return static_cast<int>(byte);
  int units = 0;
  for (size_t i = 0; i < byte; ++i) {
    const auto c = static_cast<unsigned char>(line[i]);
    if ((c & 0xC0) == 0x80) continue;  // a continuation byte
    units += c >= 0xF0 ? 2 : 1;        // a code point beyond the BMP takes a surrogate pair
  }
  return units;
}

size_t byte_column(std::string_view line, int column, bool utf8) {
  if (column <= 0) return 0;
  if (utf8) return std::min(static_cast<size_t>(column), line.size());
  int units = 0;
  size_t i = 0;
  while (i < line.size() && units < column) {
    const auto c = static_cast<unsigned char>(line[i]);
    units += c >= 0xF0 ? 2 : 1;
    ++i;
    while (i < line.size() && (static_cast<unsigned char>(line[i]) & 0xC0) == 0x80) ++i;
  }
  return i;
}

Range token_range(const Sources& sources, SourceMark mark, bool utf8) {
  Range r;
  if (mark.line == 0) return r;
  r.line = r.end_line = static_cast<int>(mark.line) - 1;
  const std::string_view line = sources.line(mark);
  if (mark.column == 0) {
    r.end_character = client_column(line, line.size(), utf8);
    return r;
  }
  const size_t start = std::min<size_t>(mark.column - 1, line.size());
  size_t end = start;
  if (end < line.size() && (line[end] == '"' || line[end] == '\'')) {
    const size_t close = line.find(line[end], end + 1);
    end = close == std::string_view::npos ? line.size() : close + 1;
  } else {
    while (end < line.size() && line[end] != ' ' && line[end] != ',' && line[end] != ']' && line[end] != '}' && line[end] != '[' &&
           line[end] != '{' && line[end] != '"' && line[end] != '\'' && !(line[end] == ':' && (end + 1 == line.size() || line[end + 1] == ' ')))
      ++end;
  }
  if (end == start && end < line.size() && (line[end] == '{' || line[end] == '[')) {
    // A flow collection (a constraint of a vault written in flow style): to its closing bracket,
    // not over what follows it on the line.
    int depth = 0;
    char quote = 0;
    for (size_t k = start; k < line.size(); ++k) {
      const char c = line[k];
      if (quote) {
        if (c == quote) quote = 0;
        else if (c == '\\' && quote == '"') ++k;
      } else if (c == '"' || c == '\'') {
        quote = c;
      } else if (c == '{' || c == '[') {
        ++depth;
      } else if ((c == '}' || c == ']') && --depth == 0) {
        end = k + 1;
        break;
      }
    }
  }
  if (end == start) end = line.size();  // a mark on a space, or a collection not closed on its line: the rest of the line
  r.character = client_column(line, start, utf8);
  r.end_character = client_column(line, end, utf8);
  return r;
}

std::map<std::string, std::vector<Problem>> problems(const Analysis& a, bool utf8) {
  std::map<std::string, std::vector<Problem>> out;
  auto place = [&](SourceMark mark, int severity, std::string message) {
    if (!mark.valid() && a.file) mark = {a.file, 1, 0};  // no place: the file's first line
    if (!mark.valid()) {
      out[a.path].push_back({Range{}, severity, std::move(message)});
      return;
    }
    mark = yaml::exact_mark(a.sources, mark);  // inside a scalar written over several lines
    out[a.sources.path(mark.file)].push_back({token_range(a.sources, mark, utf8), severity, std::move(message)});
  };
  for (const Diagnostic& d : a.diag.warnings()) place(d.mark, 2, d.message);
  for (const Diagnostic& d : a.diag.errors()) place(d.mark, 1, d.message);
  if (a.diag.count() > a.diag.errors().size())
    place({}, 1, fmt::format("{} more errors not shown", a.diag.count() - a.diag.errors().size()));
  if (!a.wc || !a.report) return out;
  const Workcell& wc = *a.wc;
  for (const CheckResult& r : a.report->results) {
    if (r.status == Status::Pass) continue;
    const Constraint& c = wc.constraints[r.constraint];
    const bool warning = c.severity == Severity::Warning && r.status != Status::Error;
    const std::string margin = margin_text(r);  // as `sscs check` prints it
    const std::string subjects = subject_names(wc, r);
    const std::string message = fmt::format("{} {} [{}]{}{}: {}{}", r.status == Status::Error ? "cannot evaluate" : warning ? "warning" : "failed",
                                            c.name, c.kind, subjects.empty() ? "" : " ", subjects, r.message, margin);
    place(c.mark, warning ? 2 : 1, message);
    // A type file's constraint: also at the object it failed for, where the user edits it.
    if (c.mark.file != a.file)
      for (int s : r.subjects)
        if (wc.objects[s].mark.file == a.file && wc.objects[s].mark.valid()) {
          place(wc.objects[s].mark, warning ? 2 : 1, message);
          break;
        }
  }
  return out;
}

}  // namespace sscs::lsp
