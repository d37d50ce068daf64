#pragma once
/// What scenario and campaign files share, read alike (scenario_loader.cpp): the run settings
/// and the steps. A campaign's job steps are templates: `device:` may be left to the job.
#include "core/diagnostics.h"
#include "core/yaml_tree.h"
#include "load/reader.h"
#include "load/scenario.h"

namespace sscs::load {

/// description, vault (resolved against out.path, which must be set), set, sim, record and
/// cameras of a scenario or (`campaign`: sim.seed too) a campaign file.
void read_run_file(MapReader& root, RunFileSpec& out, Diagnostics& diag, bool campaign);
/// One step; `templated`: a campaign job's, whose `device:` the job supplies when absent.
StepSpec read_step(yaml::Node node, Diagnostics& diag, bool templated);
/// `steps:`: a non-empty sequence of read_step()s (an absent node gives none; the caller
/// requires it).
std::vector<StepSpec> read_steps(yaml::Node steps, Diagnostics& diag, bool templated);

}  // namespace sscs::load
