#include "pipeline/compile_vault.h"

#include "core/timer.h"
#include "load/load.h"

namespace sscs {

std::optional<Workcell> compile_vault(const VaultSpec& spec, const CompileOptions& options, Sources& sources, Diagnostics& diag) {
  std::optional<VaultInputs> inputs = gather_vault(spec, options, sources, diag);
  if (!inputs) return std::nullopt;
  return compile(spec, *inputs, options, sources, diag);
}

std::optional<Workcell> compile_file(const std::string& path, const CompileOptions& options, Sources& sources, Diagnostics& diag) {
  StageTimer timer;
  auto spec = load_vault(path, sources, diag);
  timer.lap("load");
  if (!spec || diag.has_errors()) return std::nullopt;
  auto wc = compile_vault(*spec, options, sources, diag);
  timer.lap("compile");
  return wc;
}

std::vector<ObjectType> load_library(const std::vector<std::pair<std::string, SourceMark>>& dirs, Sources& sources,
                                     Diagnostics& diag, const std::vector<std::string>& package_paths,
                                     const std::vector<PluginType>& plugin_types, const std::set<std::string>* wanted) {
  return build_library(gather_library(dirs, sources, diag, package_paths, plugin_types), sources, diag, wanted);
}

}  // namespace sscs
