#include <nlohmann/json.hpp>

#include "report/report.h"

namespace sscs {

namespace {

nlohmann::ordered_json number_or_null(const std::optional<double>& v) {
  if (!v || !std::isfinite(*v)) return nullptr;
  return stable(*v);
}

nlohmann::ordered_json vault_json(const VaultReport& vr, const Sources& sources) {
  const Workcell& wc = *vr.workcell;
  nlohmann::ordered_json j;
  j["sscs"] = 1;
  j["vault"] = wc.name;
  j["file"] = vr.file;
  j["passed"] = vr.report.passed;
  j["failed"] = vr.report.failed;
  j["warnings"] = vr.report.warnings;
  if (vr.baseline) {
    const BaselineDiff& d = *vr.baseline;
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
    j["baseline"] = std::move(b);
  }
  auto results = nlohmann::ordered_json::array();
  for (size_t i = 0; i < vr.report.results.size(); ++i) {
    const CheckResult& r = vr.report.results[i];
    const Constraint& c = wc.constraints[r.constraint];
    nlohmann::ordered_json e;
    e["constraint"] = c.name;
    e["kind"] = c.kind;
    e["severity"] = c.severity == Severity::Warning ? "warning" : "error";
    e["status"] = status_name(r.status);
    auto subjects = nlohmann::ordered_json::array();
    for (int s : r.subjects) subjects.push_back(wc.objects[s].name);
    e["subject"] = std::move(subjects);
    e["lhs"] = number_or_null(r.lhs);
    e["rhs"] = number_or_null(r.rhs);
    e["margin"] = number_or_null(r.margin);
    e["unit"] = r.margin_unit();
    e["message"] = r.message;
    e["location"] = {{"file", sources.path(c.mark.file)}, {"line", c.mark.line}, {"column", c.mark.column}};
    if (vr.baseline) e["baseline"] = change_name(vr.baseline->changes[i]);
    results.push_back(std::move(e));
  }
  j["results"] = std::move(results);
  return j;
}

}  // namespace

std::string format_json(const std::vector<VaultReport>& reports, const Sources& sources) {
  if (reports.size() == 1) return vault_json(reports[0], sources).dump(2) + "\n";
  nlohmann::ordered_json j;
  j["sscs"] = 1;
  auto all = nlohmann::ordered_json::array();
  for (const VaultReport& vr : reports) all.push_back(vault_json(vr, sources));
  j["reports"] = std::move(all);
  return j.dump(2) + "\n";
}

}  // namespace sscs
