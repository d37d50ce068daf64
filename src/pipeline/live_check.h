#pragma once
/// One check of a vault as the live design view (`sscs serve`) shows it: the report page, or the
/// input errors as they are printed, and every file the check read (what a save may change).
#include <atomic>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "compile/compile.h"
#include "pipeline/prepare.h"
#include "report/report.h"

namespace sscs {

/// A vault's check as `sscs serve` keeps it: what its page is made of, made when asked (the page
/// in full, or a save's changes alone: the page's data and the objects whose drawing changed).
class LiveVault {
 public:
  LiveVault() = default;
  LiveVault(const LiveVault&) = delete;
  LiveVault& operator=(const LiveVault&) = delete;
  /// The whole page (check_html).
  std::string page() const;
  /// The page's data, as its data element holds it (json_in_script).
  const std::string& data() const { return data_; }
  /// Per object name, what its drawing is made of (object_model_keys).
  using Keys = std::map<std::string, std::string>;
  const std::shared_ptr<const Keys>& keys() const { return keys_; }
  /// A model (binary glTF) of the objects whose key is not the one in `before` (new or changed),
  /// "" when there are none; and the names in `before` gone now.
  std::string changed_model(const Keys& before, std::vector<std::string>& removed) const;

 private:
  friend struct LiveVaultMaker;
  Sources sources_;
  PreparedVault vault_;
  std::vector<VaultReport> reports_;
  std::string data_;
  std::shared_ptr<const Keys> keys_ = std::make_shared<const Keys>();
};

struct LiveCheck {
  bool compiled = false;  ///< no input error: `page` (or `vault`) is the report
  std::string page;       ///< a run's page (a scenario, a campaign), when compiled
  std::shared_ptr<const LiveVault> vault;  ///< a vault's check, when compiled
  std::string errors;     ///< the input errors with file:line:col and the source line, when not
  std::string summary;    ///< "12 passed, 1 failed, 0 warnings", or "3 input errors"
  std::vector<std::string> files;  ///< every file read: the vault, types, URDFs, meshes (absolute)
};

/// Compiles and checks the vault `path` and makes its page (the caller has confined what files
/// named inside it may read). `library` keeps its type library from one check to the next.
/// `cancel`: when it turns true, the check stops (CheckCancelled): a newer save supersedes it.
LiveCheck live_check(const std::string& path, const CompileOptions& options, LibraryCache& library,
                     const std::atomic<bool>* cancel = nullptr);

/// The same for a scenario or a campaign: it is run as `sscs simulate --no-frames` runs it (its
/// own `sim:` mode), into `scratch` (a folder of the caller's, replaced at each run), and the
/// page is the run's report: its vault, its planned motions animated, its events and verdict.
LiveCheck live_run(const std::string& path, const CompileOptions& options, const std::string& scratch);

}  // namespace sscs
