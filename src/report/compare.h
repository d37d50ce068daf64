#pragma once
/// `sscs compare RUN...`: the summaries of simulation runs side by side (cycle time, joint travel,
/// tool path length, collisions and other event counts), as text, JSON or CSV.
#include <string>
#include <vector>

#include "core/expected.h"


#include "simulate/summary_file.h"

namespace sscs {

struct RunRecord {
  std::string path;              ///< the run folder as given
  RunSummaryFile summary;
};

/// Reads each run's summary.json. On a problem returns false with `error` saying which and why.
Expected<std::vector<RunRecord>> read_runs(const std::vector<std::string>& paths);

std::string compare_text(const std::vector<RunRecord>& runs);
std::string compare_json(const std::vector<RunRecord>& runs);
std::string compare_csv(const std::vector<RunRecord>& runs);

}  // namespace sscs
