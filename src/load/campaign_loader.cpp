// Campaign files: `sscs: 1`, `campaign: NAME`, the run settings of a scenario, loads, jobs,
// on_failure (campaign-format.md).
#include <set>

#include <fmt/format.h>

#include "core/files.h"
#include "core/names.h"
#include "core/yaml_tree.h"
#include "load/campaign.h"
#include "load/load.h"
#include "load/reader.h"
#include "load/run_file.h"

namespace sscs {

using load::MapReader;

namespace {

const std::vector<std::string> kChoices = {"nearest", "first", "lowest", "random"};
const std::vector<std::string> kOnFailure = {"continue", "stop"};

/// Words users write for a slot choice, by meaning (`closest` was taken for `lowest`, the nearer
/// spelling).
const std::vector<std::pair<std::string, std::string>> kChoiceSynonyms = {
    {"closest", "nearest"}, {"near", "nearest"}, {"shortest", "nearest"}, {"bottom", "lowest"}, {"low", "lowest"},
    {"any", "random"}, {"shuffle", "random"}, {"next", "first"}, {"in_order", "first"}, {"order", "first"}};

/// A word of `words`, or an error at the scalar naming them (with a suggestion: by meaning when
/// `synonyms` has the word, else by spelling).
void one_of(const Scalar& s, const std::vector<std::string>& words, std::string_view what, Diagnostics& diag,
            const std::vector<std::pair<std::string, std::string>>& synonyms = {}) {
  if (!s.present || s.null) return;
  if (std::find(words.begin(), words.end(), s.text) != words.end()) return;
  std::string hint = did_you_mean(s.text, words);
  for (const auto& [word, meant] : synonyms)
    if (word == s.text) hint = fmt::format(" (did you mean '{}'?)", meant);
  diag.error(s.mark, fmt::format("unknown {} '{}'; expected one of {}{}", what, s.text, fmt::join(words, ", "), hint));
}

/// The `{word}`s of `text`, in order.
std::vector<std::string> placeholders(std::string_view text) {
  std::vector<std::string> out;
  for (size_t open = text.find('{'); open != std::string_view::npos; open = text.find('{', open + 1)) {
    const size_t close = text.find('}', open);
    if (close == std::string_view::npos) break;
    out.emplace_back(text.substr(open + 1, close - open - 1));
  }
  return out;
}

ArrivalSpec read_arrival(yaml::Node node, Diagnostics& diag) {
  ArrivalSpec a;
  a.mark = node.mark();
  MapReader r(node, "arrive", diag);
  if (!r.ok()) return a;
  yaml::Node every = r.take("every"), times = r.take("times"), random = r.take("random"), first = r.take("first");
  const int kinds = every.valid() + times.valid() + random.valid();
  if (kinds != 1)
    diag.error(a.mark, kinds == 0 ? "arrive needs one of every, times or random"
                                  : "arrive takes one of every, times or random, not several");
  if (every.valid()) {
    a.kind = ArrivalSpec::Kind::Every;
    a.every = load::scalar(every, "arrive every", diag);
    a.first = load::scalar(first, "arrive first", diag);
  } else if (first.valid()) {
    diag.error(first.mark(), "'first' applies to arrive: {every: ...}");
  }
  if (times.valid()) {
    a.kind = ArrivalSpec::Kind::Times;
    if (!times.is_sequence() || times.size() == 0) load::expected(diag, times, "a non-empty sequence of times", "arrive times");
    else a.times = load::scalar_list(times, "an arrival time", diag);
  }
  if (random.valid()) {
    a.kind = ArrivalSpec::Kind::Random;
    MapReader m(random, "arrive random", diag);
    a.mean = load::scalar(m.require("mean"), "arrive random mean", diag);
    if (m.ok()) m.finish();
  }
  r.finish();
  return a;
}

LoadStreamSpec read_loads(yaml::Node node, Diagnostics& diag) {
  LoadStreamSpec l;
  l.mark = node.mark();
  MapReader r(node, "load stream", diag);
  if (!r.ok()) return l;
  l.name = load::scalar(r.require("name"), "load name", diag);
  if (l.name.present && !l.name.null) {
    bool counted = true;
    for (const std::string& p : placeholders(l.name.text))
      if (p != "n") {
        diag.error(l.name.mark, fmt::format("unknown placeholder '{{{}}}' in a load's name; a load's name counts with {{n}}", p));
        counted = false;
      }
    std::string example;  // the first name: {n} is 1
    for (size_t k = 0; k < l.name.text.size(); ++k) {
      if (l.name.text.compare(k, 3, "{n}") == 0) {
        example += '1';
        k += 2;
      } else {
        example += l.name.text[k];
      }
    }
    if (counted && !is_valid_name(example))
      diag.error(l.name.mark, fmt::format("a load's name '{}' must give names (letter first, then letters, digits, _ or -; "
                                          "{{n}} counts from 1), found '{}'", l.name.text, example));
  }
  l.type = load::scalar(r.require("type"), "load type", diag);
  l.count = load::scalar(r.take("count"), "load count", diag);
  l.at = load::scalar(r.require("at"), "load at", diag);
  MapReader attrs(r.take("attributes"), "attributes", diag);
  for (auto& [k, v] : attrs.rest()) {
    l.attributes.emplace_back(load::name(k, "an attribute", diag), load::scalar(v, "an attribute value", diag));
    l.attribute_marks.push_back(k.mark());
  }
  yaml::Node arrive = r.require("arrive");
  if (arrive.valid()) l.arrive = read_arrival(arrive, diag);
  // (A name with some other placeholder was reported above: no second error about it.)
  if (l.count.present && !l.count.null && l.name.present && l.name.text.find('{') == std::string::npos && l.count.text != "1")
    diag.error(l.name.mark, fmt::format("a stream of {} loads names each with {{n}} (`{}_{{n}}`): '{}' would name them all alike",
                                        l.count.text, l.name.text, l.name.text));
  r.finish();
  return l;
}

/// Every placeholder of the job's steps is one the job defines: {load}, {device}, {slot} with
/// `slot:`, {to} with `to:`.
void check_placeholders(const JobSpec& job, const std::vector<StepSpec>& steps, Diagnostics& diag) {
  const std::vector<std::string> known(std::begin(kJobPlaceholders), std::end(kJobPlaceholders));
  auto check = [&](const Scalar& s) {
    if (!s.present || s.null) return;
    for (const std::string& p : placeholders(s.text)) {
      if (std::find(known.begin(), known.end(), p) == known.end())
        diag.error(s.mark, fmt::format("unknown placeholder '{{{}}}'; a job's steps may use {{load}}, {{slot}}, {{to}} and "
                                       "{{device}}{}", p, did_you_mean(p, known)));
      else if (p == "slot" && !job.slot)
        diag.error(s.mark, fmt::format("'{{slot}}' is not defined: job '{}' has no 'slot:'", job.name));
      else if (p == "to" && !job.to.present)
        diag.error(s.mark, fmt::format("'{{to}}' is not defined: job '{}' has no 'to:'", job.name));
      else if ((p == "slot" || p == "to") && s.text.find(fmt::format("{{{}}}.", p)) != std::string::npos)
        diag.error(s.mark, fmt::format("'{{{0}}}' is a frame already (OBJECT.FRAME): '{1}' names a frame of a frame; write "
                                       "'{{{0}}}' and move from it with an offset", p, s.text));
    }
  };
  for (const StepSpec& s : steps) {
    check(s.device);
    std::visit(
        [&](const auto& a) {
          using A = std::decay_t<decltype(a)>;
          if constexpr (std::is_same_v<A, MoveToSpec>) check(a.target.ref);
          else if constexpr (std::is_same_v<A, GraspSpec> || std::is_same_v<A, ReleaseSpec>) check(a.object);
          else if constexpr (std::is_same_v<A, ParallelSpec>) check_placeholders(job, a.steps, diag);
        },
        s.action);
  }
}

JobSpec read_job(yaml::Node node, Diagnostics& diag) {
  JobSpec j;
  j.mark = node.mark();
  MapReader r(node, "job", diag);
  if (!r.ok()) return j;
  j.name = load::name(r.require("name"), "a job", diag);
  j.each = load::scalar(r.require("each"), "each", diag);
  j.after = load::scalar(r.take("after"), "after", diag);
  yaml::Node devices = r.require("devices");
  if (devices.valid()) {
    if (devices.is_sequence() && devices.size() == 0) load::expected(diag, devices, "a non-empty list of devices", "devices");
    else j.devices = load::scalar_list(devices, "a device", diag);
  }
  yaml::Node slot = r.take("slot");
  if (slot.valid()) {
    SlotSpec s;
    s.mark = slot.mark();
    MapReader m(slot, "slot", diag);
    // A YAML list of frame globs is the list selector `[A.x_*, B.y]` written out.
    if (yaml::Node from = m.require("from"); from.valid() && from.is_sequence()) {
      std::vector<std::string> items;
      for (const Scalar& item : load::scalar_list(from, "a frame glob of slot from", diag)) items.push_back(item.text);
      s.from.text = fmt::format("[{}]", fmt::join(items, ", "));
      s.from.mark = from.mark();
      s.from.present = true;
    } else {
      s.from = load::scalar(from, "slot from", diag);
    }
    s.choose = load::scalar(m.take("choose"), "slot choose", diag);
    one_of(s.choose, kChoices, "slot choice", diag, kChoiceSynonyms);
    if (m.ok()) m.finish();
    j.slot = std::move(s);
  }
  j.to = load::scalar(r.take("to"), "to", diag);
  if (j.slot && j.to.present) diag.error(j.to.mark, fmt::format("job '{}' has both 'slot:' and 'to:'; a job goes to one", j.name));
  yaml::Node claims = r.take("claims");
  if (claims.valid()) j.claims = load::scalar_list(claims, "a claim", diag);
  j.steps = load::read_steps(r.require("steps"), diag, true);
  r.finish();
  check_placeholders(j, j.steps, diag);
  return j;
}

}  // namespace

std::optional<CampaignSpec> load_campaign(const std::string& path, Sources& sources, Diagnostics& diag) {
  uint32_t file = read_source(path, sources, diag);
  if (file == 0) return std::nullopt;
  return load_campaign(file, sources, diag);
}

std::optional<CampaignSpec> load_campaign(uint32_t file, Sources& sources, Diagnostics& diag) {
  yaml::Document doc = yaml::parse(sources, file, diag);
  if (doc.empty()) return std::nullopt;
  MapReader root(doc.root(), "a campaign file", diag);
  if (!root.ok()) return std::nullopt;
  load::check_version(root, diag);
  CampaignSpec c;
  c.path = sources.path(file);
  yaml::Node name = root.require("campaign");
  c.name = load::name(name, "the campaign", diag);
  c.mark = name.valid() ? name.mark() : root.mark();
  load::read_run_file(root, c, diag, true);
  yaml::Node loads = root.take("loads");
  if (loads.valid() && !loads.is_sequence()) load::expected(diag, loads, "a sequence of load streams", "loads");
  else if (loads.valid())
    for (size_t i = 0; i < loads.size() && !diag.full(); ++i) c.loads.push_back(read_loads(loads.item(i), diag));
  yaml::Node jobs = root.require("jobs");
  if (jobs.valid() && (!jobs.is_sequence() || jobs.size() == 0)) {
    load::expected(diag, jobs, "a non-empty sequence of jobs", "jobs");
  } else if (jobs.valid()) {
    std::set<std::string> names;
    for (size_t i = 0; i < jobs.size() && !diag.full(); ++i) {
      JobSpec j = read_job(jobs.item(i), diag);
      if (!j.name.empty() && !names.insert(j.name).second) diag.error(j.mark, fmt::format("duplicate job name '{}'", j.name));
      c.jobs.push_back(std::move(j));
    }
  }
  c.on_failure = load::scalar(root.take("on_failure"), "on_failure", diag);
  one_of(c.on_failure, kOnFailure, "on_failure", diag);
  root.finish();
  return c;
}

}  // namespace sscs
