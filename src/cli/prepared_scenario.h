#pragma once
/// A scenario made ready to run or replay: `sscs simulate`, `sscs replay` and the benchmarks.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "compile/compile.h"
#include "geometry/geometry.h"
#include "load/scenario.h"
#include "render/camera_path.h"
#include "simulate/plan.h"

namespace sscs {

/// A scenario loaded, its vault compiled with the overrides (the scenario's `set:`, then
/// --set), planned, and its cameras (or a camera file's) compiled. Input errors are in `diag`.
struct PreparedScenario {
  Sources sources;
  Diagnostics diag;
  std::optional<ScenarioSpec> spec;
  std::optional<Workcell> wc;
  GeometryModel geometry;
  std::optional<Plan> plan;
  CameraPath cameras;
  std::vector<std::pair<std::string, std::string>> overrides;  ///< in force, in order

  bool prepare(const std::string& path, const CompileOptions& base, const std::string& camera_file = "") {
    spec = load_scenario(path, sources, diag);
    if (!spec || diag.has_errors()) return false;
    CompileOptions options = base;
    for (const auto& [name, value] : spec->set) overrides.emplace_back(name, value.text);
    overrides.insert(overrides.end(), base.overrides.begin(), base.overrides.end());
    options.overrides = overrides;
    wc = compile_file(spec->vault_path, options, sources, diag);
    if (wc) geometry = build_geometry(*wc, diag, nullptr, {.visuals = true});  // frames draw what devices look like
    if (wc && !diag.has_errors()) plan = plan_scenario(*spec, *wc, geometry, diag);
    std::vector<CameraKeySpec> keys = spec->cameras;
    if (!camera_file.empty())
      if (auto file = load_cameras(camera_file, sources, diag)) keys = *file;
    if (plan && !diag.has_errors()) cameras = compile_cameras(keys, *wc, diag);
    return plan && !diag.has_errors();
  }
};

}  // namespace sscs
