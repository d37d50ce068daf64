// SARIF 2.1.0 for code-scanning tools: a failing check becomes an annotation on the constraint's
// line in the vault file of a pull request.
#include <filesystem>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/digest.h"
#include "report/json_writer.h"
#include "report/report.h"

namespace sscs {

namespace {

struct Rule {
  const char* kind;
  const char* name;
  const char* text;
};

// One rule per constraint kind, always in this order (stable rule indices).
constexpr Rule kRules[] = {
    {"bound", "BoundConstraint", "A bound constraint (lhs OP rhs with tolerances) is violated."},
    {"expr", "ExpressionConstraint", "A functional constraint written as an expression is violated."},
    {"plugin", "PluginConstraint", "A functional constraint implemented by a plugin is violated."},
    {"clearance", "Clearance", "Two geometries are closer than the minimum clearance."},
    {"no_overlap", "NoOverlap", "Two geometries interpenetrate."},
    {"inside", "Inside", "An object is not within its container."},
    {"reach", "Reach", "A device cannot place its tool at a target within its joint limits and without collision."},
};

static_assert(std::size(kRules) == kConstraintKindNames.size(), "a rule per constraint kind");

int rule_index(const std::string& kind) {
  for (int i = 0; i < static_cast<int>(std::size(kRules)); ++i)
    if (kind == kRules[i].kind) return i;
  return -1;
}

/// RFC 3986 percent-encoding of a path's characters that may not stand in a URI as they are.
std::string uri_path(const std::string& path) {
  std::string out;
  for (unsigned char c : path) {
    if (std::isalnum(c) || std::string_view("-._~/").find(static_cast<char>(c)) != std::string_view::npos) out += static_cast<char>(c);
    else out += fmt::format("%{:02X}", c);
  }
  return out;
}

/// The artifact location of a file: relative to base_dir (uriBaseId SRCROOT) when inside it,
/// else an absolute file: URI.
nlohmann::ordered_json artifact(const std::string& file, const std::string& base_dir) {
  namespace fs = std::filesystem;
  fs::path abs = fs::absolute(file).lexically_normal();
  fs::path rel = abs.lexically_relative(fs::absolute(base_dir).lexically_normal());
  if (!rel.empty() && *rel.begin() != "..") return {{"uri", uri_path(rel.generic_string())}, {"uriBaseId", "SRCROOT"}};
  return {{"uri", "file://" + uri_path(abs.generic_string())}};
}

nlohmann::ordered_json location(SourceMark mark, const Sources& sources, const std::string& base_dir) {
  return {{"physicalLocation",
           {{"artifactLocation", artifact(sources.path(mark.file), base_dir)},
            {"region", {{"startLine", mark.line}, {"startColumn", sources.character_column(mark)}}}}}};
}

/// A fingerprint that follows a result across edits that move lines: vault, constraint, subjects.
std::string fingerprint(const std::string& vault, const std::string& constraint, const std::vector<std::string>& subject) {
  return sha256_hex(fmt::format("{}\n{}\n{}", vault, constraint, fmt::join(subject, "\n"))).substr(0, 32);
}

}  // namespace

void write_sarif(std::ostream& out, const std::vector<VaultReport>& reports, const Sources& sources, bool strict,
                 const std::string& base_dir) {
  nlohmann::ordered_json rules = nlohmann::ordered_json::array();
  for (const Rule& r : kRules)
    rules.push_back({{"id", fmt::format("sscs/{}", r.kind)},
                     {"name", r.name},
                     {"shortDescription", {{"text", r.text}}},
                     {"fullDescription", {{"text", fmt::format("{} (sscs constraint kind `{}`)", r.text, r.kind)}}},
                     {"defaultConfiguration", {{"level", "error"}}},
                     {"properties", {{"tags", {"design-rule", r.kind}}}}});
  // After the constraint kinds (their indices stay): warnings of the inputs.
  const int input_warning_rule = static_cast<int>(rules.size());
  rules.push_back({{"id", "sscs/input-warning"},
                   {"name", "InputWarning"},
                   {"shortDescription", {{"text", "An input file has something sscs skipped or worked around."}}},
                   {"fullDescription", {{"text", "An input file has something sscs skipped or worked around (a degenerate URDF "
                                                 "shape, an inertia simulated as a box, a texture not read); it fails no check."}}},
                   {"defaultConfiguration", {{"level", "warning"}}},
                   {"properties", {{"tags", {"input"}}}}});
  // The document up to "results", then each result as it is made: no tree of them all.
  JsonWriter w(out);
  w.begin_object();
  w.field("$schema", "https://json.schemastore.org/sarif-2.1.0.json");
  w.field("version", "2.1.0");
  w.key("runs");
  w.begin_array();
  w.begin_object();
  w.field("tool", nlohmann::ordered_json{{"driver", {{"name", "sscs"}, {"semanticVersion", SSCS_VERSION}, {"rules", std::move(rules)}}}});
  w.field("columnKind", "unicodeCodePoints");  // Sources::character_column (SARIF's default counts UTF-16 units)
  w.key("results");
  w.begin_array();
  for (const VaultReport& vr : reports) {
    const Workcell& wc = *vr.workcell;
    for (size_t i = 0; i < vr.report.results.size(); ++i) {
      const CheckResult& r = vr.report.results[i];
      if (r.status == Status::Pass) continue;
      const Constraint& c = wc.constraints[r.constraint];
      std::vector<std::string> subject;
      for (int s : r.subjects) subject.push_back(wc.objects[s].name);
      const bool warning = c.severity == Severity::Warning && r.status != Status::Error;
      const std::string margin = margin_text(r);
      nlohmann::ordered_json res;
      res["ruleId"] = fmt::format("sscs/{}", c.kind);
      res["ruleIndex"] = rule_index(c.kind);
      res["kind"] = "fail";
      res["level"] = warning && !strict ? "warning" : "error";
      // Checks of plugin classes share the rule sscs/plugin: the message names the class.
      const auto* plugin = std::get_if<PluginCheck>(&c.body);
      std::string cls = plugin && !plugin->class_name.empty() ? fmt::format(" (plugin class {})", plugin->class_name) : "";
      res["message"] = {{"text", fmt::format("{}{}{}{}{}: {}{}{}", c.name, cls, subject.empty() ? "" : " [", fmt::join(subject, ", "),
                                             subject.empty() ? "" : "]", r.status == Status::Error ? "could not be evaluated: " : "",
                                             r.message, margin)}};
      res["locations"] = nlohmann::ordered_json::array({location(c.mark, sources, base_dir)});
      res["partialFingerprints"] = {{"sscsResult/v1", fingerprint(wc.name, c.name, subject)}};
      if (vr.baseline) res["baselineState"] = vr.baseline->changes[i] == Change::New ? "new" : "unchanged";
      res["properties"] = {{"vault", wc.name},      {"constraint", c.name},       {"status", status_name(r.status)},
                           {"subject", subject},     {"lhs", number_or_null(r.lhs)}, {"rhs", number_or_null(r.rhs)},
                           {"margin", number_or_null(r.margin)}, {"unit", r.margin_unit()}};
      w.json(res);
    }
    // Warnings of the inputs (a URDF shape skipped): annotations too, under a rule of their own.
    for (const Diagnostic& d : vr.input_warnings) {
      nlohmann::ordered_json res;
      res["ruleId"] = "sscs/input-warning";
      res["ruleIndex"] = input_warning_rule;
      res["kind"] = "fail";  // SARIF 2.1.0 3.27.9: a level other than none goes with kind fail
      res["level"] = "warning";
      res["message"] = {{"text", d.message}};
      if (d.mark.valid()) res["locations"] = nlohmann::ordered_json::array({location(d.mark, sources, base_dir)});
      res["properties"] = {{"vault", wc.name}};
      w.json(res);
    }
    if (!vr.baseline) continue;
    // Baseline failures that are gone: `absent` results (kind pass, level none), at the
    // constraint when it still exists.
    for (const BaselineDiff::Gone& g : vr.baseline->fixed) {
      const Constraint* c = nullptr;
      for (const Constraint& k : wc.constraints)
        if (k.name == g.constraint) c = &k;
      nlohmann::ordered_json res;
      res["ruleId"] = c ? fmt::format("sscs/{}", c->kind) : "sscs/fixed";
      if (c) res["ruleIndex"] = rule_index(c->kind);
      res["kind"] = "pass";
      res["level"] = "none";
      res["message"] = {{"text", describe_fixed(g)}};
      if (c) res["locations"] = nlohmann::ordered_json::array({location(c->mark, sources, base_dir)});
      res["partialFingerprints"] = {{"sscsResult/v1", fingerprint(wc.name, g.constraint, g.subject)}};
      res["baselineState"] = "absent";
      res["properties"] = {{"vault", wc.name}, {"constraint", g.constraint}, {"subject", g.subject}};
      w.json(res);
    }
  }
  w.end_array();
  w.end_object();
  w.end_array();
  w.end_object();
}

std::string format_sarif(const std::vector<VaultReport>& reports, const Sources& sources, bool strict,
                         const std::string& base_dir) {
  std::ostringstream out;
  write_sarif(out, reports, sources, strict, base_dir);
  return out.str();
}

}  // namespace sscs
