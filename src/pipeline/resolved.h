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
#include "simulate/simulate.h"

namespace sscs {

/// `overrides`: the parameter overrides in force, in order (the scenario's `set:`, then --set);
/// a later one wins. Files named but unreadable now are an error (they were read moments ago).
/// `files`: the files of `sources` this run read, when the registry holds others too (a sweep's
/// other scenarios and vaults, the sweep file); null: all of them. `kind`: the run file's
/// (scenario or campaign: resolved/scenario.yaml names its schema).
RunInputs collect_run_inputs(const ScenarioSpec& scenario, const std::vector<std::pair<std::string, std::string>>& overrides,
                             const Workcell& wc, const GeometryModel& geometry, const Sources& sources,
                             const std::vector<uint32_t>* files = nullptr, const char* kind = "scenario");

/// A campaign run's final.yaml (campaign-format.md): the vault as the run leaves it, a vault file
/// that checks and starts the next campaign. The vault's own text with its objects listed one by
/// one (arrays expanded, expressions evaluated to numbers in the file's units), each where it
/// stands at the end (`at:` kept for what did not move; what moved in the frame of the room it
/// stands in), the loads that
/// arrived added and those that never did left out, devices at their last joint values; its
/// parameters pinned to the values the run used; constraints, cameras and the rest as written.
/// `beside_resolved`: the run folder holds resolved/ (its library and meshes are named there);
/// else the vault's library and mesh files are named by absolute path. `title`: the run's name.
std::string final_vault_text(const Workcell& wc, const Sources& sources, const FinalState& end, const std::string& title,
                             bool beside_resolved);

}  // namespace sscs
