#include "pipeline/prepare.h"

#include <fmt/format.h>

#include "core/files.h"
#include "load/campaign.h"
#include "pipeline/campaign.h"
#include "load/load.h"

#include "geometry/mesh_io.h"

namespace sscs {

PreparedVault prepare_vault(const std::string& path, const CompileOptions& options, Sources& sources, Diagnostics& diag,
                            const GeometryOptions& geometry, MeshCache* meshes) {
  PreparedVault out;
  out.wc = compile_file(path, options, sources, diag);
  if (out.wc) out.geometry = build_geometry(*out.wc, diag, meshes, geometry);
  return out;
}

PreparedVault prepare_vault(const VaultSpec& vault, const CompileOptions& options, Sources& sources, Diagnostics& diag,
                            const GeometryOptions& geometry, MeshCache* meshes) {
  PreparedVault out;
  out.wc = compile_vault(vault, options, sources, diag);
  if (out.wc) out.geometry = build_geometry(*out.wc, diag, meshes, geometry);
  return out;
}

PreparedVault prepare_vault(const std::string& path, const CompileOptions& options, Sources& sources, Diagnostics& diag,
                            const GeometryOptions& geometry, LibraryCache& library) {
  // Which library the vault names, from a first read of its text (a millisecond): the kept one, if
  // it still holds, with its files seeded where its marks point; else the library compiled whole
  // and kept for the next change.
  CompileOptions kept = options;
  {
    Sources probe;
    probe.set_unsaved(sources.unsaved_texts());
    library.seed(probe);
    Diagnostics quiet;
    if (std::optional<VaultSpec> spec = load_vault(path, probe, quiet)) kept.library = library.find(*spec, options, probe);
  }
  if (kept.library) library.seed(sources);
  std::optional<VaultSpec> spec = load_vault(path, sources, diag);
  if (!spec || diag.has_errors()) return {};
  if (!kept.library && LibraryCache::keepable(*spec, options)) {
    // The whole library, kept whatever the vault's own errors (a vault being typed has them most
    // of the time); a library folder that cannot be read keeps nothing (the compile reports it).
    Diagnostics quiet;
    auto types = std::make_shared<const std::vector<ObjectType>>(
        load_library(library_dirs(*spec, options), sources, quiet, options.package_paths));
    if (!quiet.has_errors() && quiet.warnings().empty()) {
      library.keep(*spec, options, types, sources);
      kept.library = std::move(types);
    }
  }
  return prepare_vault(*spec, kept, sources, diag, geometry);
}

bool PreparedScenario::prepare(const std::string& path, const CompileOptions& base, const std::string& camera_file) {
  auto file = load_run_file(path, sources, diag);
  if (!file || diag.has_errors()) return false;
  if (auto* c = std::get_if<CampaignSpec>(&*file)) {
    campaign = std::move(*c);
    spec.emplace();
    static_cast<RunFileSpec&>(*spec) = *campaign;  // its name, vault, settings and cameras: a run's
  } else {
    spec = std::move(std::get<ScenarioSpec>(*file));
  }
  // The vault it names, said at its `vault:` (it read "sscs: error: cannot read ...", no place).
  if (std::string why = not_a_file(spec->vault_path); !why.empty()) {
    diag.error(spec->vault.mark, fmt::format("cannot read the vault '{}': it {}", spec->vault.text, why));
    return false;
  }
  CompileOptions options = base;
  for (const auto& [name, value] : spec->set) overrides.emplace_back(name, value.text);
  overrides.insert(overrides.end(), base.overrides.begin(), base.overrides.end());
  options.overrides = overrides;
  PreparedVault vault;
  if (campaign) {  // its arriving loads are objects of the vault, kept away until they arrive
    std::optional<VaultSpec> v = load_vault(spec->vault_path, sources, diag);
    if (!v || diag.has_errors()) return false;
    add_arriving_loads(*campaign, *v, diag);
    if (diag.has_errors()) return false;
    vault = prepare_vault(*v, options, sources, diag, {.visuals = true, .contacts = nullptr});
  } else {
    vault = prepare_vault(spec->vault_path, options, sources, diag, {.visuals = true, .contacts = nullptr});  // frames draw what devices look like
  }
  wc = std::move(vault.wc);
  geometry = std::move(vault.geometry);
  if (wc && !diag.has_errors() && campaign) {
    if (auto commands = compile_campaign(*campaign, *wc, geometry, diag)) plan = plan_campaign(*commands, *wc, geometry, diag);
  } else if (wc && !diag.has_errors()) {
    plan = plan_scenario(*spec, *wc, geometry, diag);
  }
  std::vector<CameraKeySpec> keys = spec->cameras;
  if (!camera_file.empty())
    if (auto file = load_cameras(camera_file, sources, diag)) keys = *file;
  if (plan && !diag.has_errors()) cameras = CameraPath(compile_camera_keys(keys, *wc, diag));
  return plan && !diag.has_errors();
}

}  // namespace sscs
