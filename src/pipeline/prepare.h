#pragma once
/// The pipeline's front half, written once for every command, the sweep and the benchmarks:
/// a vault compiled and its geometry built (prepare_vault), a scenario loaded, its vault compiled
/// with the overrides, planned, and its cameras compiled (PreparedScenario).
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "pipeline/compile_vault.h"
#include "geometry/geometry.h"
#include "load/campaign.h"
#include "load/scenario.h"
#include "render/camera_path.h"
#include "pipeline/scenario.h"
#include "simulate/plan.h"

namespace sscs {

/// A vault compiled with `options` and its geometry built. `wc` is empty when it did not
/// compile; every input error and warning is in the Diagnostics given.
struct PreparedVault {
  std::optional<Workcell> wc;
  GeometryModel geometry;
};

/// Compiles the vault file `path` and builds its geometry (with what devices look like when
/// `geometry.visuals`: render, frames, export). `meshes` keeps the meshes read for later builds.
PreparedVault prepare_vault(const std::string& path, const CompileOptions& options, Sources& sources, Diagnostics& diag,
                            const GeometryOptions& geometry = {}, MeshCache* meshes = nullptr);
/// The same for a vault already loaded (a sweep compiles one vault again per variant).
PreparedVault prepare_vault(const VaultSpec& vault, const CompileOptions& options, Sources& sources, Diagnostics& diag,
                            const GeometryOptions& geometry = {}, MeshCache* meshes = nullptr);

/// The same for a vault compiled again and again (sscs lsp, sscs serve): its library is taken
/// from `library` while it holds (LibraryCache::find), else compiled whole and kept there. `sources`
/// starts empty (with the editor's unsaved texts set, if any).
PreparedVault prepare_vault(const std::string& path, const CompileOptions& options, Sources& sources, Diagnostics& diag,
                            const GeometryOptions& geometry, LibraryCache& library);

/// A scenario loaded, its vault compiled with the overrides (the scenario's `set:`, then
/// --set), planned, and its cameras (or a camera file's) compiled. Input errors are in `diag`.
struct PreparedScenario {
  Sources sources;
  Diagnostics diag;
  std::optional<ScenarioSpec> spec;  ///< a campaign's: its run settings, no steps
  std::optional<CampaignSpec> campaign;  ///< when the file is a campaign (it is planned by the dispatcher)
  std::optional<Workcell> wc;
  GeometryModel geometry;
  std::optional<Plan> plan;
  CameraPath cameras;
  std::vector<std::pair<std::string, std::string>> overrides;  ///< in force, in order

  /// False when an input error stopped it (in `diag`).
  bool prepare(const std::string& path, const CompileOptions& base, const std::string& camera_file = "");
};

}  // namespace sscs
