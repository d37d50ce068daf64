#pragma once
/// A campaign file resolved against its compiled vault for the dispatcher: devices, selectors,
/// slot frames, destinations and claims named in the vault, its job templates checked for every
/// object they go over. Every mistake is an input error at its line; a template that does not
/// compile for one of its objects names that object.
#include <optional>

#include "compile/workcell.h"
#include "core/diagnostics.h"
#include "geometry/geometry.h"
#include "load/campaign.h"
#include "load/spec.h"
#include "simulate/dispatch.h"

namespace sscs {

/// `spec` must outlive the result (its job steps are expanded when a job starts).
std::optional<CampaignCommands> compile_campaign(const CampaignSpec& spec, const Workcell& wc, const GeometryModel& geometry,
                                                 Diagnostics& diag);

/// The loads a campaign's `loads:` bring, added to its vault as objects standing at their spot
/// (`at:`); the run keeps each away until it arrives. `{n}` of a name counts from 1.
void add_arriving_loads(const CampaignSpec& spec, VaultSpec& vault, Diagnostics& diag);

/// A step of a job template with its placeholders ({load}, {device}, {slot}, {to}) replaced, and
/// the job's device where the step names none.
StepSpec expand_step(const StepSpec& step, const std::string& load, const std::string& device, const std::string& place);

}  // namespace sscs
