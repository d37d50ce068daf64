#include "report/compare.h"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <set>

#include <fmt/format.h>

#include "core/csv.h"

#include "core/archive.h"
#include "core/digest.h"

namespace fs = std::filesystem;

namespace sscs {

namespace {

/// One comparable figure of a run.
struct CompareRow {
  std::string name;
  std::string unit;
  std::vector<std::string> values;  // one per run, "" when absent
};


/// The value of `key` in a list of pairs, or nullptr.
template <typename T>
const T* find_in(const std::vector<std::pair<std::string, T>>& pairs, const std::string& key) {
  for (const auto& [k, v] : pairs)
    if (k == key) return &v;
  return nullptr;
}

/// How a table shows numbers: rounded for reading (text), or every digit the summary holds (CSV,
/// read by scripts that rank runs: 0.0297 and 0.0304 must not both be 0.030).
enum class Digits { Rounded, Full };

std::vector<CompareRow> metrics(const std::vector<RunRecord>& runs, Digits digits) {
  // Rounded: `fixed` decimals, but a clearance keeps 4 significant digits (a 0.4 mm penetration is not "-0.000").
  auto number = [digits](double v, int fixed) {
    if (digits == Digits::Full) return fmt::format("{}", v);
    return fixed >= 0 ? fmt::format("{:.{}f}", v, fixed) : fmt::format("{:.4g}", v);
  };
  std::vector<CompareRow> out = {{"scenario", "", {}}, {"status", "", {}}, {"cycle time", "s", {}}};
  std::set<std::string> devices, kinds;
  for (const RunRecord& r : runs) {
    for (const auto& [name, d] : r.summary.devices) devices.insert(name);
    for (const auto& [kind, n] : r.summary.events) kinds.insert(kind);
    out[0].values.push_back(r.summary.scenario);
    out[1].values.push_back(r.summary.status);
    out[2].values.push_back(r.summary.cycle_time ? number(*r.summary.cycle_time, 3) : "");
  }
  // A campaign's figures (campaign-format.md), where any run is one: what decides between two
  // concepts over hours.
  if (std::any_of(runs.begin(), runs.end(), [](const RunRecord& r) { return r.summary.campaign.has_value(); })) {
    using Campaign = RunSummaryFile::Campaign;
    auto figure = [&](const char* name, const char* unit, const std::function<std::string(const Campaign&)>& value) {
      CompareRow row{name, unit, {}};
      for (const RunRecord& r : runs) row.values.push_back(r.summary.campaign ? value(*r.summary.campaign) : "");
      out.push_back(std::move(row));
    };
    figure("throughput", "jobs/h", [&](const Campaign& c) { return number(c.throughput, 2); });
    figure("makespan", "s", [&](const Campaign& c) { return number(c.makespan, 3); });
    figure("jobs done", "", [](const Campaign& c) { return fmt::format("{}", c.done); });
    figure("jobs failed", "", [](const Campaign& c) { return fmt::format("{}", c.failed); });
    figure("jobs not started", "", [](const Campaign& c) { return fmt::format("{}", c.not_started); });
    figure("wait mean", "s", [&](const Campaign& c) { return number(c.wait_mean, 3); });
    figure("wait p95", "s", [&](const Campaign& c) { return number(c.wait_p95, 3); });
    figure("wait max", "s", [&](const Campaign& c) { return number(c.wait_max, 3); });
    figure("queue max", "", [](const Campaign& c) { return fmt::format("{}", c.queue_max); });
    std::set<std::string> used;
    for (const RunRecord& r : runs)
      if (r.summary.campaign)
        for (const auto& [name, use] : r.summary.campaign->devices) used.insert(name);
    for (const std::string& d : used) {
      CompareRow row{d + " utilization", "", {}}, jobs{d + " jobs", "", {}};
      for (const RunRecord& r : runs) {
        const Campaign::DeviceUse* use = r.summary.campaign ? find_in(r.summary.campaign->devices, d) : nullptr;
        row.values.push_back(use ? number(use->utilization, 3) : "");
        jobs.values.push_back(use ? fmt::format("{}", use->jobs) : "");
      }
      out.push_back(std::move(row));
      out.push_back(std::move(jobs));
    }
  }
  CompareRow clearance{"min clearance", "m", {}}, pair{"closest pair", "", {}};
  for (const RunRecord& r : runs) {
    const auto& mc = r.summary.min_clearance;
    clearance.values.push_back(mc ? number(mc->distance, -1) : "> 2");
    pair.values.push_back(mc ? fmt::format("{} / {}", mc->a, mc->b) : "");
  }
  out.push_back(std::move(clearance));
  out.push_back(std::move(pair));
  for (const std::string& d : devices) {
    // Joint travel per joint kind (degrees and metres are never added): a row for each kind the
    // device has in any of the runs.
    CompareRow path{d + " tool path", "m", {}}, turned{d + " joint travel, revolute", "deg", {}}, slid{d + " joint travel, prismatic", "m", {}};
    bool any_turned = false, any_slid = false;
    for (const RunRecord& r : runs) {
      const RunSummaryFile::DeviceFigures* f = find_in(r.summary.devices, d);
      const bool t = f && f->revolute_deg, s = f && f->prismatic_m;  // runs before per-kind totals have none
      path.values.push_back(f ? number(f->tool_path_length, 3) : "");
      turned.values.push_back(t ? number(*f->revolute_deg, 1) : "");
      slid.values.push_back(s ? number(*f->prismatic_m, 3) : "");
      any_turned = any_turned || t;
      any_slid = any_slid || s;
    }
    out.push_back(std::move(path));
    if (any_turned) out.push_back(std::move(turned));
    if (any_slid) out.push_back(std::move(slid));
  }
  // Collisions first among the events: they are what a reviewer looks for.
  std::vector<std::string> order(kinds.begin(), kinds.end());
  std::stable_partition(order.begin(), order.end(), [](const std::string& k) { return k == "collision"; });
  if (!kinds.count("collision")) order.insert(order.begin(), "collision");
  for (const std::string& k : order) {
    CompareRow m{k + " events", "", {}};
    for (const RunRecord& r : runs) {
      const size_t* n = find_in(r.summary.events, k);
      m.values.push_back(fmt::format("{}", n ? *n : 0));
    }
    out.push_back(std::move(m));
  }
  return out;
}

}  // namespace

Expected<std::vector<RunRecord>> read_runs(const std::vector<std::string>& paths) {
  std::vector<RunRecord> runs;
  for (const std::string& p : paths) {
    std::error_code ec;
    std::optional<std::string> text;
    std::string where;
    if (fs::is_regular_file(p, ec) && fs::path(p).extension() == ".zip") {
      where = p + ":summary.json";
      Expected<std::string> entry = read_zip_entry(p, "summary.json");
      if (!entry) return Unexpected{entry.error()};
      text = std::move(*entry);
    } else {
      where = (fs::path(p) / "summary.json").string();
      if (!(text = read_file_bytes(where))) {
        return Unexpected{fmt::format("{}: not a run folder or bundle (expected {})", p, where)};
      }
    }
    std::string why;
    auto summary = RunSummaryFile::parse(*text, why);
    if (!summary) {
      return Unexpected{fmt::format("{}: not a summary written by sscs simulate ({})", where, why)};
    }
    runs.push_back({p, std::move(*summary)});
  }
  return runs;
}

std::string compare_text(const std::vector<RunRecord>& runs) {
  std::vector<CompareRow> ms = metrics(runs, Digits::Rounded);
  std::vector<std::string> head = {""};
  for (const RunRecord& r : runs) head.push_back(r.path);
  std::vector<size_t> width(head.size(), 0);
  auto label = [](const CompareRow& m) { return m.unit.empty() ? m.name : fmt::format("{} ({})", m.name, m.unit); };
  for (size_t c = 0; c < head.size(); ++c) width[c] = head[c].size();
  for (const CompareRow& m : ms) {
    width[0] = std::max(width[0], label(m).size());
    for (size_t c = 0; c < m.values.size(); ++c) width[c + 1] = std::max(width[c + 1], m.values[c].size());
  }
  std::string out;
  auto row = [&](const std::vector<std::string>& cells) {
    std::string line = fmt::format("{:<{}}", cells[0], width[0]);
    for (size_t c = 1; c < cells.size(); ++c) line += fmt::format("  {:>{}}", cells[c], width[c]);
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out += line + "\n";
  };
  row(head);
  for (const CompareRow& m : ms) {
    std::vector<std::string> cells = {label(m)};
    cells.insert(cells.end(), m.values.begin(), m.values.end());
    row(cells);
  }
  return out;
}

std::string compare_json(const std::vector<RunRecord>& runs) {
  nlohmann::ordered_json j;
  j["sscs"] = 1;
  auto arr = nlohmann::ordered_json::array();
  for (const RunRecord& r : runs) {
    nlohmann::ordered_json e;
    e["run"] = r.path;
    const nlohmann::ordered_json whole = r.summary.to_json();
    for (const char* k : {"scenario", "vault", "status", "cycle_time", "min_clearance", "devices", "events", "campaign"})
      if (whole.contains(k)) e[k] = whole[k];
    arr.push_back(std::move(e));
  }
  j["runs"] = std::move(arr);
  return j.dump(2) + "\n";
}

std::string compare_csv(const std::vector<RunRecord>& runs) {
  std::vector<CompareRow> ms = metrics(runs, Digits::Full);
  std::vector<std::string> head = {"run"};
  for (const CompareRow& m : ms) head.push_back(m.unit.empty() ? m.name : fmt::format("{} ({})", m.name, m.unit));
  std::string out;
  for (size_t c = 0; c < head.size(); ++c) out += (c ? "," : "") + csv_field(head[c]);
  out += "\n";
  for (size_t r = 0; r < runs.size(); ++r) {
    out += csv_field(runs[r].path);
    for (const CompareRow& m : ms) out += "," + csv_field(m.values[r]);
    out += "\n";
  }
  return out;
}

}  // namespace sscs
