#include "simulate/dispatch.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <set>

#include <fmt/format.h>

#include "core/names.h"

namespace sscs {

std::string frame_text(const Workcell& wc, const FrameRef& f) {
  return f.frame == "origin" ? wc.objects[f.object].name : fmt::format("{}.{}", wc.objects[f.object].name, f.frame);
}

namespace {

class Dispatcher {
 public:
  Dispatcher(const CampaignCommands& c, const Workcell& wc, const GeometryModel& geometry, Diagnostics& diag)
      : c_(c), wc_(wc), geometry_(geometry), diag_(diag), planner_(c.settings, wc, geometry), rng_(c.seed) {}

  std::optional<Plan> run() {
    Plan& plan = planner_.plan();
    for (const CampaignCommands::Job& j : c_.jobs) {
      PlannedJob pj;
      pj.name = c_.templates[j.job_template].name;
      pj.object = j.object;
      pj.ready = j.ready;
      plan.jobs.push_back(std::move(pj));
    }
    for (const JobTemplate& tmpl : c_.templates)
      for (int d : tmpl.devices)
        if (std::find(plan.campaign_devices.begin(), plan.campaign_devices.end(), d) == plan.campaign_devices.end())
          plan.campaign_devices.push_back(d);
    std::set<std::string> seen;
    for (const JobTemplate& tmpl : c_.templates)
      for (const FrameRef& f : tmpl.slots)
        if (seen.insert(frame_text(wc_, f)).second)
          plan.slot_frames.push_back({frame_text(wc_, f), planner_.frame_pose(f.object, f.frame).translation(), f.object});
    for (size_t k = 0; k < c_.arrivals.size(); ++k) {
      const CampaignCommands::Arrival& a = c_.arrivals[k];
      spots_[frame_text(wc_, a.spot)].queue.push_back(k);
      arriving_[a.object] = INFINITY;
      planner_.set_absent(a.object, true);
    }
    // A job of a load is ready once it arrives: never, if it never does (it was ready at 0 in
    // jobs.csv, and the makespan, throughput and queue counted it).
    for (size_t i = 0; i < c_.jobs.size(); ++i)
      if (arriving_.count(c_.jobs[i].object)) plan.jobs[i].ready = INFINITY;
    // Events in planned time: arrivals, readiness, devices going idle, claims and slots freed (a job's end).
    double t = 0;
    while (!stopped_) {
      arrive(t);
      start_what_can(t);
      double next = INFINITY;
      for (size_t i = 0; i < c_.jobs.size(); ++i)
        if (!plan.jobs[i].started && ready(i) > t) next = std::min(next, ready(i));
      for (const auto& [key, spot] : spots_)
        if (const double at = spot.next_arrival(c_); at > t) next = std::min(next, at);
      for (const auto& [d, until] : busy_until_)
        if (until > t) next = std::min(next, until);
      if (!std::isfinite(next) || stopped_ || next >= stop_at_) break;
      if (next > c_.settings.limit) {
        past_limit_ = true;
        break;
      }
      t = next;
    }
    for (const CampaignCommands::Arrival& a : c_.arrivals) plan.arrivals.emplace_back(a.object, arriving_[a.object]);
    for (size_t i = 0; i < plan.jobs.size(); ++i)
      if (!plan.jobs[i].started) plan.jobs[i].why_not = why_not(i);
    if (terminal_) plan.failure = terminal_;  // on_failure: stop: the run stops there
    plan.jobs_fail_alone = !c_.stop_on_failure;
    plan.runs_to_limit = past_limit_ && !terminal_;
    return planner_.finish(diag_);
  }

 private:
  /// A spot loads arrive at, one at a time: the arrivals in their order, and when the load
  /// standing there leaves (infinity until the job taking it is planned; 0: none stands there).
  struct Spot {
    std::vector<size_t> queue;  // CampaignCommands::arrivals
    size_t next = 0;
    int occupant = -1;
    double free_at = 0;
    double next_arrival(const CampaignCommands& c) const {
      return next < queue.size() ? std::max(c.arrivals[queue[next]].scheduled, free_at) : INFINITY;
    }
  };

  /// When job i is ready: its `after`, and for an arriving load once it has arrived (infinity before).
  double ready(size_t i) const {
    auto it = arriving_.find(c_.jobs[i].object);
    return it == arriving_.end() ? c_.jobs[i].ready : std::max(c_.jobs[i].ready, it->second);
  }

  /// The loads due at t arrive (each spot's next, once the load before it has left).
  void arrive(double t) {
    for (auto& [key, spot] : spots_) {
      const double at = spot.next_arrival(c_);
      if (at > t + 1e-9 || at >= stop_at_) continue;
      const int o = c_.arrivals[spot.queue[spot.next++]].object;
      arriving_[o] = at;
      planner_.set_absent(o, false);
      spot.occupant = o;
      spot.free_at = INFINITY;  // until the job that takes it lifts it away
      for (size_t i = 0; i < c_.jobs.size(); ++i)
        if (c_.jobs[i].object == o) planner_.plan().jobs[i].ready = ready(i);
    }
  }

  /// Starts, in queue order, every ready job that can start at t, until none can.
  void start_what_can(double t) {
    Plan& plan = planner_.plan();
    if (t >= stop_at_) return;  // the campaign stopped at a failure (on_failure: stop)
    for (bool any = true; any && !stopped_ && t < stop_at_;) {
      any = false;
      // The queue: in the order the jobs became ready (ties: the order of jobs:, then the names).
      std::vector<size_t> queue;
      for (size_t i = 0; i < c_.jobs.size(); ++i)
        if (!plan.jobs[i].started && ready(i) <= t + 1e-9) queue.push_back(i);
      std::stable_sort(queue.begin(), queue.end(), [&](size_t a, size_t b) { return ready(a) < ready(b); });
      for (size_t i : queue) {
        if (stopped_) break;
        const JobTemplate& tmpl = c_.templates[c_.jobs[i].job_template];
        if (!claims_free(tmpl, t)) continue;
        const int d = idle_device(tmpl, t);
        if (d < 0) continue;
        std::optional<FrameRef> place = tmpl.to;
        if (!tmpl.slots.empty()) {
          place = choose_slot(tmpl, c_.jobs[i].object, t);
          if (!place) continue;
        }
        start(i, d, place, t);
        any = true;
        break;  // the queue again: what this job took is taken
      }
    }
  }

  bool claims_free(const JobTemplate& tmpl, double t) const {
    for (int z : tmpl.claims)
      if (auto it = claimed_until_.find(z); it != claimed_until_.end() && it->second > t) return false;
    return true;
  }

  int idle_device(const JobTemplate& tmpl, double t) {
    for (int d : tmpl.devices) {
      auto busy = busy_until_.find(d);  // a job's last step may be a wait, which no device's motion shows
      if (!out_.count(d) && planner_.free_at(d) <= t + 1e-9 && (busy == busy_until_.end() || busy->second <= t + 1e-9)) return d;
    }
    return -1;
  }

  /// A frame of the template's slots that no object stands at (its origin within 5 cm) and no
  /// running job has reserved, by the template's choice; nullopt when none is free.
  std::optional<FrameRef> choose_slot(const JobTemplate& tmpl, int object, double t) {
    std::vector<std::pair<const FrameRef*, Eigen::Vector3d>> free;
    for (const FrameRef& f : tmpl.slots) {
      bool reserved = false;
      for (const auto& [r, until] : reserved_)
        if (until > t && r.object == f.object && r.frame == f.frame) reserved = true;
      if (reserved) continue;
      const Eigen::Vector3d p = planner_.frame_pose(f.object, f.frame).translation();
      bool taken = false;
      for (size_t o = 0; o < wc_.objects.size() && !taken; ++o)
        if (!geometry_.objects[o].device && !wc_.types[wc_.objects[o].type].container && static_cast<int>(o) != f.object &&
            !geometry_.objects[o].shapes.empty() && !absent(static_cast<int>(o)))
          taken = (planner_.object_pose(static_cast<int>(o)).translation() - p).norm() <= kSlotOccupied;
      if (!taken) free.emplace_back(&f, p);
    }
    if (free.empty()) return std::nullopt;
    switch (tmpl.choose) {
      case SlotChoice::First: return *free.front().first;  // the slots are in natural order
      case SlotChoice::Random: return *free[rng_() % free.size()].first;
      case SlotChoice::Lowest: {
        auto it = std::min_element(free.begin(), free.end(), [](const auto& a, const auto& b) { return a.second.z() < b.second.z() - 1e-9; });
        return *it->first;
      }
      case SlotChoice::Nearest: {
        const Eigen::Vector3d from = planner_.object_pose(object).translation();
        auto it = std::min_element(free.begin(), free.end(), [&](const auto& a, const auto& b) {
          return (a.second - from).norm() < (b.second - from).norm() - 1e-9;
        });
        return *it->first;
      }
    }
    return std::nullopt;
  }

  /// Job i starts at t on device d: its steps are planned one after another; a step that fails
  /// ends the job there (and the campaign, with on_failure: stop).
  void start(size_t i, int d, const std::optional<FrameRef>& place, double t) {
    Plan& plan = planner_.plan();
    PlannedJob& job = plan.jobs[i];
    const CampaignCommands::Job& j = c_.jobs[i];
    const JobTemplate& tmpl = c_.templates[j.job_template];
    job.started = true;
    job.device = d;
    job.start = t;
    job.place = place ? frame_text(wc_, *place) : "";
    Diagnostics local;
    std::vector<StepCommand> steps = c_.steps(JobBinding{j.job_template, j.object, d, place}, local);
    double at = t, lifted_at = INFINITY;
    bool grasped = false, found = false;
    size_t k = 0;
    for (; k < steps.size() && !local.has_errors(); ++k) {
      steps[k].index = next_index_++;
      at = planner_.plan(steps[k], at, static_cast<int>(i), local);
      if (planner_.failure()) break;
      // A failure an earlier run found here: the job ends with this step (which the run begins,
      // and finds failing again).
      if (std::any_of(c_.found.begin(), c_.found.end(), [&](const FoundInRun& f) { return f.job == i && f.step == k; })) {
        found = true;
        break;
      }
      if (steps[k].kind == StepKind::Grasp && steps[k].object == j.object) grasped = true;
      else if (grasped && !std::isfinite(lifted_at) && (steps[k].kind == StepKind::MoveTo || steps[k].kind == StepKind::MoveJoints) &&
               clear_of_spot(j.object))
        lifted_at = at;
    }
    for (const Diagnostic& e : local.errors())
      diag_.error(e.mark, fmt::format("{} (job '{}' for {}, on {})", e.message, tmpl.name, wc_.objects[j.object].name,
                                      wc_.objects[d].name));
    if (local.has_errors()) {  // reported: the campaign does not run
      stopped_ = true;
      return;
    }
    if (found) {
      for (size_t rest = k + 1; rest < steps.size(); ++rest) {
        steps[rest].index = next_index_++;
        PlannedStep ps{steps[rest].index, steps[rest].kind, steps[rest].mark, steps[rest].device, steps[rest].object, 0, 0};
        ps.job = static_cast<int>(i);
        plan.not_begun.push_back(ps);
      }
      out_.insert(d);  // the device takes no more jobs
    }
    if (planner_.failure()) {
      for (size_t rest = k + 1; rest < steps.size(); ++rest) {
        steps[rest].index = next_index_++;
        PlannedStep ps{steps[rest].index, steps[rest].kind, steps[rest].mark, steps[rest].device, steps[rest].object, 0, 0};
        ps.job = static_cast<int>(i);
        plan.not_begun.push_back(ps);
      }
      if (c_.stop_on_failure) {  // the campaign ends here: jobs under way then go on until it, none starts after
        PlanFailure f = planner_.take_failure();
        if (!terminal_ || f.t < terminal_->t) {  // the earliest failure stops it; a later one is never reached
          if (terminal_) plan.jobs[terminal_job_].failure.reset();
          terminal_ = f;
          terminal_job_ = i;
          job.failure = std::numeric_limits<size_t>::max();
        }
        stop_at_ = terminal_->t;
      } else {
        job.failure = plan.job_failures.size();
        plan.job_failures.push_back(planner_.take_failure());
        out_.insert(d);  // the device takes no more jobs
      }
    }
    // The load this job takes leaves its arrival spot with the first move after its grasp that
    // takes it clear of it: the next may come then.
    for (auto& [key, spot] : spots_)
      if (spot.occupant == j.object) {
        spot.free_at = lifted_at;
        if (std::isfinite(lifted_at)) spot.occupant = -1;
      }
    job.end = at;
    busy_until_[d] = at;
    for (int z : tmpl.claims) claimed_until_[z] = at;
    if (place && !tmpl.slots.empty()) reserved_.emplace_back(*place, at);
  }

  /// Whether load `o`, where planning has it now, is clear of the place it arrived at: its box
  /// there and its box now (each widened by 1 cm) do not meet. A forklift's pallet lifted 10 cm
  /// still hangs over its stand (the next pallet appeared under it: ODE gave up on the meshes).
  bool clear_of_spot(int o) const {
    const ObjectGeometry& g = geometry_.objects[o];
    const Eigen::AlignedBox3d there = g.bbox_world;
    if (there.isEmpty()) return true;
    const Eigen::Isometry3d moved = planner_.object_pose(o) * g.X_world_object.inverse();
    Eigen::AlignedBox3d now;
    for (int c = 0; c < 8; ++c) now.extend(moved * there.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));
    const Eigen::Vector3d widen = Eigen::Vector3d::Constant(0.01);
    return !Eigen::AlignedBox3d(there.min() - widen, there.max() + widen).intersects(now);
  }

  bool absent(int o) const {
    auto it = arriving_.find(o);
    return it != arriving_.end() && !std::isfinite(it->second);
  }

  std::string why_not(size_t i) {
    const JobTemplate& tmpl = c_.templates[c_.jobs[i].job_template];
    // The campaign ends with its last job (or its failure): a load due after that never arrives,
    // though the planned time had it arrive (with no slot free for it, say).
    double end = terminal_ ? terminal_->t : 0;
    for (const PlannedJob& job : planner_.plan().jobs)
      if (job.started) end = std::max(end, job.end);
    auto arrives = [&](int o) {
      auto it = arriving_.find(o);
      return it == arriving_.end() || it->second <= end + 1e-9;
    };
    if (absent(c_.jobs[i].object) || !arrives(c_.jobs[i].object)) {
      for (const auto& [key, spot] : spots_)
        if (spot.occupant >= 0 && arrives(spot.occupant) && std::find_if(spot.queue.begin(), spot.queue.end(), [&](size_t k) {
              return c_.arrivals[k].object == c_.jobs[i].object;
            }) != spot.queue.end())
          return fmt::format("it never arrived: {} still stood at {}, where it arrives", wc_.objects[spot.occupant].name, key);
      return "it never arrived: the campaign ended first";
    }
    if (terminal_) return fmt::format("the campaign stopped at {:g} s, when a job failed (on_failure: stop)", terminal_->t);
    if (past_limit_ || c_.jobs[i].ready > c_.settings.limit) return "the campaign's time limit came first";
    bool any_device = false;
    for (int d : tmpl.devices) any_device = any_device || !out_.count(d);
    if (!any_device) return "every device that may do it failed a job and was taken out";
    if (!tmpl.slots.empty()) return "no slot was free";
    return "it could never start";
  }

  const CampaignCommands& c_;
  const Workcell& wc_;
  const GeometryModel& geometry_;
  Diagnostics& diag_;
  StepPlanner planner_;
  std::mt19937_64 rng_;  // fully specified by the standard: the same picks on any platform
  std::map<int, double> busy_until_, claimed_until_;
  std::map<std::string, Spot> spots_;  // by the frame's name
  std::map<int, double> arriving_;     // arriving load -> when it arrived (infinity: not yet)
  std::vector<std::pair<FrameRef, double>> reserved_;  // slots and until when their job runs
  std::set<int> out_;                                  // devices that failed a job (on_failure: continue)
  size_t next_index_ = 0;
  bool stopped_ = false, past_limit_ = false;  // stopped_: an input error in a job's steps
  std::optional<PlanFailure> terminal_;         // on_failure: stop: the earliest failure
  size_t terminal_job_ = 0;
  double stop_at_ = INFINITY;
};

}  // namespace

std::optional<Plan> plan_campaign(const CampaignCommands& campaign, const Workcell& wc, const GeometryModel& geometry,
                                  Diagnostics& diag) {
  std::optional<Plan> plan = Dispatcher(campaign, wc, geometry, diag).run();
  if (plan && plan->jobs_fail_alone) {
    plan->found = campaign.found;
    // The same campaign knowing one more failure (its inputs were read without error once).
    plan->replan = [commands = std::make_shared<const CampaignCommands>(campaign), &wc, &geometry](const std::vector<FoundInRun>& found) {
      CampaignCommands again = *commands;
      again.found = found;
      Diagnostics quiet;
      return plan_campaign(again, wc, geometry, quiet);
    };
  }
  return plan;
}

}  // namespace sscs
