#include "simulate/clearance.h"

#include <algorithm>
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

bool ClearanceTracker::Pair::is_excused(double t) const {
  return std::any_of(excused.begin(), excused.end(), [t](const auto& w) { return t >= w.first && t <= w.second; });
}

void ClearanceTracker::keep(Pair& pair, Seen seen) {
  if (seen.distance >= pair.closest()) return;
  if (seen.distance >= -kContact && pair.is_excused(seen.t)) return;
  pair.records.push_back(std::move(seen));
}

void ClearanceTracker::measure(double t, int moving, const std::vector<int>& skip, const std::vector<char>& parts) {
  // Only closer approaches than seen so far are news: the search skips pairs that cannot be.
  auto closest_seen = [this, moving](int other) {
    auto it = pairs_.find(key(moving, other));
    return it == pairs_.end() ? INFINITY : it->second.closest();
  };
  for (const Proximity& p : nearby_.proximity(moving, skip, kClearanceReach, closest_seen, parts))
    keep(pairs_[key(moving, p.other)],
         {p.distance, t, run_part_name(wc_, geometry_, moving, p.part), run_part_name(wc_, geometry_, p.other, p.other_part)});
}

void ClearanceTracker::measure_penetration(double t, int a, int b) {
  std::pair<int, int> parts{-1, -1};  // named as a collision names them: the device's part
  const std::optional<double> d = nearby_.distance(a, b, &parts);
  if (!d || *d >= -kContact) return;
  keep(pairs_[key(a, b)], {*d, t, run_part_name(wc_, geometry_, a, parts.first), run_part_name(wc_, geometry_, b, parts.second)});
}

void ClearanceTracker::excuse(int a, int b, double from, double to) {
  Pair& pair = pairs_[key(a, b)];
  pair.excused.emplace_back(from, to);
  std::erase_if(pair.records, [&](const Seen& s) { return s.distance >= -kContact && s.t >= from && s.t <= to; });
}

std::optional<RunSummaryFile::Clearance> ClearanceTracker::closest() const {
  const Seen* best = nullptr;
  for (const auto& [k, pair] : pairs_)
    if (!pair.records.empty() && (!best || pair.records.back().distance < best->distance)) best = &pair.records.back();
  if (!best) return std::nullopt;
  return RunSummaryFile::Clearance{r9(best->distance), best->a, best->b, r9(best->t)};
}

}  // namespace sscs
