#include "simulate/events.h"

#include <algorithm>

namespace sscs {

size_t EventLog::add(double t, EventKind kind, const nlohmann::ordered_json& fields) {
  nlohmann::ordered_json e;
  e["t"] = r9(t);
  e["kind"] = event_kind_name(kind);
  for (const auto& [k, v] : fields.items()) e[k] = v;
  events_.push_back(std::move(e));
  ++counts_[static_cast<size_t>(kind)];
  return events_.size() - 1;
}

std::string EventLog::jsonl() const {
  // In time order: an event found between samples (a rule broken between them) is added at the
  // sample after it; events of one time keep the order they were added in.
  std::vector<size_t> order(events_.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return events_[a]["t"].get<double>() < events_[b]["t"].get<double>(); });
  std::string out;
  for (size_t i : order) out += events_[i].dump() + "\n";
  return out;
}

nlohmann::ordered_json EventLog::counts_json() const {
  nlohmann::ordered_json counts = nlohmann::ordered_json::object();
  for (size_t k = 0; k < counts_.size(); ++k)
    if (counts_[k] > 0) counts[std::string(kEventKindNames[k])] = counts_[k];
  return counts;
}

}  // namespace sscs
