#pragma once
/// The report stage: check results -> text, JSON, JUnit, SARIF; the comparison with a baseline
/// report. Formatting only; no checking here.
#include <map>
#include <ostream>
#include <optional>
#include <string>
#include <vector>

#include "check/check.h"
#include "compile/workcell.h"
#include "core/expected.h"
#include "core/files.h"
#include "core/source.h"
#include "core/units.h"

namespace sscs {

/// How a result compares with the baseline report (`--baseline OLD.json`).
enum class Change : uint8_t {
  New,           ///< failing now, not in the baseline (or passing there): fails the gate
  StillFailing,  ///< failing now and in the baseline
  Fixed,         ///< passing now, failing in the baseline
  Unchanged,     ///< passing now and there (or new and passing)
};
const char* change_name(Change c);

/// Text as XML (or HTML) character data or an attribute value: control characters (which XML
/// 1.0 cannot carry even as references) and bytes that are not UTF-8 become '?', markup is escaped.
std::string xml_escape(std::string_view text);  ///< "new", "still_failing", "fixed", "unchanged"

/// One vault against its part of the baseline report.
struct BaselineDiff {
  std::string file;                ///< the baseline report's path
  bool vault_in_baseline = false;  ///< false: the baseline has no report of this vault
  std::vector<Change> changes;     ///< parallel to CheckReport::results
  /// A baseline failure with no failing counterpart now: fixed. `why`: "passes now" or
  /// "no longer checked" (its subject is gone).
  struct Gone {
    std::string constraint;
    std::vector<std::string> subject;
    std::string message, why;
  };
  std::vector<Gone> fixed;
  std::vector<std::pair<std::string, std::string>> renamed;  ///< (baseline name, name now)
  struct Removed {
    std::string constraint;
    bool was_failing = false;
  };
  std::vector<Removed> removed;  ///< in the baseline, not in the vault, not renamed
  size_t new_failures = 0, still_failing = 0, unchanged = 0;
  /// New failures that fail the gate: error severity, or warnings too when strict.
  size_t gating_new = 0, gating_new_strict = 0;
};

/// One vault's results with what is needed to print them.
struct VaultReport {
  const Workcell* workcell = nullptr;
  std::string file;  ///< the vault path as given
  CheckReport report;
  std::optional<BaselineDiff> baseline;
  /// Warnings of its inputs (a URDF shape skipped, a texture not read): on stderr as the vault
  /// loads, and in the report so CI annotates them.
  std::vector<Diagnostic> input_warnings;
  /// The parameter values set on the vault (`--set`, a sweep's variant), in order: the report
  /// says them ("set"), so that what it was made from can be compiled again (`sscs report`).
  std::vector<std::pair<std::string, std::string>> overrides = {};
  /// The gate: with a baseline, only new failures; else every failure.
  bool violated(bool strict) const {
    if (!baseline) return report.violated(strict);
    return (strict ? baseline->gating_new_strict : baseline->gating_new) > 0;
  }
};

/// A baseline report read from JSON (`sscs check --format json`): per vault name, its results.
struct BaselineResult {
  std::string constraint, kind, status, message;
  std::vector<std::string> subject;
};
struct Baseline {
  std::string file;
  std::map<std::string, std::vector<BaselineResult>> vaults;
};

/// Reads a baseline report. On failure returns nullopt with `error` set ("FILE:LINE:COL: ...").
Expected<Baseline> read_baseline(const std::string& path);

/// Compares one vault's results with the baseline's results for the vault of the same name.
BaselineDiff compare_with_baseline(const Workcell& wc, const CheckReport& report, const Baseline& baseline);

/// "1 new failure, 1 fixed, 2 still failing, 14 unchanged" (plus renamed/removed counts).
std::string baseline_summary(const BaselineDiff& d);

/// The lines after a vault's results: "fixed: NAME [subjects] (why; was: message)", "renamed:
/// 'a' is now 'b'", "removed: 'c' (it failed in the baseline)".
std::string baseline_lines(const BaselineDiff& d);

/// "fixed: NAME [subjects] (why; was: message)".
std::string describe_fixed(const BaselineDiff::Gone& g);

struct TextOptions {
  bool color = false;
  bool quiet = false;   ///< only the summary line(s)
  bool strict = false;  ///< warnings count as failures
};

std::string format_text(const std::vector<VaultReport>& reports, const Sources& sources, const TextOptions& options);
/// One vault: the report object of cli.md. Several: {"sscs": 1, "reports": [...]}. Written as it
/// goes (no tree of the whole report); format_json returns the same text.
void write_json(std::ostream& out, const std::vector<VaultReport>& reports, const Sources& sources);
std::string format_json(const std::vector<VaultReport>& reports, const Sources& sources);
/// One <testsuite> per vault, one <testcase> per check; streamed like write_json.
void write_junit(std::ostream& out, const std::vector<VaultReport>& reports, const Sources& sources, bool strict);
std::string format_junit(const std::vector<VaultReport>& reports, const Sources& sources, bool strict);
/// SARIF 2.1.0: one run, one result per failing check located at its constraint; rules per
/// constraint kind; `baselineState` with a baseline (fixed ones as `absent`). File URIs are
/// relative to `base_dir` (the working directory) with uriBaseId SRCROOT when inside it.
void write_sarif(std::ostream& out, const std::vector<VaultReport>& reports, const Sources& sources, bool strict,
                 const std::string& base_dir);
std::string format_sarif(const std::vector<VaultReport>& reports, const Sources& sources, bool strict,
                         const std::string& base_dir);

/// "Rack_1 Rack_2": the subject names of a result.
std::string subject_names(const Workcell& wc, const CheckResult& r, const char* separator = ", ");

/// " (margin -0.05 m)": a result's margin as every report and the editor print it, "" without one.
std::string margin_text(const CheckResult& r);


}  // namespace sscs
