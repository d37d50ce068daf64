// The comparison with a baseline report: what a change broke, fixed, or left as it was.
#include <algorithm>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/digest.h"
#include "report/report.h"

namespace sscs {

const char* change_name(Change c) {
  switch (c) {
    case Change::New: return "new";
    case Change::StillFailing: return "still_failing";
    case Change::Fixed: return "fixed";
    case Change::Unchanged: break;
  }
  return "unchanged";
}

namespace {

/// "line:col" of byte `offset` in `text` (1-based).
std::string line_col(const std::string& text, size_t offset) {
  size_t line = 1, col = 1;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') ++line, col = 1;
    else ++col;
  }
  return fmt::format("{}:{}", line, col);
}

/// The results of one vault report object; throws std::runtime_error saying what is wrong.
std::vector<BaselineResult> results_of(const nlohmann::json& vault) {
  auto str = [](const nlohmann::json& j, const char* key, bool required) -> std::string {
    auto it = j.find(key);
    if (it == j.end() || it->is_null()) {
      if (required) throw std::runtime_error(fmt::format("a result has no \"{}\"", key));
      return "";
    }
    if (!it->is_string()) throw std::runtime_error(fmt::format("\"{}\" of a result is not a string", key));
    return it->get<std::string>();
  };
  auto it = vault.find("results");
  if (it == vault.end() || !it->is_array()) throw std::runtime_error("a vault report has no \"results\" array");
  std::vector<BaselineResult> out;
  for (const nlohmann::json& r : *it) {
    if (!r.is_object()) throw std::runtime_error("a result is not an object");
    BaselineResult b;
    b.constraint = str(r, "constraint", true);
    b.status = str(r, "status", true);
    if (b.status != "pass" && b.status != "fail" && b.status != "error")
      throw std::runtime_error(fmt::format("result status '{}' is none of pass, fail, error", b.status));
    b.kind = str(r, "kind", false);
    b.message = str(r, "message", false);
    auto s = r.find("subject");
    if (s != r.end() && !s->is_array()) throw std::runtime_error("\"subject\" of a result is not an array");
    if (s != r.end())
      for (const nlohmann::json& name : *s) {
        if (!name.is_string()) throw std::runtime_error("\"subject\" of a result holds something that is not a name");
        b.subject.push_back(name.get<std::string>());
      }
    out.push_back(std::move(b));
  }
  return out;
}

std::string key_of(const std::string& constraint, const std::vector<std::string>& subject) {
  return fmt::format("{}\x1f{}", constraint, fmt::join(subject, "\x1e"));
}

}  // namespace

Expected<Baseline> read_baseline(const std::string& path) {
  auto text = read_file_bytes(path);
  if (!text) return Unexpected{fmt::format("cannot read the baseline report '{}'", path)};
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(*text);
  } catch (const nlohmann::json::parse_error& e) {
    std::string what = e.what();
    what = what.substr(what.find("syntax error"));
    return Unexpected{fmt::format("{}:{}: the baseline is not JSON (expected a report of sscs check --format json): {}", path,
                                  line_col(*text, e.byte > 0 ? e.byte - 1 : 0), what)};
  }
  Baseline b;
  b.file = path;
  try {
    if (!j.is_object() || j.value("sscs", 0) != 1)
      throw std::runtime_error("expected a report of sscs check --format json (an object with \"sscs\": 1)");
    std::vector<const nlohmann::json*> vaults;
    if (j.contains("reports")) {
      if (!j["reports"].is_array()) throw std::runtime_error("\"reports\" is not an array");
      for (const nlohmann::json& v : j["reports"]) vaults.push_back(&v);
    } else {
      vaults.push_back(&j);
    }
    for (const nlohmann::json* v : vaults) {
      if (!v->is_object() || !v->contains("vault") || !(*v)["vault"].is_string())
        throw std::runtime_error("a vault report has no \"vault\" name");
      b.vaults[(*v)["vault"].get<std::string>()] = results_of(*v);
    }
  } catch (const std::exception& e) {
    return Unexpected{fmt::format("{}: not an sscs check report: {}", path, e.what())};
  }
  return b;
}

BaselineDiff compare_with_baseline(const Workcell& wc, const CheckReport& report, const Baseline& baseline) {
  BaselineDiff d;
  d.file = baseline.file;
  static const std::vector<BaselineResult> kNone;
  auto found = baseline.vaults.find(wc.name);
  d.vault_in_baseline = found != baseline.vaults.end();
  const std::vector<BaselineResult>& old = d.vault_in_baseline ? found->second : kNone;

  // Constraint names then and now; a name that went while another came with the same kind and
  // the same objects is a rename (when that pairing is unambiguous).
  std::map<std::string, std::pair<std::string, std::set<std::string>>> then;  // name -> (kind, subjects)
  for (const BaselineResult& r : old) {
    auto& [kind, subjects] = then[r.constraint];
    kind = r.kind;
    subjects.insert(r.subject.begin(), r.subject.end());
  }
  std::map<std::string, std::pair<std::string, std::set<std::string>>> now;
  for (const Constraint& c : wc.constraints) now[c.name].first = c.kind;
  for (const CheckResult& r : report.results)
    for (int s : r.subjects) now[wc.constraints[r.constraint].name].second.insert(wc.objects[s].name);
  std::vector<std::string> gone, came;
  for (const auto& [name, sig] : then)
    if (!now.count(name)) gone.push_back(name);
  for (const auto& [name, sig] : now)
    if (!then.count(name)) came.push_back(name);
  std::map<std::string, std::string> alias;  // baseline name -> name now
  for (const auto& [name, sig] : then)
    if (now.count(name)) alias[name] = name;
  // Pairs of the same kind whose objects mostly agree (Jaccard >= 0.5), best first.
  auto jaccard = [](const std::set<std::string>& a, const std::set<std::string>& b) {
    if (a.empty() && b.empty()) return 1.0;
    size_t common = std::count_if(a.begin(), a.end(), [&](const std::string& x) { return b.count(x) > 0; });
    return static_cast<double>(common) / static_cast<double>(a.size() + b.size() - common);
  };
  std::vector<std::tuple<double, std::string, std::string>> pairs;
  for (const std::string& g : gone)
    for (const std::string& c : came)
      if (then[g].first == now[c].first)
        if (double score = jaccard(then[g].second, now[c].second); score >= 0.5) pairs.emplace_back(-score, g, c);
  std::sort(pairs.begin(), pairs.end());
  std::set<std::string> taken;
  for (const auto& [score, g, c] : pairs)
    if (!alias.count(g) && !taken.count(c)) {
      alias[g] = c;
      taken.insert(c);
      d.renamed.emplace_back(g, c);
    }
  std::sort(d.renamed.begin(), d.renamed.end());
  for (const std::string& g : gone) {
    if (alias.count(g)) continue;
    bool failing = std::any_of(old.begin(), old.end(), [&](const BaselineResult& r) { return r.constraint == g && r.status != "pass"; });
    d.removed.push_back({g, failing});
  }

  // Results matched by (constraint, subject).
  std::map<std::string, const BaselineResult*> old_failing;
  for (const BaselineResult& r : old)
    if (r.status != "pass" && alias.count(r.constraint)) old_failing[key_of(alias[r.constraint], r.subject)] = &r;
  std::set<std::string> matched;
  d.changes.resize(report.results.size(), Change::Unchanged);
  for (size_t i = 0; i < report.results.size(); ++i) {
    const CheckResult& r = report.results[i];
    if (r.status == Status::Pass) continue;
    std::vector<std::string> subject;
    for (int s : r.subjects) subject.push_back(wc.objects[s].name);
    std::string key = key_of(wc.constraints[r.constraint].name, subject);
    if (old_failing.count(key)) {
      d.changes[i] = Change::StillFailing;
      matched.insert(key);
      ++d.still_failing;
    } else {
      d.changes[i] = Change::New;
      ++d.new_failures;
      ++d.gating_new_strict;
      if (wc.constraints[r.constraint].severity == Severity::Error) ++d.gating_new;
    }
  }
  // Baseline failures without a failing counterpart: fixed, by a passing result of the same
  // constraint that covers their objects, or because their objects are no longer checked.
  for (const auto& [key, r] : old_failing) {
    if (matched.count(key)) continue;
    const std::string& name = alias[r->constraint];
    std::string why = "no longer checked";
    for (size_t i = 0; i < report.results.size(); ++i) {
      const CheckResult& cur = report.results[i];
      if (cur.status != Status::Pass || wc.constraints[cur.constraint].name != name) continue;
      std::set<std::string> covered;
      for (int s : cur.subjects) covered.insert(wc.objects[s].name);
      if (std::all_of(r->subject.begin(), r->subject.end(), [&](const std::string& s) { return covered.count(s) > 0; })) {
        d.changes[i] = Change::Fixed;
        why = "passes now";
        break;
      }
    }
    d.fixed.push_back({name, r->subject, r->message, why});
  }
  d.unchanged = std::count(d.changes.begin(), d.changes.end(), Change::Unchanged);
  return d;
}

std::string describe_fixed(const BaselineDiff::Gone& g) {
  return fmt::format("fixed: {}{}{}{} ({}; was: {})", g.constraint, g.subject.empty() ? "" : " [", fmt::join(g.subject, ", "),
                     g.subject.empty() ? "" : "]", g.why, g.message);
}

std::string baseline_lines(const BaselineDiff& d) {
  std::string out;
  for (const BaselineDiff::Gone& g : d.fixed) out += describe_fixed(g) + "\n";
  for (const auto& [from, to] : d.renamed) out += fmt::format("renamed: '{}' is now '{}'\n", from, to);
  for (const BaselineDiff::Removed& r : d.removed)
    out += fmt::format("removed: '{}' (it {} in the baseline)\n", r.constraint, r.was_failing ? "failed" : "passed");
  return out;
}

std::string baseline_summary(const BaselineDiff& d) {
  std::string s = fmt::format("{} new failure{}, {} fixed, {} still failing, {} unchanged", d.new_failures,
                              d.new_failures == 1 ? "" : "s", d.fixed.size(), d.still_failing, d.unchanged);
  if (!d.renamed.empty()) s += fmt::format(", {} renamed", d.renamed.size());
  if (!d.removed.empty()) s += fmt::format(", {} removed", d.removed.size());
  if (!d.vault_in_baseline) s += " (the baseline has no report of this vault)";
  return s;
}

}  // namespace sscs
