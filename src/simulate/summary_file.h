#pragma once
/// summary.json, a run's one-page account: the one type that `simulate` writes and `compare`
/// (and the sweep's run metrics) read, so the file's keys are written down once.
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace sscs {

struct RunSummaryFile {
  std::string scenario, vault, status;  ///< status: ok, violations or failed
  std::string mode = "physics";         ///< sim.mode: physics or fast (files before it: physics)
  /// Fast mode: the devices that went on in physics, when, and why (a collision).
  struct HandOver {
    std::string device;
    double t = 0;
    std::string why;
  };
  std::vector<HandOver> handed_to_physics;
  /// Fast mode: how the run went: glides (stretches without steps), steps taken (contacts
  /// found) and of those the steps that ran the dynamics.
  struct FastFigures {
    long glides = 0, steps = 0, dynamics_steps = 0;
  };
  FastFigures fast;
  std::optional<double> cycle_time;     ///< null when the run stopped before its cycle was done
  double simulated_time = 0;
  struct Stopped {
    std::string by;  ///< the event that stopped it (unreachable, time_limit, ...)
    double t = 0;
    std::string message;
  };
  std::optional<Stopped> stopped;
  struct Step {
    size_t index = 0;
    std::string action;
    std::optional<std::string> device, object;
    std::optional<std::string> job;    ///< a campaign's: the job it belongs to ("store In_3")
    std::optional<double> start, end;  ///< null: not begun / not finished when the run stopped
    std::optional<double> short_by;    ///< a move that ended with its tool this far off its target (m)
    std::optional<double> turned_by;   ///< ... or turned this far off its target's orientation (deg)
  };
  std::vector<Step> steps;
  struct DeviceFigures {
    std::vector<std::pair<std::string, double>> joint_travel;  ///< per joint: deg (revolute) or m
    std::optional<double> revolute_deg, prismatic_m;            ///< totals per joint kind
    double tool_path_length = 0;                                ///< m
  };
  std::vector<std::pair<std::string, DeviceFigures>> devices;
  struct Clearance {
    double distance = 0;
    std::string a, b;
    double t = 0;
    /// A lower bound over the whole motion, between samples too (runs since issue 36); runs
    /// before it measured at the samples only.
    bool certified = false;
  };
  std::optional<Clearance> min_clearance;  ///< none: nothing came within the tracked range
  /// A collision from its first contact to its last (contacts apart less than 0.1 s are one):
  /// the deepest the two went into each other, when and where.
  struct CollisionEpisode {
    std::string a, b;  ///< `Object` or `Device.part`, as the first contact named them
    double start = 0, end = 0;
    double depth = 0;  ///< m, the deepest penetration of the episode
    double deepest_at = 0;
    std::optional<std::vector<double>> point;  ///< where the deepest contact was, when the physics placed it
  };
  std::vector<CollisionEpisode> collisions;
  std::vector<std::pair<std::string, size_t>> events;  ///< counts by kind
  /// ODE's solver messages, when there were any: on how many steps, the first and when.
  struct PhysicsMessages {
    size_t steps = 0;
    double first_at = 0;
    std::string first;
  };
  std::optional<PhysicsMessages> physics_messages;
  /// A campaign's figures (campaign-format.md, "What a campaign run writes").
  struct Campaign {
    size_t done = 0, failed = 0, not_started = 0;
    double makespan = 0;    ///< s: the first readiness to the last job's end
    double throughput = 0;  ///< jobs done per hour of the makespan
    struct DeviceUse {
      size_t jobs = 0;
      double busy = 0, utilization = 0;  ///< s running jobs, and that over the makespan
    };
    std::vector<std::pair<std::string, DeviceUse>> devices;
    double wait_mean = 0, wait_p95 = 0, wait_max = 0;  ///< s from ready to start, over the jobs started
    size_t queue_max = 0;   ///< the most jobs ready and waiting at once
    size_t slots_used = 0, slots_free_at_end = 0;
  };
  std::optional<Campaign> campaign;
  std::vector<std::pair<std::string, std::string>> inputs;  ///< path, sha256
  std::vector<std::string> inputs_not_in_resolved;
  std::string sscs_version;

  nlohmann::ordered_json to_json() const;
  /// The summary in `text`; nullopt with `error` set when it is not JSON or not a summary sscs
  /// writes (a key missing or of another type). Files of earlier versions without the per-kind
  /// travel totals, `stopped` or `inputs` are read.
  static std::optional<RunSummaryFile> parse(const std::string& text, std::string& error);
};

}  // namespace sscs
