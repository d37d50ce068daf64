#pragma once
/// Campaign files (campaign-format.md) as written: the run settings a scenario has, the loads
/// that arrive, the jobs generated from templates, and what a failure does. Values stay text
/// with marks; the campaign is resolved against the compiled vault later.
#include <optional>
#include <variant>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/source.h"
#include "load/scenario.h"

namespace sscs {

/// `arrive:` of a load stream: exactly one of every (with first), times, or random (its mean).
struct ArrivalSpec {
  enum class Kind { Every, Times, Random };
  Kind kind = Kind::Every;
  SourceMark mark;
  Scalar every, first;            ///< Every: the gap, and the first arrival (default 0 s)
  std::vector<Scalar> times;      ///< Times: each arrival
  Scalar mean;                    ///< Random: the mean of the exponential gaps
};

/// One entry of `loads:`: `count` objects of `type` named from `name` ({n} counts from 1),
/// each appearing at the frame `at` when it arrives.
struct LoadStreamSpec {
  SourceMark mark;
  Scalar name;                    ///< a name pattern: `In_{n}`
  Scalar type, count, at;
  std::vector<std::pair<std::string, Scalar>> attributes;
  std::vector<SourceMark> attribute_marks;
  ArrivalSpec arrive;
};

/// `slot:` of a job: a free frame among those `from` matches, chosen by `choose`.
struct SlotSpec {
  SourceMark mark;
  Scalar from;                    ///< a frame selector: `Row_*.top_*`
  Scalar choose;                  ///< nearest (default) | first | lowest | random
};

/// One entry of `jobs:`: a job per object `each` selects, done by one of `devices`.
struct JobSpec {
  SourceMark mark;
  std::string name;
  Scalar each;                    ///< an object selector
  Scalar after;                   ///< when an object of the vault is ready (default 0 s)
  std::vector<Scalar> devices;
  std::optional<SlotSpec> slot;
  Scalar to;                      ///< a fixed destination frame, instead of a slot
  std::vector<Scalar> claims;     ///< zones (objects) held exclusively while the job runs
  std::vector<StepSpec> steps;    ///< templates: {load}, {slot}, {to}, {device} expand
};

struct CampaignSpec : RunFileSpec {
  std::vector<LoadStreamSpec> loads;
  std::vector<JobSpec> jobs;
  Scalar on_failure;              ///< continue (default) | stop
};

/// The placeholders a job's steps may use: {load} (the job's object), {slot}, {to}, {device}.
inline constexpr const char* kJobPlaceholders[] = {"load", "slot", "to", "device"};

/// Loads a campaign file strictly (unknown and duplicate keys, wrong kinds, names, placeholders
/// that are not defined for their job). Returns nullopt when the file could not be parsed at
/// all; otherwise the spec, every problem reported.
std::optional<CampaignSpec> load_campaign(const std::string& path, Sources& sources, Diagnostics& diag);
/// Loads a campaign already registered in `sources` (tests).
std::optional<CampaignSpec> load_campaign(uint32_t file, Sources& sources, Diagnostics& diag);
/// Loads a file `sscs simulate` runs: a scenario, or a campaign (its top key says which).
std::optional<std::variant<ScenarioSpec, CampaignSpec>> load_run_file(const std::string& path, Sources& sources, Diagnostics& diag);

}  // namespace sscs
