#pragma once
/// The report stage: check results -> text, JSON, JUnit. Formatting only; no checking here.
#include <string>
#include <vector>

#include "check/check.h"
#include "compile/workcell.h"
#include "core/files.h"
#include "core/source.h"
#include "core/units.h"

namespace sscs {

/// One vault's results with what is needed to print them.
struct VaultReport {
  const Workcell* workcell = nullptr;
  std::string file;  ///< the vault path as given
  CheckReport report;
};

struct TextOptions {
  bool color = false;
  bool quiet = false;   ///< only the summary line(s)
  bool strict = false;  ///< warnings count as failures
};

std::string format_text(const std::vector<VaultReport>& reports, const Sources& sources, const TextOptions& options);
/// One vault: the report object of cli.md. Several: {"sscs": 1, "reports": [...]}.
std::string format_json(const std::vector<VaultReport>& reports, const Sources& sources);
/// One <testsuite> per vault, one <testcase> per check.
std::string format_junit(const std::vector<VaultReport>& reports, const Sources& sources, bool strict);

/// "Rack_1 Rack_2": the subject names of a result.
std::string subject_names(const Workcell& wc, const CheckResult& r, const char* separator = ", ");



}  // namespace sscs
