#include <sstream>

#include <nlohmann/json.hpp>

#include "report/json_writer.h"
#include "core/units.h"
#include "report/report.h"

namespace sscs {

namespace {

void number_or_null(JsonWriter& w, const std::optional<double>& v) {
  if (!v || !std::isfinite(*v)) w.null();
  else w.stable_number(*v);
}

void point(JsonWriter& w, const Eigen::Vector3d& p) {
  w.begin_array();
  for (int k = 0; k < 3; ++k) w.stable_number(p[k]);
  w.end_array();
}

/// A failed reach target's closest pose: joints in file units (deg, m), the tool's and the
/// target's world points, and each part's pose in the device's frame as [x, y, z, qw, qx, qy, qz].
void write_closest(JsonWriter& w, const ClosestPose& c) {
  w.key("closest");
  w.begin_object();
  w.key("joints");
  w.begin_array();
  for (const ClosestPose::Joint& j : c.joints) {
    const Dim dim = j.revolute ? Dim::Angle : Dim::Length;
    w.begin_object();
    w.field("name", j.name);
    w.key("value");
    w.stable_number(si_to_file(j.value, dim));
    w.field("unit", file_unit(dim));
    w.end_object();
  }
  w.end_array();
  w.key("tool");
  point(w, c.tool);
  w.key("target");
  point(w, c.target);
  w.key("parts");
  w.begin_object();
  for (const ClosestPose::Part& p : c.parts) {
    const Eigen::Quaterniond q(p.X_object_part.linear());
    w.key(p.name);
    w.begin_array();
    for (double v : {p.X_object_part.translation().x(), p.X_object_part.translation().y(), p.X_object_part.translation().z(), q.w(), q.x(),
                     q.y(), q.z()})
      w.stable_number(v);
    w.end_array();
  }
  w.end_object();
  w.end_object();
}

/// The baseline section: small, so built as a tree.
nlohmann::ordered_json baseline_json(const BaselineDiff& d) {
  nlohmann::ordered_json b;
  b["file"] = d.file;
  b["vault_in_baseline"] = d.vault_in_baseline;
  b["new"] = d.new_failures;
  b["fixed"] = d.fixed.size();
  b["still_failing"] = d.still_failing;
  b["unchanged"] = d.unchanged;
  auto fixed = nlohmann::ordered_json::array();
  for (const BaselineDiff::Gone& g : d.fixed)
    fixed.push_back({{"constraint", g.constraint}, {"subject", g.subject}, {"why", g.why}, {"message", g.message}});
  b["fixed_results"] = std::move(fixed);
  auto renamed = nlohmann::ordered_json::array();
  for (const auto& [from, to] : d.renamed) renamed.push_back({{"from", from}, {"to", to}});
  b["renamed"] = std::move(renamed);
  auto removed = nlohmann::ordered_json::array();
  for (const BaselineDiff::Removed& r : d.removed)
    removed.push_back({{"constraint", r.constraint}, {"was", r.was_failing ? "failing" : "passing"}});
  b["removed"] = std::move(removed);
  return b;
}

/// One vault's report, written result by result as it goes.
void write_vault(JsonWriter& w, const VaultReport& vr, const Sources& sources) {
  const Workcell& wc = *vr.workcell;
  w.begin_object();
  w.field("sscs", 1);
  w.field("vault", wc.name);
  w.field("file", vr.file);
  if (!vr.overrides.empty()) {
    nlohmann::ordered_json set = nlohmann::ordered_json::object();
    for (const auto& [name, value] : vr.overrides) set[name] = value;  // the last of a name is the one in force
    w.field("set", set);
  }
  w.field("passed", vr.report.passed);
  w.field("failed", vr.report.failed);
  w.field("warnings", vr.report.warnings);
  if (!vr.input_warnings.empty()) {
    w.key("input_warnings");
    w.begin_array();
    for (const Diagnostic& d : vr.input_warnings)
      w.json(nlohmann::ordered_json{{"file", d.mark.valid() ? sources.path(d.mark.file) : ""}, {"line", d.mark.line},
                                    {"column", sources.character_column(d.mark)}, {"message", d.message}});
    w.end_array();
  }
  if (vr.baseline) w.field("baseline", baseline_json(*vr.baseline));
  w.key("results");
  w.begin_array();
  // Every result repeats its file's path: escaped once per file.
  std::vector<std::string> paths;
  auto path = [&](uint32_t file) -> const std::string& {
    if (file >= paths.size()) paths.resize(file + 1);
    if (paths[file].empty()) append_json_string(paths[file], sources.path(file));
    return paths[file];
  };
  for (size_t i = 0; i < vr.report.results.size(); ++i) {
    const CheckResult& r = vr.report.results[i];
    const Constraint& c = wc.constraints[r.constraint];
    w.begin_object();
    w.field("constraint", c.name);
    w.field("kind", c.kind);
    w.field("severity", c.severity == Severity::Warning ? "warning" : "error");
    w.field("status", status_name(r.status));
    w.key("subject");
    w.begin_array();
    for (int s : r.subjects) w.string(wc.objects[s].name);
    w.end_array();
    w.key("lhs");
    number_or_null(w, r.lhs);
    w.key("rhs");
    number_or_null(w, r.rhs);
    w.key("margin");
    number_or_null(w, r.margin);
    w.field("unit", r.margin_unit());
    w.field("message", r.message);
    if (r.closest) write_closest(w, *r.closest);
    w.key("location");
    w.begin_object();
    w.key("file");
    w.literal(path(c.mark.file));
    w.field("line", c.mark.line);
    w.field("column", sources.character_column(c.mark));
    w.end_object();
    if (vr.baseline) w.field("baseline", change_name(vr.baseline->changes[i]));
    w.end_object();
  }
  w.end_array();
  w.end_object();
}

}  // namespace

void write_json(std::ostream& out, const std::vector<VaultReport>& reports, const Sources& sources) {
  JsonWriter w(out);
  if (reports.size() == 1) {
    write_vault(w, reports[0], sources);
    return;
  }
  w.begin_object();
  w.field("sscs", 1);
  w.key("reports");
  w.begin_array();
  for (const VaultReport& vr : reports) write_vault(w, vr, sources);
  w.end_array();
  w.end_object();
}

std::string format_json(const std::vector<VaultReport>& reports, const Sources& sources) {
  std::ostringstream out;
  write_json(out, reports, sources);
  return out.str();
}

}  // namespace sscs
