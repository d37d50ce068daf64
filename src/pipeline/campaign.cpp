#include "pipeline/campaign.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <random>

#include <fmt/format.h>

#include "compile/values.h"
#include "core/names.h"
#include "pipeline/scenario.h"

namespace sscs {

namespace {

std::string substitute(std::string text, const std::string& load, const std::string& device, const std::string& place) {
  for (const auto& [key, value] : {std::pair<const char*, const std::string*>{"{load}", &load}, {"{device}", &device},
                                   {"{slot}", &place}, {"{to}", &place}})
    for (size_t at = text.find(key); at != std::string::npos; at = text.find(key, at + value->size()))
      text.replace(at, std::string_view(key).size(), *value);
  return text;
}

std::string load_name(const std::string& pattern, long n) {
  std::string out = pattern;
  for (size_t at = out.find("{n}"); at != std::string::npos; at = out.find("{n}", at)) out.replace(at, 3, std::to_string(n));
  return out;
}

/// How many loads a stream brings: `count` (default 1, or as many as `times`).
long load_count(const LoadStreamSpec& l, Diagnostics* diag) {
  const long times = static_cast<long>(l.arrive.times.size());
  if (!l.count.present || l.count.null) return l.arrive.kind == ArrivalSpec::Kind::Times ? times : 1;
  const bool digits = !l.count.text.empty() && l.count.text.size() <= 6 &&
                      std::all_of(l.count.text.begin(), l.count.text.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
  const long n = digits ? std::stol(l.count.text) : -1;
  if (n < 1) {
    if (diag) diag->error(l.count.mark, fmt::format("count must be a whole number from 1 to 999999, found '{}'", l.count.text));
    return 0;
  }
  if (l.arrive.kind == ArrivalSpec::Kind::Times && n != times) {
    if (diag) diag->error(l.count.mark, fmt::format("count is {} but arrive lists {} times: one time a load", n, times));
    return 0;
  }
  return n;
}

class CampaignCompiler {
 public:
  CampaignCompiler(const CampaignSpec& spec, const Workcell& wc, const GeometryModel& geometry, Diagnostics& diag)
      : spec_(spec), wc_(wc), geometry_(geometry), diag_(diag) {}

  std::optional<CampaignCommands> run() {
    CampaignCommands c;
    c.settings = compile_settings(spec_, wc_, geometry_, diag_);
    c.seed = seed();
    arrivals(c);
    c.stop_on_failure = spec_.on_failure.present && spec_.on_failure.text == "stop";
    std::vector<std::vector<int>> selected;
    for (size_t ti = 0; ti < spec_.jobs.size(); ++ti) {
      const JobSpec& js = spec_.jobs[ti];
      c.templates.push_back(job_template(js));
      selected.push_back(each(js));
      const double after = js.after.present ? literal_si(js.after, Dim::Time, "after", diag_).value_or(0) : 0;
      if (after < 0) diag_.error(js.after.mark, fmt::format("after must not be negative, found {}", js.after.text));
      for (int o : selected.back()) c.jobs.push_back({ti, o, std::max(after, 0.0)});
    }
    // The queue's order: readiness, then the order of `jobs:`, then the object's name.
    std::stable_sort(c.jobs.begin(), c.jobs.end(), [&](const CampaignCommands::Job& a, const CampaignCommands::Job& b) {
      if (a.ready != b.ready) return a.ready < b.ready;
      if (a.job_template != b.job_template) return a.job_template < b.job_template;
      return natural_less(wc_.objects[a.object].name, wc_.objects[b.object].name);
    });
    if (!diag_.has_errors())
      for (size_t ti = 0; ti < c.templates.size(); ++ti) check_template(ti, c.templates[ti], selected[ti]);
    if (diag_.has_errors()) return std::nullopt;
    const CampaignSpec* spec = &spec_;
    const Workcell* wc = &wc_;
    const GeometryModel* geometry = &geometry_;
    c.steps = [spec, wc, geometry](const JobBinding& b, Diagnostics& diag) {
      const JobSpec& js = spec->jobs[b.job_template];
      const std::string place = b.place ? frame_text(*wc, *b.place) : "";
      std::vector<StepCommand> out;
      for (size_t k = 0; k < js.steps.size(); ++k)
        out.push_back(compile_step(expand_step(js.steps[k], wc->objects[b.object].name, wc->objects[b.device].name, place), k, *wc,
                                   *geometry, diag));
      return out;
    };
    return c;
  }

 private:
  uint64_t seed() {
    const Scalar& s = spec_.seed;
    if (!s.present || s.null) return 0;
    const bool digits = !s.text.empty() && s.text.size() <= 19 && std::all_of(s.text.begin(), s.text.end(), [](char ch) {
      return std::isdigit(static_cast<unsigned char>(ch));
    });
    if (!digits) {
      diag_.error(s.mark, fmt::format("sim.seed must be a whole number from 0 to 10^19 - 1, found '{}'", s.text));
      return 0;
    }
    return std::stoull(s.text);
  }

  /// When each load of `loads:` is due at its spot: every (from first), the times listed, or
  /// exponential gaps of the mean (from the seed: a generator of its own, so a change in the
  /// slot choices leaves the arrivals as they were).
  void arrivals(CampaignCommands& c) {
    std::mt19937_64 rng(c.seed ^ 0x9e3779b97f4a7c15ull);
    auto uniform = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };  // [0, 1), the same on any platform
    for (const LoadStreamSpec& l : spec_.loads) {
      const long n = load_count(l, nullptr);  // (its errors were reported with the vault's loads)
      std::optional<FrameRef> spot = l.at.present ? frame(l.at) : std::nullopt;
      if (!spot) continue;
      const ArrivalSpec& a = l.arrive;
      auto time = [&](const Scalar& v, const char* what, double fallback) {
        if (!v.present || v.null) return fallback;
        const double x = literal_si(v, Dim::Time, what, diag_).value_or(fallback);
        if (x < 0) diag_.error(v.mark, fmt::format("{} must not be negative, found {}", what, v.text));
        return std::max(x, 0.0);
      };
      const double every = a.kind == ArrivalSpec::Kind::Every ? time(a.every, "arrive every", 0) : 0;
      const double first = a.kind == ArrivalSpec::Kind::Every ? time(a.first, "arrive first", 0) : 0;
      const double mean = a.kind == ArrivalSpec::Kind::Random ? time(a.mean, "arrive random mean", 0) : 0;
      if (a.kind == ArrivalSpec::Kind::Random && !(mean > 0)) diag_.error(a.mean.mark, "arrive random mean must be positive");
      double t = 0;
      for (long k = 1; k <= n; ++k) {
        switch (a.kind) {
          case ArrivalSpec::Kind::Every: t = first + (k - 1) * every; break;
          case ArrivalSpec::Kind::Times:
            t = time(a.times[k - 1], "an arrival time", 0);
            break;
          case ArrivalSpec::Kind::Random: t += -mean * std::log1p(-uniform()); break;
        }
        const int o = wc_.find_object(load_name(l.name.text, k));
        if (o >= 0) c.arrivals.push_back({o, t, *spot});
      }
    }
  }

  std::vector<std::string> names_of(bool devices_only) const {
    std::vector<std::string> names;
    for (size_t o = 0; o < wc_.objects.size(); ++o)
      if (!devices_only || geometry_.objects[o].device) names.push_back(wc_.objects[o].name);
    return names;
  }

  int object(const Scalar& s, std::string_view what, bool device) {
    const int o = wc_.find_object(s.text);
    if (o < 0) {
      diag_.error(s.mark, fmt::format("unknown {} '{}'{}", what, s.text, did_you_mean(s.text, names_of(device))));
      return -1;
    }
    if (device && !geometry_.objects[o].device) {
      diag_.error(s.mark, fmt::format("'{}' is a {}, not a device", s.text, wc_.types[wc_.objects[o].type].name));
      return -1;
    }
    return o;
  }

  JobTemplate job_template(const JobSpec& js) {
    JobTemplate t;
    t.name = js.name;
    t.mark = js.mark;
    for (const Scalar& d : js.devices)
      if (int o = object(d, "device", true); o >= 0 && std::find(t.devices.begin(), t.devices.end(), o) == t.devices.end())
        t.devices.push_back(o);
    if (js.slot) {
      t.slots = slot_frames(js.slot->from);
      const std::string& choose = js.slot->choose.present ? js.slot->choose.text : "nearest";
      t.choose = choose == "first" ? SlotChoice::First : choose == "lowest" ? SlotChoice::Lowest
                 : choose == "random" ? SlotChoice::Random : SlotChoice::Nearest;
    }
    if (js.to.present && !js.to.null) t.to = frame(js.to);
    for (const Scalar& z : js.claims)
      if (int o = object(z, "claim (a zone or object of the vault)", false); o >= 0) t.claims.push_back(o);
    for (const StepSpec& step : js.steps)
      if (std::holds_alternative<ParallelSpec>(step.action))
        diag_.error(step.mark, "a job's steps run on its device one after another: a parallel group cannot be one of them");
    return t;
  }

  /// The objects a job's `each:` selects (an error when none).
  std::vector<int> each(const JobSpec& js) {
    if (!js.each.present || js.each.null) return {};
    std::optional<std::vector<int>> sel = wc_.select(js.each.text);
    if (!sel) {
      diag_.error(js.each.mark, fmt::format("each: '{}' names no object or type of the vault{}", js.each.text,
                                            did_you_mean(js.each.text, names_of(false))));
      return {};
    }
    if (sel->empty()) diag_.error(js.each.mark, fmt::format("each: '{}' selects no object of the vault", js.each.text));
    return *sel;
  }

  /// `OBJECTS.FRAMES` (globs both; OBJECTS a selector, `[Row_1, Row_3]` too) of `slot.from`, or a
  /// list of those (`[PlA.spot_*, PlB.spot_1]`), in natural order of their names.
  std::vector<FrameRef> slot_frames(const Scalar& from) {
    std::vector<FrameRef> out;
    const bool list = from.text.starts_with('[') && from.text.ends_with(']');
    std::vector<std::string_view> items = list ? split_selector_list(from.text) : std::vector<std::string_view>{from.text};
    std::optional<std::vector<int>> sel;
    for (std::string_view item : items) {
      const size_t dot = item.rfind('.');
      if (dot == std::string::npos || item.starts_with('!')) {
        diag_.error(from.mark, fmt::format("slot from '{}' must name frames: OBJECTS.FRAMES (`Row_*.top_*`, `[Row_1, Row_3].top_*`) "
                                           "or a list of those (`[Row_1.top_*, Dock.top]`){}",
                                           from.text, list ? fmt::format(", found '{}' in the list", item) : ""));
        return {};
      }
      const std::string objects(item.substr(0, dot)), frames(item.substr(dot + 1));
      std::optional<std::vector<int>> found = wc_.select(objects);
      const size_t before = out.size();
      if (found)
        for (int o : *found)
          for (const std::string& f : wc_.frame_names(o))
            if (glob_match(frames, f)) out.push_back({o, f});
      if (list && out.size() == before) {  // a name of the list that is no frame: a typo, not a smaller list
        diag_.error(from.mark, fmt::format("slot from '{}': '{}' matches no frame of the vault{}", from.text, item,
                                           found && !found->empty() ? fmt::format(" ({} has the frames {})", wc_.objects[found->front()].name,
                                                                                  name_list(wc_.frame_names(found->front()), 8))
                                                                    : ""));
        return {};
      }
      if (!sel && found) sel = found;
    }
    std::sort(out.begin(), out.end(), [](const FrameRef& a, const FrameRef& b) { return std::tie(a.object, a.frame) < std::tie(b.object, b.frame); });
    out.erase(std::unique(out.begin(), out.end(), [](const FrameRef& a, const FrameRef& b) { return a.object == b.object && a.frame == b.frame; }),
              out.end());
    if (out.empty()) {
      diag_.error(from.mark, fmt::format("slot from '{}' matches no frame of the vault{}", from.text,
                                         sel && !sel->empty() ? fmt::format(" ({} has the frames {})", wc_.objects[sel->front()].name,
                                                                            name_list(wc_.frame_names(sel->front()), 8))
                                                              : ""));
      return out;
    }
    std::stable_sort(out.begin(), out.end(), [&](const FrameRef& a, const FrameRef& b) {
      return natural_less(frame_text(wc_, a), frame_text(wc_, b));
    });
    return out;
  }

  /// `OBJECT.FRAME` (or `OBJECT`: its origin) of `to:`.
  std::optional<FrameRef> frame(const Scalar& s) {
    const size_t dot = s.text.rfind('.');
    Scalar obj = s;
    if (dot != std::string::npos) obj.text = s.text.substr(0, dot);
    const int o = object(obj, "object for to", false);
    if (o < 0) return std::nullopt;
    const std::string f = dot == std::string::npos ? "origin" : s.text.substr(dot + 1);
    const std::vector<std::string> names = wc_.frame_names(o);
    if (std::find(names.begin(), names.end(), f) == names.end()) {
      diag_.error(s.mark, fmt::format("'{}' is not a frame of {}; its frames: {}{}", f, obj.text, name_list(names), did_you_mean(f, names)));
      return std::nullopt;
    }
    return FrameRef{o, f};
  }

  /// The template's steps compile for each object it goes over (its first device, its first
  /// slot): the errors of the first object they do not compile for, named with it.
  void check_template(size_t ti, const JobTemplate& t, const std::vector<int>& objects) {
    if (t.devices.empty()) return;
    const JobSpec& js = spec_.jobs[ti];
    const std::string device = wc_.objects[t.devices.front()].name;
    const std::string place = !t.slots.empty() ? frame_text(wc_, t.slots.front()) : t.to ? frame_text(wc_, *t.to) : "";
    std::vector<Diagnostic> first;
    int first_object = -1;
    size_t failing = 0;
    for (int o : objects) {
      Diagnostics local;
      for (size_t k = 0; k < js.steps.size(); ++k)
        compile_step(expand_step(js.steps[k], wc_.objects[o].name, device, place), k, wc_, geometry_, local);
      if (!local.has_errors()) continue;
      if (++failing == 1) {
        first = local.errors();
        first_object = o;
      }
    }
    for (const Diagnostic& e : first)
      diag_.error(e.mark, fmt::format("{} (job '{}' for {}{})", e.message, t.name, wc_.objects[first_object].name,
                                      objects.size() > 1 ? fmt::format("; it fails for {} of its {} objects", failing, objects.size()) : ""));
  }

  const CampaignSpec& spec_;
  const Workcell& wc_;
  const GeometryModel& geometry_;
  Diagnostics& diag_;
};

}  // namespace

void add_arriving_loads(const CampaignSpec& spec, VaultSpec& vault, Diagnostics& diag) {
  for (const LoadStreamSpec& l : spec.loads) {
    const long n = load_count(l, &diag);
    if (!l.name.present || l.name.null || !l.type.present || !l.at.present) continue;
    for (long k = 1; k <= n; ++k) {
      ObjectSpec o;
      o.mark = l.mark;
      o.type = l.type.text;
      o.type_mark = l.type.mark;
      o.name = l.name;
      o.name.text = load_name(l.name.text, k);
      o.at = l.at;
      for (size_t a = 0; a < l.attributes.size(); ++a)
        o.attributes.push_back({l.attributes[a].first, l.attribute_marks[a], l.attributes[a].second});
      vault.objects.push_back(std::move(o));
    }
  }
}

StepSpec expand_step(const StepSpec& step, const std::string& load, const std::string& device, const std::string& place) {
  StepSpec out = step;
  auto expand = [&](Scalar& s) {
    if (s.present && !s.null) s.text = substitute(s.text, load, device, place);
  };
  const bool has_device = !std::holds_alternative<WaitSpec>(step.action) && !std::holds_alternative<ParallelSpec>(step.action);
  if (has_device && !out.device.present) {
    out.device.text = device;
    out.device.present = true;
    out.device.mark = step.mark;
  }
  expand(out.device);
  std::visit(
      [&](auto& a) {
        using A = std::decay_t<decltype(a)>;
        if constexpr (std::is_same_v<A, MoveToSpec>) expand(a.target.ref);
        else if constexpr (std::is_same_v<A, GraspSpec> || std::is_same_v<A, ReleaseSpec>) expand(a.object);
      },
      out.action);
  return out;
}

std::optional<CampaignCommands> compile_campaign(const CampaignSpec& spec, const Workcell& wc, const GeometryModel& geometry,
                                                 Diagnostics& diag) {
  return CampaignCompiler(spec, wc, geometry, diag).run();
}

}  // namespace sscs
