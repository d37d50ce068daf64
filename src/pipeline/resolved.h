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
#include "simulate/run_inputs.h"

namespace sscs {

/// `overrides`: the parameter overrides in force, in order (the scenario's `set:`, then --set);
/// a later one wins. Files named but unreadable now are an error (they were read moments ago).
/// `files`: the files of `sources` this run read, when the registry holds others too (a sweep's
/// other scenarios and vaults, the sweep file); null: all of them. `kind`: the run file's
/// (scenario or campaign: resolved/scenario.yaml names its schema).
RunInputs collect_run_inputs(const ScenarioSpec& scenario, const std::vector<std::pair<std::string, std::string>>& overrides,
                             const Workcell& wc, const GeometryModel& geometry, const Sources& sources,
                             const std::vector<uint32_t>* files = nullptr, const char* kind = "scenario");

}  // namespace sscs
