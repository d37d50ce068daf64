#pragma once
/// One check of a vault as the live design view (`sscs serve`) shows it: the report page, or the
/// input errors as they are printed, and every file the check read (what a save may change).
#include <string>
#include <vector>

#include "compile/compile.h"

namespace sscs {

struct LiveCheck {
  bool compiled = false;  ///< no input error: `page` is the report
  std::string page;       ///< the check's HTML page (check_html), when compiled
  std::string errors;     ///< the input errors with file:line:col and the source line, when not
  std::string summary;    ///< "12 passed, 1 failed, 0 warnings", or "3 input errors"
  std::vector<std::string> files;  ///< every file read: the vault, types, URDFs, meshes (absolute)
};

/// Compiles and checks the vault `path` and makes its page (the caller has confined what files
/// named inside it may read). `library` keeps its type library from one check to the next.
LiveCheck live_check(const std::string& path, const CompileOptions& options, LibraryCache& library);

/// The same for a scenario or a campaign: it is run as `sscs simulate --no-frames` runs it (its
/// own `sim:` mode), into `scratch` (a folder of the caller's, replaced at each run), and the
/// page is the run's report: its vault, its planned motions animated, its events and verdict.
LiveCheck live_run(const std::string& path, const CompileOptions& options, const std::string& scratch);

}  // namespace sscs
