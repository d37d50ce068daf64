#pragma once
/// A run's event log: typed events with their fields, in time order, counted by kind. Written
/// as events.jsonl and counted in summary.json's `events`.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace sscs {

/// Times and values as runs log them: rounded to 1e-9 (nanoseconds, nanometres).
inline double r9(double x) { return std::round(x * 1e9) / 1e9; }

/// Every kind of event a run records, in the alphabetical order of their names (summary.json
/// counts them in that order).
enum class EventKind : uint8_t {
  Arrived, AtRest, Collision, Constraint, Displaced, Grasp, GraspMissed, JointLimit, KeepOut, Landed, LoadShifted, NotAtRest, Propped, Release, Singular,
  StepEnd, StepStart, TimeLimit, TrackingError, Unreachable, WallLimit,
};
inline constexpr std::array<std::string_view, 21> kEventKindNames = {
    "arrived", "at_rest", "collision", "constraint", "displaced", "grasp", "grasp_missed", "joint_limit", "keep_out", "landed", "load_shifted",
    "not_at_rest", "propped", "release", "singular", "step_end", "step_start", "time_limit", "tracking_error", "unreachable", "wall_limit"};
static_assert(static_cast<size_t>(EventKind::WallLimit) + 1 == kEventKindNames.size());
/// The name events.jsonl writes (`step_start`, `collision`, ...).
constexpr std::string_view event_kind_name(EventKind k) { return kEventKindNames[static_cast<size_t>(k)]; }

class EventLog {
 public:
  /// Records an event at simulated time `t` (rounded as every logged time is): `t`, `kind`, then
  /// `fields` in their order.
  /// Returns its index, for update().
  size_t add(double t, EventKind kind, const nlohmann::ordered_json& fields = nlohmann::ordered_json::object());
  /// Sets field `key` of event `index` (an episode's event that grows while it lasts).
  void update(size_t index, const std::string& key, const nlohmann::ordered_json& value) { events_.at(index)[key] = value; }
  size_t count(EventKind kind) const { return counts_[static_cast<size_t>(kind)]; }
  size_t size() const { return events_.size(); }
  /// events.jsonl: one JSON object per line.
  std::string jsonl() const;
  /// {kind: count} of the kinds that occurred, by name.
  nlohmann::ordered_json counts_json() const;

 private:
  std::vector<nlohmann::ordered_json> events_;
  std::array<size_t, kEventKindNames.size()> counts_{};
};

}  // namespace sscs
