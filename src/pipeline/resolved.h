#pragma once
/// What a run read and how to run it again: the sha256 of every input file, and the resolved/
/// tree — the vault, the types it uses (with their URDF and mesh files) and the scenario, with
/// the vault path, the library and the parameter overrides pinned, so that
/// `sscs simulate RUN/resolved/scenario.yaml` reruns exactly the same operation later.
#include <string>
#include <utility>
#include <vector>

#include "compile/workcell.h"
#include "core/source.h"
#include "geometry/geometry.h"
#include "load/scenario.h"

namespace sscs {

struct InputFile {
  std::string path;  ///< as it was read
  std::string sha256;
};

struct RunInputs {
  std::vector<InputFile> files;
  /// Files of resolved/: a path relative to the run folder ("resolved/vault.yaml") and its bytes.
  std::vector<std::pair<std::string, std::string>> resolved;
  /// Inputs resolved/ could not hold (an absolute path, or one outside its library folder):
  /// a rerun reads them from where they are.
  std::vector<std::string> not_copied;
};

/// `overrides`: the parameter overrides in force, in order (the scenario's `set:`, then --set);
/// a later one wins. Files named but unreadable now are an error (they were read moments ago).
RunInputs collect_run_inputs(const ScenarioSpec& scenario, const std::vector<std::pair<std::string, std::string>>& overrides,
                             const Workcell& wc, const GeometryModel& geometry, const Sources& sources);

}  // namespace sscs
