#include <fmt/format.h>

#include "report/report.h"

namespace sscs {

namespace {

std::string xml_escape(std::string_view s) {
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

}  // namespace

std::string format_junit(const std::vector<VaultReport>& reports, const Sources& sources, bool strict) {
  std::string suites;
  size_t total = 0, total_failures = 0, total_errors = 0;
  for (const VaultReport& vr : reports) {
    const Workcell& wc = *vr.workcell;
    std::string cases;
    size_t failures = 0, errors = 0;
    for (size_t i = 0; i < vr.report.results.size(); ++i) {
      const CheckResult& r = vr.report.results[i];
      const Constraint& c = wc.constraints[r.constraint];
      // With a baseline, say what the change did to this check.
      std::string change;
      if (vr.baseline && r.status != Status::Pass)
        change = vr.baseline->changes[i] == Change::New ? " [new failure]" : " [still failing]";
      std::string subjects = subject_names(wc, r, " ");
      std::string name = subjects.empty() || r.subjects.size() == c.subjects.size() ? c.name
                                                                                      : fmt::format("{} [{}]", c.name, subjects);
      std::string margin = (r.margin ? fmt::format(" (margin {:g}{}{})", stable(*r.margin), *r.margin_unit() ? " " : "",
                                                   r.margin_unit())
                                     : "") +
                           change;
      std::string where = fmt::format("{}:{}:{}", sources.path(c.mark.file), c.mark.line, c.mark.column);
      cases += fmt::format("    <testcase name=\"{}\" classname=\"{}.{}\" file=\"{}\" line=\"{}\"", xml_escape(name),
                           xml_escape(wc.name), c.kind, xml_escape(sources.path(c.mark.file)), c.mark.line);
      bool warning = c.severity == Severity::Warning;
      if (r.status == Status::Pass && vr.baseline && vr.baseline->changes[i] == Change::Fixed) {
        cases += ">\n      <system-out>fixed since the baseline</system-out>\n    </testcase>\n";
      } else if (r.status == Status::Pass) {
        cases += "/>\n";
      } else if (r.status == Status::Error && (!warning || strict)) {
        ++errors;
        cases += fmt::format(">\n      <error message=\"{}{}\" type=\"{}\">{}: {}{}</error>\n    </testcase>\n",
                             xml_escape(r.message), xml_escape(change), c.kind, xml_escape(where), xml_escape(r.message),
                             xml_escape(change));
      } else if (!warning || strict) {
        ++failures;
        cases += fmt::format(">\n      <failure message=\"{}{}\" type=\"{}\">{}: {}{}</failure>\n    </testcase>\n",
                             xml_escape(r.message), xml_escape(margin), c.kind, xml_escape(where), xml_escape(r.message),
                             xml_escape(margin));
      } else {
        // A warning passes the gate unless --strict; it is shown, not counted as a failure.
        cases += fmt::format(">\n      <system-out>warning: {}: {}{}</system-out>\n    </testcase>\n", xml_escape(where),
                             xml_escape(r.message), xml_escape(margin));
      }
    }
    std::string suite_out;
    if (vr.baseline) {
      const BaselineDiff& d = *vr.baseline;
      suite_out = fmt::format("baseline {}: {}\n", d.file, baseline_summary(d));
      suite_out += baseline_lines(d);
      cases += fmt::format("    <system-out>{}</system-out>\n", xml_escape(suite_out));
    }
    total += vr.report.results.size();
    total_failures += failures;
    total_errors += errors;
    suites += fmt::format("  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"{}\" skipped=\"0\" file=\"{}\">\n{}"
                          "  </testsuite>\n",
                          xml_escape(wc.name), vr.report.results.size(), failures, errors, xml_escape(vr.file), cases);
  }
  return fmt::format("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"sscs check\" tests=\"{}\" "
                     "failures=\"{}\" errors=\"{}\">\n{}</testsuites>\n",
                     total, total_failures, total_errors, suites);
}

}  // namespace sscs
