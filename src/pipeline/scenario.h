#pragma once
/// A scenario file compiled against its vault for planning: device, joint, object and frame
/// names resolved to indices, values read in SI, settings checked. Every mistake is an input
/// error at its line; the steps it leaves unresolved are skipped by the planner.
#include <optional>

#include "compile/workcell.h"
#include "core/diagnostics.h"
#include "geometry/geometry.h"
#include "load/scenario.h"
#include "simulate/plan.h"

namespace sscs {

/// One step compiled against the vault (a campaign job's, its placeholders expanded).
StepCommand compile_step(const StepSpec& step, size_t index, const Workcell& wc, const GeometryModel& geometry, Diagnostics& diag);
/// The `sim:` and `record:` settings of a scenario or campaign file.
SimSettings compile_settings(const RunFileSpec& spec, const Workcell& wc, const GeometryModel& geometry, Diagnostics& diag);

ScenarioCommands compile_scenario(const ScenarioSpec& spec, const Workcell& wc, const GeometryModel& geometry, Diagnostics& diag);

/// Compiles and plans a scenario. Returns nullopt when an input error was reported.
std::optional<Plan> plan_scenario(const ScenarioSpec& spec, const Workcell& wc, const GeometryModel& geometry, Diagnostics& diag);

}  // namespace sscs
