#pragma once
/// What the HTML reports and `sscs export RUN` gather: a run folder (or bundle) read back with its
/// vault compiled again, its motion as an animated glTF; a check's reports with each vault's
/// model; a sweep's results with links to its variants. The page itself is report/html.h.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "compile/compile.h"
#include "core/expected.h"
#include "core/files.h"
#include "geometry/geometry.h"
#include "report/html.h"
#include "report/report.h"

namespace sscs {

/// A run folder, or a bundle unpacked into a temporary folder (removed when this goes).
class OpenedRun {
 public:
  /// `path`: a run folder or a bundle (.zip); why not when it is neither (a folder without
  /// resolved/scenario.yaml, an unreadable zip).
  static Expected<std::shared_ptr<OpenedRun>> open(const std::string& path);
  const std::string& dir() const { return dir_; }
  const std::string& given() const { return given_; }

 private:
  std::string given_, dir_;
  std::optional<StagedDir> unpacked_;
};

/// The run's vault with its motion as the glTF animation "run", its camera and the vault's
/// (render/gltf.h). Why not (the vault's input errors formatted, a log that does not match).
/// `warnings`: where the vault's warnings go, formatted (may be null).
Expected<std::string> run_gltf(const OpenedRun& run, const CompileOptions& options, bool binary, std::string* warnings = nullptr);

/// The HTML page of a check: each vault's JSON report (its baseline diff in it) and its model.
std::string check_html(const std::vector<VaultReport>& reports, const Sources& sources,
                       const std::vector<const GeometryModel*>& geometry);
/// What that page holds: its data and (with `models`) each vault's model; without them, the
/// data names the models as the page with them does (`sscs serve` sends a save's changes alone).
HtmlReport check_report(const std::vector<VaultReport>& reports, const Sources& sources,
                        const std::vector<const GeometryModel*>& geometry, bool models = true);

/// The HTML page of a run: its summary, events, trajectories and animated model.
Expected<std::string> run_html(const OpenedRun& run, const CompileOptions& options, std::string* warnings = nullptr);

/// The HTML page of a sweep folder (its results.json), each variant linked relative to the
/// folder the page is written to (`html_path`'s).
Expected<std::string> sweep_html(const std::string& sweep_dir, const std::string& html_path);

/// The HTML page of a check's JSON report (`sscs check --format json`): each vault it names is
/// compiled again, with the values the report says it was checked with ("set"), for its
/// model; a vault not found, not compiling or lacking an object the report names gets none, and
/// the page (and `warnings`) says why. `confine(file)` is called before each vault is read.
Expected<std::string> report_json_html(const std::string& json_path, const CompileOptions& options,
                                       const std::function<void(const std::string&)>& confine, std::string* warnings = nullptr);

}  // namespace sscs
