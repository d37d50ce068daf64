#include <fmt/format.h>

#include "core/diagnostics.h"
#include "report/report.h"

namespace sscs {

std::string format_text(const std::vector<VaultReport>& reports, const Sources& sources, const TextOptions& options) {
  const char* red = options.color ? "\033[1;31m" : "";
  const char* yellow = options.color ? "\033[1;33m" : "";
  const char* bold = options.color ? "\033[1m" : "";
  const char* reset = options.color ? "\033[0m" : "";
  std::string out;
  size_t passed = 0, failed = 0, unevaluated = 0, warnings = 0, input_warnings = 0;
  // "N failed (K could not be evaluated)": those K count as failures whatever their severity.
  auto failed_text = [](size_t n, size_t k) { return k ? fmt::format("{} failed ({} could not be evaluated)", n, k) : fmt::format("{} failed", n); };
  for (const VaultReport& vr : reports) {
    const Workcell& wc = *vr.workcell;
    for (size_t i = 0; i < vr.report.results.size(); ++i) {
      const CheckResult& r = vr.report.results[i];
      if (r.status == Status::Pass || options.quiet) continue;
      const Constraint& c = wc.constraints[r.constraint];
      bool warning = c.severity == Severity::Warning;
      const char* word = r.status == Status::Error ? "error" : warning ? "warning" : "fail";
      const std::string margin = margin_text(r);
      std::string subjects = subject_names(wc, r);
      std::string change;
      if (vr.baseline) change = vr.baseline->changes[i] == Change::New ? " [new failure]" : " [still failing]";
      // Names and messages come from input: no escape sequence of theirs reaches a terminal or a CI log.
      out += fmt::format("{}{}:{}:{}:{} {}{}:{} {} [{}{}{}]: {}{}{}\n", bold, printable(sources.path(c.mark.file)), c.mark.line,
                         sources.character_column(c.mark), reset, warning && r.status != Status::Error ? yellow : red, word, reset, printable(c.name),
                         c.kind, subjects.empty() ? "" : " ", printable(subjects), printable(within_window(r.message)), margin, change);
    }
    if (vr.baseline && !options.quiet) out += baseline_lines(*vr.baseline);
    if (vr.baseline) out += fmt::format("{}baseline {}: {}\n", reports.size() > 1 ? printable(wc.name) + ": " : "", printable(vr.baseline->file),
                                        baseline_summary(*vr.baseline));
    passed += vr.report.passed;
    failed += vr.report.failed;
    unevaluated += vr.report.unevaluated;
    warnings += vr.report.warnings;
    input_warnings += vr.input_warnings.size();
    if (reports.size() > 1)
      out += fmt::format("{}: {} passed, {}, {} warnings\n", printable(wc.name), vr.report.passed,
                         failed_text(vr.report.failed, vr.report.unevaluated), vr.report.warnings);
  }
  // Warnings of the inputs (printed on stderr as they loaded) are counted apart: they fail nothing.
  out += fmt::format("{} passed, {}, {} warnings{}{}\n", passed, failed_text(failed, unevaluated), warnings,
                     input_warnings ? fmt::format("; {} input warning{}", input_warnings, input_warnings == 1 ? "" : "s") : "",
                     options.strict && warnings > 0 ? " (warnings fail with --strict)" : "");
  return out;
}

}  // namespace sscs
