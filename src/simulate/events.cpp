#include "simulate/events.h"

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
  std::string out;
  for (const auto& e : events_) out += e.dump() + "\n";
  return out;
}

nlohmann::ordered_json EventLog::counts_json() const {
  nlohmann::ordered_json counts = nlohmann::ordered_json::object();
  for (size_t k = 0; k < counts_.size(); ++k)
    if (counts_[k] > 0) counts[std::string(kEventKindNames[k])] = counts_[k];
  return counts;
}

}  // namespace sscs
