#include "simulate/campaign_outcome.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>

#include "core/csv.h"
#include "simulate/dispatch.h"
#include "simulate/events.h"

namespace sscs {

namespace {

enum class JobStatus : uint8_t { NotStarted, Done, Failed };
const char* status_name(JobStatus s) { return s == JobStatus::Done ? "done" : s == JobStatus::Failed ? "failed" : "not_started"; }

struct JobRow {
  JobStatus status = JobStatus::NotStarted;
  double start = NAN, end = NAN;
  std::string message;
};

std::string number(double x) { return std::isfinite(x) ? fmt::format("{}", r9(x)) : ""; }

}  // namespace

CampaignOutcome campaign_outcome(const Workcell& wc, const Plan& plan, const RunReach& reach) {
  const double stop = std::min(reach.stopped_at, reach.ended_at) + 1e-9;
  // A job ready only after the run ended (its `after` past the end of a campaign whose devices
  // were out) was never ready: no ready time, no place in the queue.
  auto ready = [&](size_t i) { return plan.jobs[i].ready <= stop ? plan.jobs[i].ready : INFINITY; };
  std::vector<JobRow> rows(plan.jobs.size());
  std::vector<char> all_ended(plan.jobs.size(), 1);
  for (size_t k = 0; k < plan.steps.size(); ++k)
    if (plan.steps[k].job >= 0 && (k >= reach.ended.size() || !reach.ended[k])) all_ended[plan.steps[k].job] = 0;
  for (const PlannedStep& ps : plan.not_begun)
    if (ps.job >= 0) all_ended[ps.job] = 0;
  for (size_t i = 0; i < plan.jobs.size(); ++i) {
    const PlannedJob& job = plan.jobs[i];
    JobRow& row = rows[i];
    const auto out = job.started ? reach.out_at.find(job.device) : reach.out_at.end();
    const bool device_out = out != reach.out_at.end() && job.start > out->second + 1e-9;
    if (job.started && !std::isfinite(ready(i))) {  // planned for after the run ended (its `after` past it)
      row.message = fmt::format("the run ended at {:g} s, before it was ready", r9(std::min(reach.stopped_at, reach.ended_at)));
      continue;
    }
    if (!job.started || (job.start > stop && !device_out)) {
      row.message = !job.started ? job.why_not
                    : std::isfinite(reach.stopped_at)
                        ? fmt::format("the campaign stopped at {:g} s, before it began: {}", r9(reach.stopped_at), reach.stop_message)
                        : fmt::format("the run ended at {:g} s, before it began", r9(reach.ended_at));
      continue;
    }
    if (device_out) {
      row.message = fmt::format("planned for {}, which was out after a failure at {:g} s (on_failure: continue); it was "
                                "not given to another device",
                                wc.objects[job.device].name, r9(out->second));
      continue;
    }
    row.start = job.start;
    if (const auto failed = std::find_if(reach.job_failures.begin(), reach.job_failures.end(),
                                         [i](const RunReach::JobFailure& f) { return f.job == static_cast<int>(i); });
        failed != reach.job_failures.end() && failed->t <= stop) {
      row.status = JobStatus::Failed;
      row.end = failed->t;
      row.message = failed->message;
      continue;
    }
    const PlanFailure* f = !job.failure ? nullptr
                           : *job.failure < plan.job_failures.size() ? &plan.job_failures[*job.failure]
                           : plan.failure ? &*plan.failure : nullptr;
    if (f && f->t <= stop) {
      row.status = JobStatus::Failed;
      row.end = f->t;
      row.message = f->message;
    } else if (!f && all_ended[i]) {
      row.status = JobStatus::Done;
      row.end = job.end;
    } else {
      row.status = JobStatus::Failed;
      row.end = reach.stopped_at;
      row.message = fmt::format("the campaign stopped at {:g} s: {}", r9(reach.stopped_at), reach.stop_message);
    }
  }

  CampaignOutcome out;
  RunSummaryFile::Campaign& c = out.figures;
  double first = INFINITY, last = -INFINITY;
  std::vector<double> waits;
  for (size_t i = 0; i < rows.size(); ++i) {
    c.done += rows[i].status == JobStatus::Done;
    c.failed += rows[i].status == JobStatus::Failed;
    c.not_started += rows[i].status == JobStatus::NotStarted;
    first = std::min(first, ready(i));
    if (std::isfinite(rows[i].start)) {
      last = std::max(last, rows[i].end);
      waits.push_back(rows[i].start - plan.jobs[i].ready);
    }
  }
  c.makespan = std::isfinite(first) && std::isfinite(last) ? r9(std::max(0.0, last - first)) : 0;
  c.throughput = c.makespan > 0 ? r9(c.done * 3600.0 / c.makespan) : 0;
  for (int d : plan.campaign_devices) {
    RunSummaryFile::Campaign::DeviceUse use;
    for (size_t i = 0; i < rows.size(); ++i)
      if (plan.jobs[i].device == d && std::isfinite(rows[i].start)) {
        ++use.jobs;
        use.busy += rows[i].end - rows[i].start;
      }
    use.busy = r9(use.busy);
    use.utilization = c.makespan > 0 ? r9(use.busy / c.makespan) : 0;
    c.devices.emplace_back(wc.objects[d].name, use);
  }
  if (!waits.empty()) {
    std::sort(waits.begin(), waits.end());
    double sum = 0;
    for (double w : waits) sum += w;
    c.wait_mean = r9(sum / waits.size());
    c.wait_p95 = r9(waits[static_cast<size_t>(std::ceil(0.95 * waits.size())) - 1]);  // nearest rank
    c.wait_max = r9(waits.back());
  }
  // The queue: a job joins when ready and leaves when it starts (one ready and started at once
  // never waited); those never started wait to the end.
  std::vector<std::pair<double, int>> queue;
  for (size_t i = 0; i < rows.size(); ++i) {
    if (!std::isfinite(ready(i))) continue;  // never ready (a load that never arrived, or the run ended first)
    if (std::isfinite(rows[i].start) && rows[i].start <= plan.jobs[i].ready + 1e-9) continue;
    queue.emplace_back(plan.jobs[i].ready, +1);
    if (std::isfinite(rows[i].start)) queue.emplace_back(rows[i].start, -1);
  }
  std::sort(queue.begin(), queue.end());  // at one time, starts (-1) before arrivals
  long waiting = 0;
  for (const auto& [t, change] : queue) c.queue_max = std::max<size_t>(c.queue_max, static_cast<size_t>(std::max(0L, waiting += change)));
  for (size_t i = 0; i < rows.size(); ++i)
    if (rows[i].status == JobStatus::Done)
      for (const Plan::SlotFrame& f : plan.slot_frames)
        if (plan.jobs[i].place == f.name) ++c.slots_used;
  // A frame is free when no object stands at it (campaign-format.md, "Slots"), the object it is
  // a frame of aside: a 2 cm pad's origin, 2 cm under its top, had every empty pad taken.
  for (const Plan::SlotFrame& f : plan.slot_frames) {
    bool taken = false;
    for (size_t o = 0; o < reach.positions.size(); ++o)
      taken = taken || (static_cast<int>(o) != f.owner && reach.positions[o] && (*reach.positions[o] - f.position).norm() <= kSlotOccupied);
    c.slots_free_at_end += !taken;
  }

  out.jobs_csv = "job,object,device,place,ready,start,end,wait,duration,status,message\n";
  for (size_t i = 0; i < rows.size(); ++i) {
    const PlannedJob& job = plan.jobs[i];
    const JobRow& r = rows[i];
    const bool ran = std::isfinite(r.start);
    const std::vector<std::string> cells = {job.name, wc.objects[job.object].name, ran ? wc.objects[job.device].name : "",
                                            ran ? job.place : "", number(ready(i)), number(r.start), number(r.end),
                                            ran ? number(r.start - job.ready) : "", ran ? number(r.end - r.start) : "", status_name(r.status),
                                            r.message};
    for (size_t k = 0; k < cells.size(); ++k) out.jobs_csv += (k ? "," : "") + csv_field(cells[k]);
    out.jobs_csv += "\n";
  }
  return out;
}

}  // namespace sscs
