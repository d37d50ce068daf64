#include "simulate/clearance.h"

#include <cmath>

#include <fmt/format.h>

#include "model/device.h"
#include "simulate/events.h"

namespace sscs {

namespace {
constexpr double kClearanceReach = 2.0;  // m: clearances beyond this are not tracked
}  // namespace

ClearanceTracker::ClearanceTracker(const Workcell& wc, const GeometryModel& geometry)
    : wc_(wc), geometry_(geometry), nearby_(geometry) {}

std::string run_part_name(const Workcell& wc, const GeometryModel& geometry, int o, int part) {
  if (o < 0) return "floor";
  const ObjectGeometry& g = geometry.objects[o];
  return part >= 0 && g.device ? fmt::format("{}.{}", wc.objects[o].name, g.device->parts[part].name) : wc.objects[o].name;
}

std::vector<int> ClearanceTracker::within(int object, const Eigen::Isometry3d& X_world_object, const std::vector<int>& skip,
                                          double gap) {
  nearby_.move(object, X_world_object);
  std::vector<int> out;
  for (const Proximity& p : nearby_.proximity(object, skip, gap)) out.push_back(p.other);
  return out;
}

void ClearanceTracker::measure(double t, int moving, const std::vector<int>& skip, const std::vector<char>& parts) {
  // Only closer approaches than seen so far are news: the search skips pairs that cannot be.
  auto closest_seen = [this, moving](int other) {
    auto it = seen_.find({moving, other});
    return it == seen_.end() ? INFINITY : it->second.distance;
  };
  for (const Proximity& p : nearby_.proximity(moving, skip, kClearanceReach, closest_seen, parts)) {
    auto key = std::make_pair(moving, p.other);
    auto it = seen_.find(key);
    if (it != seen_.end() && it->second.distance <= p.distance) continue;
    seen_[key] = {p.distance, t, run_part_name(wc_, geometry_, moving, p.part), run_part_name(wc_, geometry_, p.other, p.other_part)};
  }
}

std::optional<RunSummaryFile::Clearance> ClearanceTracker::closest(const std::set<std::pair<int, int>>& supports) const {
  const std::pair<const std::pair<int, int>, Seen>* best = nullptr;
  for (const auto& entry : seen_) {
    if (supports.count(entry.first)) continue;
    if (!best || entry.second.distance < best->second.distance) best = &entry;
  }
  if (!best) return std::nullopt;
  return RunSummaryFile::Clearance{r9(best->second.distance), best->second.a, best->second.b, r9(best->second.t)};
}

}  // namespace sscs
