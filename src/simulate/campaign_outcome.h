#pragma once
/// What a campaign's run did with its jobs (campaign-format.md, "What a campaign run writes"):
/// each job done, failed or not started, with its times, and the campaign's figures: makespan,
/// throughput, each device's utilization, waits, the longest queue, the slots.
#include <map>
#include <optional>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "compile/workcell.h"
#include "simulate/plan.h"
#include "simulate/summary_file.h"

namespace sscs {

struct CampaignOutcome {
  RunSummaryFile::Campaign figures;
  std::string jobs_csv;
};

/// How the run went, as the campaign's outcome needs it.
struct RunReach {
  std::vector<char> ended;  ///< per plan step: the run ended it
  double stopped_at = std::numeric_limits<double>::infinity();  ///< when the run stopped early, else infinity
  std::string stop_message;
  double ended_at = std::numeric_limits<double>::infinity();  ///< when the run ended (a job ready later never was)
  /// Jobs the run itself failed (a grasp missed) while the campaign went on (on_failure:
  /// continue), and from when their devices were out.
  struct JobFailure {
    int job = -1;
    double t = 0;
    std::string message;
  };
  std::vector<JobFailure> job_failures;
  std::map<int, double> out_at;
  /// Per object, where its origin is at the end: the solids a slot can hold (none for devices,
  /// containers and what has no solid).
  std::vector<std::optional<Eigen::Vector3d>> positions;
};

CampaignOutcome campaign_outcome(const Workcell& wc, const Plan& plan, const RunReach& reach);

}  // namespace sscs
