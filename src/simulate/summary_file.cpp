#include "simulate/summary_file.h"

#include <fmt/format.h>

namespace sscs {

namespace {

using json = nlohmann::ordered_json;

json or_null(const std::optional<double>& x) { return x ? json(*x) : json(nullptr); }

/// Reads a summary's members by their types; the first mismatch is kept.
class Reader {
 public:
  std::string error;

  const json* member(const json& at, const char* key, const std::string& where, bool required = true) {
    if (!at.is_object()) return fail(where, "an object");
    auto it = at.find(key);
    if (it == at.end()) {
      if (required && error.empty()) error = fmt::format("'{}' has no '{}'", where, key);
      return nullptr;
    }
    return &*it;
  }
  std::string text(const json& at, const char* key, const std::string& where) {
    const json* v = member(at, key, where);
    if (v && !v->is_string()) fail(where + "." + key, "a string");
    return v && v->is_string() ? v->get<std::string>() : "";
  }
  double number(const json& at, const char* key, const std::string& where) { return number_of(member(at, key, where), where + "." + key); }
  double number_of(const json* v, const std::string& where) {
    if (v && !v->is_number()) fail(where, "a number");
    return v && v->is_number() ? v->get<double>() : 0.0;
  }
  std::optional<double> maybe_number(const json& at, const char* key, const std::string& where) {
    const json* v = member(at, key, where, false);
    if (!v || v->is_null()) return std::nullopt;
    return number_of(v, where + "." + key);
  }
  std::optional<std::string> maybe_text(const json& at, const char* key, const std::string& where) {
    const json* v = member(at, key, where, false);
    if (!v || v->is_null()) return std::nullopt;
    if (!v->is_string()) fail(where + "." + key, "a string");
    return v->is_string() ? std::optional(v->get<std::string>()) : std::nullopt;
  }
  const json* object(const json& at, const char* key, const std::string& where, bool required = true) {
    const json* v = member(at, key, where, required);
    if (v && !v->is_object()) return fail(where + "." + key, "an object");
    return v;
  }
  const json* array(const json& at, const char* key, const std::string& where, bool required = true) {
    const json* v = member(at, key, where, required);
    if (v && !v->is_array()) return fail(where + "." + key, "an array");
    return v;
  }

 private:
  const json* fail(const std::string& where, const char* expected) {
    if (error.empty()) error = fmt::format("'{}' should be {}", where, expected);
    return nullptr;
  }
};

}  // namespace

/// What an ODE solver message means for the run's numbers (docs/simulation.md).
constexpr const char* kPhysicsMessagesMeaning =
    "on these steps ODE's contact solver stopped early and left the remaining contact forces at zero: bodies "
    "in contact then may have moved (sunk, slid or been thrown) where they would not; poses, clearances and "
    "events after the first such step are less certain than the run's other figures";

nlohmann::ordered_json RunSummaryFile::to_json() const {
  json j;
  j["sscs"] = 1;
  j["scenario"] = scenario;
  j["vault"] = vault;
  j["status"] = status;
  j["mode"] = mode;
  if (mode == "fast") {
    json h = json::array();
    for (const HandOver& x : handed_to_physics) h.push_back({{"device", x.device}, {"t", x.t}, {"why", x.why}});
    j["handed_to_physics"] = std::move(h);
    j["fast"] = {{"glides", fast.glides}, {"steps", fast.steps}, {"dynamics_steps", fast.dynamics_steps}};
  }
  j["cycle_time"] = or_null(cycle_time);
  j["simulated_time"] = simulated_time;
  if (stopped) {
    json s = {{"by", stopped->by}, {"t", stopped->t}};
    if (!stopped->message.empty()) s["message"] = stopped->message;
    j["stopped"] = std::move(s);
  }
  json st = json::array();
  for (const Step& s : steps) {
    json e = {{"index", s.index}, {"action", s.action}};
    e["device"] = s.device ? json(*s.device) : json(nullptr);
    if (s.object) e["object"] = *s.object;
    if (s.job) e["job"] = *s.job;
    e["start"] = or_null(s.start);
    e["end"] = or_null(s.end);
    if (s.short_by) e["short_by"] = *s.short_by;
    if (s.turned_by) e["turned_by"] = *s.turned_by;
    st.push_back(std::move(e));
  }
  j["steps"] = std::move(st);
  json dev = json::object();
  for (const auto& [name, d] : devices) {
    json travel = json::object();
    for (const auto& [joint, x] : d.joint_travel) travel[joint] = x;
    json totals = json::object();
    if (d.revolute_deg) totals["revolute_deg"] = *d.revolute_deg;
    if (d.prismatic_m) totals["prismatic_m"] = *d.prismatic_m;
    dev[name] = {{"joint_travel", travel}, {"joint_travel_units", "deg for revolute joints, m for prismatic"},
                 {"joint_travel_total", totals}, {"tool_path_length", d.tool_path_length}};
  }
  j["devices"] = std::move(dev);
  j["min_clearance"] = min_clearance ? json{{"distance", min_clearance->distance}, {"a", min_clearance->a}, {"b", min_clearance->b},
                                            {"t", min_clearance->t}, {"certified", min_clearance->certified}}
                                     : json(nullptr);
  json episodes = json::array();
  for (const CollisionEpisode& c : collisions) {
    json e = {{"a", c.a}, {"b", c.b}, {"start", c.start}, {"end", c.end}, {"depth", c.depth}, {"deepest_at", c.deepest_at}};
    if (c.point) e["point"] = *c.point;
    episodes.push_back(std::move(e));
  }
  j["collisions"] = std::move(episodes);
  json counts = json::object();
  for (const auto& [kind, n] : events) counts[kind] = n;
  j["events"] = std::move(counts);
  if (physics_messages)
    j["physics_messages"] = {{"steps", physics_messages->steps}, {"first_at", physics_messages->first_at},
                             {"first", physics_messages->first}, {"meaning", kPhysicsMessagesMeaning}};
  if (campaign) {
    const Campaign& c = *campaign;
    json dev = json::object();
    for (const auto& [name, d] : c.devices) dev[name] = {{"jobs", d.jobs}, {"busy", d.busy}, {"utilization", d.utilization}};
    j["campaign"] = {{"jobs", {{"done", c.done}, {"failed", c.failed}, {"not_started", c.not_started}}},
                     {"makespan", c.makespan},
                     {"throughput", c.throughput},
                     {"devices", std::move(dev)},
                     {"wait", {{"mean", c.wait_mean}, {"p95", c.wait_p95}, {"max", c.wait_max}}},
                     {"queue_max", c.queue_max},
                     {"slots", {{"used", c.slots_used}, {"free_at_end", c.slots_free_at_end}}}};
  }
  if (!inputs.empty()) {
    json in = json::array();
    for (const auto& [path, sha] : inputs) in.push_back({{"path", path}, {"sha256", sha}});
    j["inputs"] = std::move(in);
    if (!inputs_not_in_resolved.empty()) j["inputs_not_in_resolved"] = inputs_not_in_resolved;
  }
  j["sscs_version"] = sscs_version;
  return j;
}

std::optional<RunSummaryFile> RunSummaryFile::parse(const std::string& text, std::string& error) {
  json j = json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    error = "not JSON";
    return std::nullopt;
  }
  Reader r;
  RunSummaryFile s;
  s.scenario = r.text(j, "scenario", "summary");
  s.vault = r.text(j, "vault", "summary");
  s.status = r.text(j, "status", "summary");
  s.mode = r.maybe_text(j, "mode", "summary").value_or("physics");
  s.cycle_time = r.maybe_number(j, "cycle_time", "summary");
  s.simulated_time = r.number(j, "simulated_time", "summary");
  if (const json* st = r.object(j, "stopped", "summary", false))
    s.stopped = Stopped{r.text(*st, "by", "stopped"), r.number(*st, "t", "stopped"), r.maybe_text(*st, "message", "stopped").value_or("")};
  if (const json* steps = r.array(j, "steps", "summary"))
    for (const json& e : *steps) {
      Step step;
      step.index = static_cast<size_t>(r.number(e, "index", "steps[]"));
      step.action = r.text(e, "action", "steps[]");
      step.device = r.maybe_text(e, "device", "steps[]");
      step.object = r.maybe_text(e, "object", "steps[]");
      step.job = r.maybe_text(e, "job", "steps[]");
      step.start = r.maybe_number(e, "start", "steps[]");
      step.end = r.maybe_number(e, "end", "steps[]");
      step.short_by = r.maybe_number(e, "short_by", "steps[]");
      step.turned_by = r.maybe_number(e, "turned_by", "steps[]");
      s.steps.push_back(std::move(step));
    }
  if (const json* devices = r.object(j, "devices", "summary"))
    for (const auto& [name, d] : devices->items()) {
      const std::string where = "devices." + name;
      DeviceFigures f;
      if (const json* travel = r.object(d, "joint_travel", where, false))
        for (const auto& [joint, x] : travel->items()) f.joint_travel.emplace_back(joint, r.number_of(&x, where + ".joint_travel." + joint));
      if (const json* totals = r.object(d, "joint_travel_total", where, false)) {  // absent in early runs
        f.revolute_deg = r.maybe_number(*totals, "revolute_deg", where + ".joint_travel_total");
        f.prismatic_m = r.maybe_number(*totals, "prismatic_m", where + ".joint_travel_total");
      }
      f.tool_path_length = r.number(d, "tool_path_length", where);
      s.devices.emplace_back(name, std::move(f));
    }
  if (const json* mc = r.member(j, "min_clearance", "summary", false); mc && !mc->is_null())
    s.min_clearance = Clearance{r.number(*mc, "distance", "min_clearance"), r.text(*mc, "a", "min_clearance"),
                                r.text(*mc, "b", "min_clearance"), r.number(*mc, "t", "min_clearance"),
                                mc->contains("certified") && mc->at("certified").is_boolean() && mc->at("certified").get<bool>()};
  if (const json* list = r.array(j, "collisions", "summary", false))  // absent before episodes were kept
    for (const json& e : *list) {
      CollisionEpisode c{r.text(e, "a", "collisions[]"), r.text(e, "b", "collisions[]"), r.number(e, "start", "collisions[]"),
                         r.number(e, "end", "collisions[]"), r.number(e, "depth", "collisions[]"),
                         r.number(e, "deepest_at", "collisions[]"), std::nullopt};
      if (const json* p = r.array(e, "point", "collisions[]", false)) {
        std::vector<double> xyz;
        for (const json& x : *p) xyz.push_back(r.number_of(&x, "collisions[].point"));
        c.point = std::move(xyz);
      }
      s.collisions.push_back(std::move(c));
    }
  if (const json* events = r.object(j, "events", "summary"))
    for (const auto& [kind, n] : events->items()) {
      if (!n.is_number_unsigned() && !(n.is_number_integer() && n.get<long long>() >= 0)) {
        if (r.error.empty()) r.error = fmt::format("'events.{}' should be a count", kind);
        continue;
      }
      s.events.emplace_back(kind, n.get<size_t>());
    }
  if (const json* pm = r.object(j, "physics_messages", "summary", false))
    s.physics_messages = PhysicsMessages{static_cast<size_t>(r.number(*pm, "steps", "physics_messages")),
                                         r.number(*pm, "first_at", "physics_messages"), r.text(*pm, "first", "physics_messages")};
  if (const json* c = r.object(j, "campaign", "summary", false)) {
    Campaign k;
    auto count = [&](const json& at, const char* key, const std::string& where) { return static_cast<size_t>(r.number(at, key, where)); };
    if (const json* jobs = r.object(*c, "jobs", "campaign")) {
      k.done = count(*jobs, "done", "campaign.jobs");
      k.failed = count(*jobs, "failed", "campaign.jobs");
      k.not_started = count(*jobs, "not_started", "campaign.jobs");
    }
    k.makespan = r.number(*c, "makespan", "campaign");
    k.throughput = r.number(*c, "throughput", "campaign");
    if (const json* devices = r.object(*c, "devices", "campaign"))
      for (const auto& [name, d] : devices->items())
        k.devices.emplace_back(name, Campaign::DeviceUse{count(d, "jobs", "campaign.devices." + name), r.number(d, "busy", "campaign.devices." + name),
                                                         r.number(d, "utilization", "campaign.devices." + name)});
    if (const json* w = r.object(*c, "wait", "campaign")) {
      k.wait_mean = r.number(*w, "mean", "campaign.wait");
      k.wait_p95 = r.number(*w, "p95", "campaign.wait");
      k.wait_max = r.number(*w, "max", "campaign.wait");
    }
    k.queue_max = count(*c, "queue_max", "campaign");
    if (const json* sl = r.object(*c, "slots", "campaign")) {
      k.slots_used = count(*sl, "used", "campaign.slots");
      k.slots_free_at_end = count(*sl, "free_at_end", "campaign.slots");
    }
    s.campaign = std::move(k);
  }
  if (const json* inputs = r.array(j, "inputs", "summary", false))
    for (const json& e : *inputs) s.inputs.emplace_back(r.text(e, "path", "inputs[]"), r.text(e, "sha256", "inputs[]"));
  if (const json* left = r.array(j, "inputs_not_in_resolved", "summary", false))
    for (const json& e : *left) {
      if (e.is_string()) s.inputs_not_in_resolved.push_back(e.get<std::string>());
      else if (r.error.empty()) r.error = "'inputs_not_in_resolved' should hold strings";
    }
  if (auto v = r.maybe_text(j, "sscs_version", "summary")) s.sscs_version = *v;
  if (!r.error.empty()) {
    error = r.error;
    return std::nullopt;
  }
  return s;
}

}  // namespace sscs
