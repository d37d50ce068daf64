#include <sstream>

#include <fmt/format.h>

#include "core/diagnostics.h"
#include "report/report.h"

namespace sscs {

std::string xml_escape(std::string_view text) {
  const std::string s = printable(text, true);
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

namespace {

/// A check's place in the suite: a passing case, an <error> or a <failure> (counted), or a
/// warning shown in <system-out> (passes the gate unless strict). A check that could not be
/// evaluated is an <error> whatever its severity: nothing is known to hold.
enum class Outcome { Pass, Error, Failure, Warning };
Outcome outcome(const Constraint& c, const CheckResult& r, bool strict) {
  bool warning = c.severity == Severity::Warning;
  if (r.status == Status::Pass) return Outcome::Pass;
  if (r.status == Status::Error) return Outcome::Error;
  if (!warning || strict) return Outcome::Failure;
  return Outcome::Warning;
}

/// Failures and errors of one vault, for the suite's attributes (written before its cases).
std::pair<size_t, size_t> tally(const VaultReport& vr, bool strict) {
  size_t failures = 0, errors = 0;
  for (const CheckResult& r : vr.report.results) {
    Outcome o = outcome(vr.workcell->constraints[r.constraint], r, strict);
    failures += o == Outcome::Failure;
    errors += o == Outcome::Error;
  }
  return {failures, errors};
}

void write_case(std::ostream& out, const VaultReport& vr, size_t i, const Sources& sources, bool strict) {
  const Workcell& wc = *vr.workcell;
  const CheckResult& r = vr.report.results[i];
  const Constraint& c = wc.constraints[r.constraint];
  // With a baseline, say what the change did to this check.
  std::string change;
  if (vr.baseline && r.status != Status::Pass)
    change = vr.baseline->changes[i] == Change::New ? " [new failure]" : " [still failing]";
  std::string subjects = subject_names(wc, r, " ");
  std::string name = subjects.empty() || r.subjects.size() == c.subjects.size() ? c.name : fmt::format("{} [{}]", c.name, subjects);
  out << fmt::format("    <testcase name=\"{}\" classname=\"{}.{}\" file=\"{}\" line=\"{}\"", xml_escape(name), xml_escape(wc.name),
                     c.kind, xml_escape(sources.path(c.mark.file)), c.mark.line);
  Outcome o = outcome(c, r, strict);
  if (o == Outcome::Pass) {
    if (vr.baseline && vr.baseline->changes[i] == Change::Fixed)
      out << ">\n      <system-out>fixed since the baseline</system-out>\n    </testcase>\n";
    else
      out << "/>\n";
    return;
  }
  const std::string margin = margin_text(r) + change;
  std::string where = fmt::format("{}:{}:{}", sources.path(c.mark.file), c.mark.line, sources.character_column(c.mark));
  if (o == Outcome::Error)
    out << fmt::format(">\n      <error message=\"{}{}\" type=\"{}\">{}: {}{}</error>\n    </testcase>\n", xml_escape(r.message),
                       xml_escape(change), c.kind, xml_escape(where), xml_escape(r.message), xml_escape(change));
  else if (o == Outcome::Failure)
    out << fmt::format(">\n      <failure message=\"{}{}\" type=\"{}\">{}: {}{}</failure>\n    </testcase>\n", xml_escape(r.message),
                       xml_escape(margin), c.kind, xml_escape(where), xml_escape(r.message), xml_escape(margin));
  else
    out << fmt::format(">\n      <system-out>warning: {}: {}{}</system-out>\n    </testcase>\n", xml_escape(where),
                       xml_escape(r.message), xml_escape(margin));
}

}  // namespace

void write_junit(std::ostream& out, const std::vector<VaultReport>& reports, const Sources& sources, bool strict) {
  size_t total = 0, total_failures = 0, total_errors = 0;
  for (const VaultReport& vr : reports) {
    auto [failures, errors] = tally(vr, strict);
    total += vr.report.results.size();
    total_failures += failures;
    total_errors += errors;
  }
  out << fmt::format("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"sscs check\" tests=\"{}\" "
                     "failures=\"{}\" errors=\"{}\">\n", total, total_failures, total_errors);
  for (const VaultReport& vr : reports) {
    auto [failures, errors] = tally(vr, strict);
    out << fmt::format("  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"{}\" skipped=\"0\" file=\"{}\">\n",
                       xml_escape(vr.workcell->name), vr.report.results.size(), failures, errors, xml_escape(vr.file));
    for (size_t i = 0; i < vr.report.results.size(); ++i) write_case(out, vr, i, sources, strict);
    if (vr.baseline) {
      const BaselineDiff& d = *vr.baseline;
      std::string suite_out = fmt::format("baseline {}: {}\n", d.file, baseline_summary(d)) + baseline_lines(d);
      out << fmt::format("    <system-out>{}</system-out>\n", xml_escape(suite_out));
    }
    out << "  </testsuite>\n";
  }
  out << "</testsuites>\n";
}

std::string format_junit(const std::vector<VaultReport>& reports, const Sources& sources, bool strict) {
  std::ostringstream out;
  write_junit(out, reports, sources, strict);
  return out.str();
}

}  // namespace sscs
