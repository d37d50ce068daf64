#include "sweep/sweep.h"

#include "core/limits.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>
#include <tuple>

#include <fmt/format.h>

#include "check/check.h"
#include "core/data_dirs.h"
#include "core/digest.h"
#include "core/files.h"
#include "core/names.h"
#include "geometry/collision.h"
#include "geometry/geometry.h"
#include "geometry/mesh_io.h"
#include "load/load.h"
#include "load/campaign.h"
#include "load/scenario.h"
#include "load/sweep.h"
#include "pipeline/prepare.h"
#include "report/report.h"
#include "pipeline/campaign.h"
#include "pipeline/scenario.h"
#include "pipeline/resolved.h"
#include "simulate/simulate.h"
#include "sweep/dealer.h"
#include "sweep/metrics.h"
#include "sweep/results.h"
#include "sweep/variants.h"

namespace fs = std::filesystem;

namespace sscs {

namespace {

using Overrides = std::vector<std::pair<std::string, std::string>>;

/// A distinct vault (and scenario) that variants run: its spec, its compiled library and the
/// overrides every variant of it starts from (the scenario's `set:`, then --set).
struct Case {
  std::string vault_path, scenario_path;
  std::string library_dir;  ///< a varied `library` folder ("" for none)
  const VaultSpec* vault = nullptr;  ///< a campaign's: with its arriving loads
  const VaultSpec* checked = nullptr;  ///< the vault as written: what the check judges (a campaign's loads are not there yet)
  const ScenarioSpec* scenario = nullptr;  ///< a campaign's: its run settings
  const CampaignSpec* campaign = nullptr;
  std::shared_ptr<const std::vector<ObjectType>> library;
  std::shared_ptr<PluginSet> plugins;
  Overrides overrides;
  /// The files of the study's sources this case reads: its scenario, its vault, and the type
  /// library (and URDFs, SRDFs) its first compile read (`library_files`, shared with the cases
  /// that reuse that library). A run's summary lists these as its inputs, not the study's.
  std::vector<uint32_t> files, library_files;
};

std::string first_line(const std::string& text) {
  std::string line = text.substr(0, text.find('\n'));
  return line;
}

/// The last non-empty line a variant's process wrote (its log), without sscs's "error:" prefix.
std::string last_line(const std::string& log) {
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  for (const char* prefix : {"sscs: error: ", "sscs: internal error: "})
    if (last.starts_with(prefix)) last = last.substr(std::strlen(prefix));
  return last;
}

/// Everything a variant needs, prepared once in the parent; children are forked from it and
/// so share it without reading a file again.
class Study {
 public:
  Study(const SweepOptions& options, Sources& sources, Diagnostics& diag) : options_(options), sources_(sources), diag_(diag) {}

  bool prepare(const std::string& path);
  SweepOutcome run();

 private:
  int axis_named(std::string_view name) const {
    for (size_t a = 0; a < set_.axes.size(); ++a)
      if (set_.axes[a].spec->name == name) return static_cast<int>(a);
    return -1;
  }
  template <class Spec, class Load>
  const Spec* parsed(std::map<std::string, Spec>& cache, const std::string& path, SourceMark where, std::string_view what,
                     Load load);
  const VaultSpec* vault_file(const std::string& path, SourceMark where);
  const ScenarioSpec* scenario_file(const std::string& path, SourceMark where);
  bool prepare_case(Case& c);
  void validate_axes(const Workcell& wc, const Case& c);
  void validate_axis_values(const Workcell& wc, const std::vector<Axis>& axes);
  /// Every varied parameter exists in the vault, and every metric names what the vault has.
  void validate_names(const Workcell& wc, const std::string& vault_path, bool simulated, bool campaign);
  /// The case's run planned: its scenario's steps, or its campaign dispatched.
  static std::optional<Plan> plan_run(const Case& c, const Workcell& wc, const GeometryModel& geometry, Diagnostics& diag) {
    if (!c.campaign) return plan_scenario(*c.scenario, wc, geometry, diag);
    auto commands = compile_campaign(*c.campaign, wc, geometry, diag);
    return commands ? plan_campaign(*commands, wc, geometry, diag) : std::nullopt;
  }
  void report_with_vault(const std::vector<Axis>& axes);
  VariantRow evaluate(const Variant& v, const std::string& dir);
  VariantRow base_row(const Variant& v) const;
  void run_variant(const Variant& v, const std::string& tmp);
  std::string commit_variant(const Variant& v);
  rlim_t memory_limit_ = 0;  ///< RLIMIT_AS of each worker, bytes
  [[noreturn]] void worker(int tasks, int done);
  std::string dir(const Variant& v) const { return out_ + "/" + set_.folder(v); }
  /// Where a variant's folder is written before it is renamed into place.
  std::string tmp_dir(const Variant& v) const { return fmt::format("{}/.{}.tmp-{}", out_, set_.folder(v), parent_pid_); }

  const SweepOptions& options_;
  Sources& sources_;
  Diagnostics& diag_;
  SweepSpec spec_;
  VariantSet set_;
  std::vector<Metric> metrics_;
  std::map<std::string, VaultSpec> vaults_;
  std::map<std::string, ScenarioSpec> scenarios_;
  std::map<std::string, CampaignSpec> campaigns_;  ///< the run files that are campaigns (their settings in scenarios_)
  std::map<std::pair<std::string, std::string>, VaultSpec> campaign_vaults_;  ///< (vault, campaign): with its loads
  std::vector<Case> cases_;
  std::vector<size_t> case_of_;  ///< per variant
  MeshCache meshes_;
  /// The costly collision answers of the variants a worker has checked: a pair of shapes the
  /// variant did not move (a rack row the aisle width leaves in place) is not measured again.
  std::shared_ptr<ContactMemo> contacts_ = std::make_shared<ContactMemo>();
  TableHeader header_;
  Manifest manifest_;
  std::string out_;
  pid_t parent_pid_ = getpid();
};

/// The spec of the file at `path`, parsed once: `what` ("vault", "scenario") names it in the
/// message when it does not exist, reported at `where`.
template <class Spec, class Load>
const Spec* Study::parsed(std::map<std::string, Spec>& cache, const std::string& path, SourceMark where,
                          std::string_view what, Load load) {
  if (auto it = cache.find(path); it != cache.end()) return &it->second;
  if (std::string why = not_a_readable_reference(path); !why.empty()) {
    diag_.error(where, fmt::format("{} file '{}' {}", what, path, why));
    return nullptr;
  }
  auto spec = load(path, sources_, diag_);
  return spec ? &cache.emplace(path, std::move(*spec)).first->second : nullptr;
}

const VaultSpec* Study::vault_file(const std::string& path, SourceMark where) {
  return parsed(vaults_, path, where, "vault", [](const std::string& p, Sources& s, Diagnostics& d) { return load_vault(p, s, d); });
}

const ScenarioSpec* Study::scenario_file(const std::string& path, SourceMark where) {
  return parsed(scenarios_, path, where, spec_.campaign ? "campaign" : "scenario",
                [this](const std::string& p, Sources& s, Diagnostics& d) -> std::optional<ScenarioSpec> {
                  auto file = load_run_file(p, s, d);
                  if (!file) return std::nullopt;
                  if (auto* c = std::get_if<CampaignSpec>(&*file)) {
                    ScenarioSpec settings;
                    static_cast<RunFileSpec&>(settings) = *c;
                    campaigns_.emplace(p, std::move(*c));
                    return settings;
                  }
                  return std::move(std::get<ScenarioSpec>(*file));
                });
}

void Study::validate_names(const Workcell& wc, const std::string& vault_path, bool simulated, bool campaign) {
  for (const VarySpec& v : spec_.vary) {
    if (v.files()) continue;
    bool found = std::any_of(wc.parameters.begin(), wc.parameters.end(), [&](const Parameter& x) { return x.name == v.name; });
    if (found) continue;
    std::vector<std::string> names;
    for (const Parameter& x : wc.parameters) names.push_back(x.name);
    diag_.error(v.mark, fmt::format("vault '{}' ({}) has no parameter '{}' to vary{}", wc.name, vault_path, v.name,
                                    did_you_mean(v.name, names)));
  }
  for (const Metric& m : metrics_) m.validate(wc, simulated, campaign, diag_);
}

void Study::report_with_vault(const std::vector<Axis>& axes) {
  // The file has errors of its own (values that do not expand, a metric that does not parse):
  // still say what else is wrong with it, against the vault it names (when it names one
  // plainly), so one run reports every error.
  if (spec_.vault_path.empty()) return;
  const VaultSpec* vault = vault_file(spec_.vault_path, spec_.vault.mark);
  if (!vault) return;
  CompileOptions options = options_.compile;
  Diagnostics scratch;  // the vault's own errors are reported when the values are fixed
  auto wc = compile_vault(*vault, options, sources_, scratch);
  if (!wc) return;
  validate_names(*wc, spec_.vault_path, !spec_.scenario_path.empty(), spec_.campaign);
  validate_axis_values(*wc, axes);
}

void Study::validate_axes(const Workcell& wc, const Case& c) {
  validate_names(wc, c.vault_path, c.scenario != nullptr, c.campaign != nullptr);
  validate_axis_values(wc, set_.axes);
}

void Study::validate_axis_values(const Workcell& wc, const std::vector<Axis>& axes) {
  for (const Axis& axis : axes) {
    const VarySpec& v = *axis.spec;
    if (v.files()) continue;
    auto p = std::find_if(wc.parameters.begin(), wc.parameters.end(), [&](const Parameter& x) { return x.name == v.name; });
    if (p == wc.parameters.end()) continue;  // reported by validate_names
    if (axis.has_unit && axis.dim != p->dim) {
      diag_.error(v.mark, fmt::format("the values of '{}' are {}, but parameter '{}' of vault '{}' is {}", v.name,
                                      a_dim(axis.dim), v.name, wc.name, a_dim(p->dim)));
      continue;
    }
    if (p->type == AttrType::Integer)
      for (const AxisValue& value : axis.values)
        if (!value.number || value.si != std::floor(value.si))
          diag_.error(value.mark, fmt::format("parameter '{}' is an integer, but '{}' varies it to '{}'", v.name, v.name,
                                              value.set_text));
  }
}

bool Study::prepare_case(Case& c) {
  // The first case of a vault file compiles it with its library; later ones reuse that.
  auto same = std::find_if(cases_.begin(), cases_.end(), [&](const Case& o) {
    return o.vault_path == c.vault_path && o.library_dir == c.library_dir && o.library;
  });
  CompileOptions options = options_.compile;
  options.overrides = c.overrides;
  if (!c.library_dir.empty()) options.library_dirs.push_back(c.library_dir);
  if (same != cases_.end()) {
    c.library = same->library;
    c.plugins = same->plugins;
  } else {
    c.plugins = std::make_shared<PluginSet>();
  }
  options.plugins = c.plugins;
  options.library = c.library;
  options.whole_library = true;  // kept for the vault's other variants (c.library below)
  const uint32_t read_before = sources_.size();
  auto wc = compile_vault(*c.vault, options, sources_, diag_);
  if (!wc) return false;
  if (same != cases_.end()) {
    c.library_files = same->library_files;
  } else {
    for (uint32_t f = read_before; f < sources_.size(); ++f) c.library_files.push_back(f);
  }
  for (const std::string* path : {&c.scenario_path, &c.vault_path})
    if (!path->empty())
      if (uint32_t f = sources_.find(*path)) c.files.push_back(f);
  c.files.insert(c.files.end(), c.library_files.begin(), c.library_files.end());
  if (!c.library) c.library = std::make_shared<const std::vector<ObjectType>>(wc->types);
  validate_axes(*wc, c);
  GeometryModel geometry = build_geometry(*wc, diag_, &meshes_);  // reads every mesh once, before the forks
  if (c.scenario && !diag_.has_errors()) plan_run(c, *wc, geometry, diag_);
  return !diag_.has_errors();
}

bool Study::prepare(const std::string& path) {
  auto spec = load_sweep(path, sources_, diag_);
  if (!spec) return false;  // errors in the file's own keys still let its axes and metrics be checked
  spec_ = std::move(*spec);
  // Every error of the file in one run: the axes are checked against the vault even when the
  // mode, a metric or another key is wrong.
  const size_t errors = diag_.count();
  std::vector<Axis> axes = expand_axes(spec_, diag_);
  std::optional<VariantSet> set;
  if (diag_.count() == errors && !axes.empty())
    set = expand_variants(spec_, axes, diag_);
  else if (spec_.random)
    random_draw(spec_, diag_);  // the mode's own errors, which need no axes
  for (const MetricSpec& m : spec_.metrics)
    if (auto metric = Metric::parse(m, diag_)) metrics_.push_back(std::move(*metric));
  if (!set || diag_.has_errors()) {
    report_with_vault(axes);
    return false;
  }
  set_ = std::move(*set);

  // The cases: every (vault, scenario) pair a variant names, each file parsed once.
  int vault_axis = axis_named("vault"), scenario_axis = axis_named("scenario"), library_axis = axis_named("library");
  std::map<std::tuple<std::string, std::string, std::string>, size_t> index;
  case_of_.resize(set_.variants.size());
  for (const Variant& v : set_.variants) {
    Case c;
    SourceMark scenario_mark = spec_.scenario.mark;
    if (scenario_axis >= 0) {
      c.scenario_path = set_.value(v, scenario_axis).set_text;
      scenario_mark = set_.value(v, scenario_axis).mark;
    } else {
      c.scenario_path = spec_.scenario_path;
    }
    if (!c.scenario_path.empty() && !(c.scenario = scenario_file(c.scenario_path, scenario_mark))) return false;
    if (auto it = campaigns_.find(c.scenario_path); it != campaigns_.end()) c.campaign = &it->second;
    if (vault_axis >= 0) {
      c.vault_path = set_.value(v, vault_axis).set_text;
      if (!(c.vault = vault_file(c.vault_path, set_.value(v, vault_axis).mark))) return false;
    } else if (!spec_.vault_path.empty()) {
      c.vault_path = spec_.vault_path;
      if (!(c.vault = vault_file(c.vault_path, spec_.vault.mark))) return false;
    } else {
      c.vault_path = c.scenario->vault_path;
      if (!(c.vault = vault_file(c.vault_path, c.scenario->vault.mark))) return false;
    }
    c.checked = c.vault;
    if (c.campaign) {  // its arriving loads are objects of its vault
      auto at = campaign_vaults_.find({c.vault_path, c.scenario_path});
      if (at == campaign_vaults_.end()) {
        std::optional<VaultSpec> with_loads = load_vault(c.vault_path, sources_, diag_);  // (a spec is not copied)
        if (!with_loads) return false;
        add_arriving_loads(*c.campaign, *with_loads, diag_);
        at = campaign_vaults_.emplace(std::make_pair(c.vault_path, c.scenario_path), std::move(*with_loads)).first;
      }
      if (diag_.has_errors()) return false;
      c.vault = &at->second;
    }
    if (library_axis >= 0) {
      const AxisValue& dir = set_.value(v, library_axis);
      c.library_dir = dir.set_text;
      std::error_code ec;
      if (!fs::is_directory(c.library_dir, ec)) {
        diag_.error(dir.mark, fmt::format("library folder '{}' does not exist", c.library_dir));
        return false;
      }
      if (std::string why = outside_roots(c.library_dir); !why.empty()) {
        diag_.error(dir.mark, fmt::format("library folder '{}' {}", c.library_dir, why));
        return false;
      }
    }
    auto [it, fresh] = index.try_emplace({c.vault_path, c.scenario_path, c.library_dir}, cases_.size());
    if (fresh) {
      if (c.scenario)
        for (const auto& [name, value] : c.scenario->set) c.overrides.emplace_back(name, value.text);
      c.overrides.insert(c.overrides.end(), options_.compile.overrides.begin(), options_.compile.overrides.end());
      if (!prepare_case(c)) return false;
      cases_.push_back(std::move(c));
    }
    case_of_[v.index] = it->second;
  }

  header_.sweep = spec_.name;
  for (const Axis& a : set_.axes) header_.parameters.emplace_back(a.spec->name, a.has_unit ? file_unit(a.dim) : "");
  for (const Metric& m : metrics_) header_.metrics.push_back(m.name());
  header_.simulated = std::any_of(cases_.begin(), cases_.end(), [](const Case& c) { return c.scenario != nullptr; });

  // The manifest: what makes two folders results of the same study.
  manifest_.sweep = spec_.name;
  manifest_.sweep_sha256 = sha256_hex(sources_.text(sources_.find(spec_.path)));
  std::vector<std::string> digests;
  // Each input by name: the standard library's files under "<library>/", the rest relative to the
  // sweep file's folder, so the same study elsewhere names them alike.
  const fs::path library = fs::absolute(standard_library_dir()).lexically_normal();
  const fs::path home = fs::absolute(spec_.path).parent_path().lexically_normal();
  for (uint32_t f = 1; f < sources_.size(); ++f) {
    std::string digest = sha256_hex(sources_.text(f));
    digests.push_back(digest);
    fs::path p = fs::absolute(sources_.path(f)).lexically_normal();
    fs::path in_library = p.lexically_relative(library);
    std::string name = !in_library.empty() && *in_library.begin() != ".." ? "<library>/" + in_library.string()
                                                                           : p.lexically_relative(home).string();
    manifest_.inputs.emplace_back(name.empty() ? p.string() : name, digest);
  }
  std::sort(manifest_.inputs.begin(), manifest_.inputs.end());
  manifest_.inputs.erase(std::unique(manifest_.inputs.begin(), manifest_.inputs.end()), manifest_.inputs.end());
  std::sort(digests.begin(), digests.end());
  manifest_.inputs_sha256 = sha256_hex(fmt::format("{}", fmt::join(digests, "\n")));
  manifest_.variants = set_.variants.size();
  manifest_.mode = spec_.random ? "random" : "grid";
  manifest_.version = SSCS_VERSION;
  if (options_.shards > 1) manifest_.shard = fmt::format("{}/{}", options_.shard, options_.shards);
  return true;
}

VariantRow Study::base_row(const Variant& v) const {
  VariantRow row;
  row.index = v.index;
  row.folder = set_.folder(v);
  for (size_t a = 0; a < set_.axes.size(); ++a) row.values.push_back(set_.value(v, a).column);
  row.metrics.assign(metrics_.size(), std::nullopt);
  row.status = "error";
  return row;
}

VariantRow Study::evaluate(const Variant& v, const std::string& dir) {
  VariantRow row = base_row(v);
  const Case& c = cases_[case_of_[v.index]];
  CompileOptions options = options_.compile;
  options.library = c.library;
  options.plugins = c.plugins;
  options.overrides = c.overrides;
  for (size_t a = 0; a < set_.axes.size(); ++a)
    if (!set_.axes[a].spec->files()) options.overrides.emplace_back(set_.axes[a].spec->name, set_.value(v, a).set_text);
  Diagnostics diag;
  GeometryOptions remember;
  remember.contacts = contacts_;
  // The check judges the vault as written: a campaign's arriving loads, all at their spot in
  // the vault its run compiles, are not there yet (forty drums on one dock overlapped).
  auto [wc, geometry] = prepare_vault(*c.checked, options, sources_, diag, remember, &meshes_);
  if (!wc || diag.has_errors()) {
    row.message = "the vault does not compile with these values: " + first_line(diag.format_errors(sources_));
    return row;
  }
  CheckReport report = check(*wc, geometry);
  std::string err = write_file_atomic(dir + "/report.json", format_json({VaultReport{&*wc, c.vault_path, report, {}, diag.warnings(), options.overrides}}, sources_));
  if (!err.empty()) throw std::runtime_error(err);
  row.passed = report.passed;
  row.failed = report.failed;
  row.warnings = report.warnings;
  row.status = report.failed > 0 ? "fail" : "pass";
  std::optional<RunSummary> run;
  if (c.scenario) {
    // The campaign's run: its vault with the loads that arrive (the check and the metrics read
    // the vault as written).
    std::optional<Workcell> with_loads;
    GeometryModel with_loads_geometry;
    if (c.vault != c.checked) {
      auto prepared = prepare_vault(*c.vault, options, sources_, diag, remember, &meshes_);
      if (!prepared.wc || diag.has_errors()) {
        row.message = "the campaign's loads do not compile with these values: " + first_line(diag.format_errors(sources_));
        return row;
      }
      with_loads = std::move(prepared.wc);
      with_loads_geometry = std::move(prepared.geometry);
    }
    const Workcell& run_wc = with_loads ? *with_loads : *wc;
    GeometryModel& run_geometry = with_loads ? with_loads_geometry : geometry;
    run_geometry.contacts.reset();  // a run's moving shapes are never placed alike twice: nothing to remember
    auto plan = plan_run(c, run_wc, run_geometry, diag);
    if (!plan || diag.has_errors()) {
      row.status = "error";
      row.message = fmt::format("the {} cannot run with these values: {}", c.campaign ? "campaign" : "scenario",
                                first_line(diag.format_errors(sources_)));
      return row;
    }
    RunInputs inputs = collect_run_inputs(*c.scenario, options.overrides, run_wc, run_geometry, sources_, &c.files,
                                          c.campaign ? "campaign" : "scenario");
    RunOptions ro;
    ro.out_dir = dir + "/run";
    ro.scenario_name = c.scenario->name;
    ro.inputs = &inputs;
    if (c.campaign)
      ro.final_vault = [&](const FinalState& end) { return final_vault_text(run_wc, sources_, end, "campaign " + c.scenario->name, true); };
    Expected<RunSummary> ran = run_simulation(run_wc, run_geometry, *plan, ro);
    if (!ran) throw std::runtime_error(ran.error());
    run = std::move(*ran);
    row.cycle_time = run->cycle_time;
    row.collisions = run->collisions;
    if (run->status != RunStatus::Ok) row.status = "fail";
  }
  std::vector<std::string> problems;
  // A check that could not be evaluated fails the variant: say why first (a plugin out of memory,
  // a value that is not a number), not only the metrics that then have no value.
  for (const CheckResult& r : report.results)
    if (r.status == Status::Error) {
      problems.push_back(fmt::format("'{}' could not be evaluated: {}", wc->constraints[r.constraint].name, r.message));
      break;
    }
  if (run && run->status != RunStatus::Ok)
    problems.push_back(fmt::format("run: {} (see run/events.jsonl)", run_status_name(run->status)));
  for (size_t i = 0; i < metrics_.size(); ++i) {
    Expected<double> value = metrics_[i].evaluate(*wc, geometry, report, run ? &*run : nullptr);
    if (value) row.metrics[i] = *value;
    else problems.push_back(value.error());
  }
  row.message = fmt::format("{}", fmt::join(problems, "; "));
  return row;
}

/// One variant in a worker: its output (log.txt) and result.json in `tmp`.
void Study::run_variant(const Variant& v, const std::string& tmp) {
  int log = open((tmp + "/log.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (log >= 0) {
    std::fflush(nullptr);
    dup2(log, STDOUT_FILENO);
    dup2(log, STDERR_FILENO);
    close(log);
  }
  VariantRow row;
  try {
    row = evaluate(v, tmp);
  } catch (const std::bad_alloc&) {
    row = base_row(v);
    row.message = fmt::format("ran out of memory: a variant may take {:.1f} GB (--variant-memory)", memory_limit_ / 1e9);
  } catch (const std::exception& e) {
    row = base_row(v);
    row.message = fmt::format("internal error: {}", e.what());
  }
  // A full disk: nothing written counts; the parent finds no complete result and stops the sweep.
  if (std::string err = write_file(tmp + "/result.json", result_json(row, header_)); !err.empty())
    std::fprintf(stderr, "%s\n", err.c_str());
  std::fflush(nullptr);
}

/// Commits a variant's folder only when its result.json is whole (a full disk leaves it empty or
/// cut short): else removes it and says why. "" when committed.
std::string Study::commit_variant(const Variant& v) {
  const std::string tmp = tmp_dir(v);
  std::error_code ec;
  if (Expected<VariantRow> written = read_result(tmp + "/result.json", header_); !written) {
    std::string said = last_line(tmp + "/log.txt");
    fs::remove_all(tmp, ec);
    return fmt::format("variant {} ('{}') was not written whole, so it is not kept (is the disk full?): {}", v.index,
                       set_.folder(v), said.empty() ? written.error() : said);
  }
  if (std::string err = commit_dir(tmp, dir(v)); !err.empty()) {
    fs::remove_all(tmp, ec);
    return err;
  }
  return "";
}

/// A worker process: forked once, it takes variant indices from `tasks` and answers each on
/// `done` when its folder is written; it ends when `tasks` closes. A variant that kills it
/// (a crash, a timeout) costs only that variant: the parent records it and starts another.
void Study::worker(int tasks, int done) {
  // A variant that would take the machine's memory fails alone: its allocation fails, it is
  // recorded as an error naming the limit, and the other workers go on.
  rlimit limit{memory_limit_, memory_limit_};
  if (memory_limit_ > 0 && kAddressSpaceLimits) setrlimit(RLIMIT_AS, &limit);
  signal(SIGINT, SIG_IGN);  // the parent decides what an interrupt stops
  signal(SIGTERM, SIG_DFL);
  signal(SIGPIPE, SIG_DFL);
  sigset_t none;
  sigemptyset(&none);
  sigprocmask(SIG_SETMASK, &none, nullptr);
  uint64_t index = 0;
  while (read(tasks, &index, sizeof index) == sizeof index) {
    run_variant(set_.variants[index], tmp_dir(set_.variants[index]));
    if (write(done, &index, sizeof index) != sizeof index) break;
  }
  _exit(0);  // not the parent's destructors
}

SweepOutcome Study::run() {
  SweepOutcome out;
  out.variants = set_.variants.size();
  out.out = options_.out.empty() ? "sweep-" + spec_.name : options_.out;
  out_ = out.out;
  std::error_code ec;
  // Never write into (or with --force, clear) a folder that holds something other than a sweep.
  if (fs::is_directory(out.out, ec) && !fs::is_empty(out.out, ec) && !fs::exists(out.out + "/sweep.json", ec)) {
    out.end = SweepOutcome::End::InputError;
    out.message = fmt::format("'{}' is not empty and holds no sweep (no sweep.json); choose another --out", out.out);
    return out;
  }
  fs::create_directories(out.out, ec);
  if (ec) {
    out.end = SweepOutcome::End::InputError;
    out.message = fmt::format("cannot create '{}': {}", out.out, ec.message());
    return out;
  }
  // A folder of another sweep (or of other inputs, or another shard) is not resumed into.
  std::string manifest_path = out.out + "/sweep.json";
  if (fs::exists(manifest_path)) {
    auto old = read_manifest(manifest_path);
    bool same = old && old->sweep_sha256 == manifest_.sweep_sha256 && old->inputs_sha256 == manifest_.inputs_sha256 &&
                old->shard == manifest_.shard && old->variants == manifest_.variants;
    if (!same && !options_.force) {
      out.end = SweepOutcome::End::InputError;
      out.message = fmt::format("'{}' holds the results of {} (a different sweep file, inputs or shard); use --force to "
                                "replace them, or another --out", out.out, old ? "sweep '" + old->sweep + "'" : "something else");
      return out;
    }
  }
  if (options_.force)
    for (const auto& entry : fs::directory_iterator(out.out, ec)) fs::remove_all(entry.path(), ec);
  // Folders of variants a killed run left half-written.
  for (const auto& entry : fs::directory_iterator(out.out, ec))
    if (entry.path().filename().string().starts_with(".") && entry.path().filename().string().find(".tmp-") != std::string::npos)
      fs::remove_all(entry.path(), ec);
  if (std::string err = write_file_atomic(manifest_path, manifest_json(manifest_)); !err.empty()) {
    out.end = SweepOutcome::End::OutputError;
    out.message = err;
    return out;
  }

  std::vector<const Variant*> todo, mine;
  for (const Variant& v : set_.variants) {
    if (v.index % options_.shards != options_.shard) continue;
    mine.push_back(&v);
    if (fs::exists(fmt::format("{}/{}/result.json", out.out, set_.folder(v)))) ++out.resumed;
    else todo.push_back(&v);
  }
  out.mine = mine.size();

  unsigned jobs = options_.jobs ? options_.jobs : std::max(1u, std::thread::hardware_concurrency());
  if (options_.variant_memory_gb > 0) {
    memory_limit_ = static_cast<rlim_t>(options_.variant_memory_gb * 1e9);
  } else {  // the machine's memory shared by the workers, at least 1 GB each
    const double physical = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
    memory_limit_ = static_cast<rlim_t>(std::max(1e9, physical / jobs));
  }
  jobs = static_cast<unsigned>(std::min<size_t>(jobs, std::max<size_t>(todo.size(), 1)));
  struct Worker {
    pid_t pid = -1;
    int tasks = -1, done = -1;         ///< pipe ends: parent -> worker, worker -> parent
    const Variant* variant = nullptr;  ///< the one it runs, if any
    std::chrono::steady_clock::time_point started;
    bool killed = false;
  };
  std::vector<Worker> workers(jobs);
  ProgressBar progress(options_.progress, todo.size());
  Dealer dealer(todo.size(), jobs);
  size_t done = 0;
  std::string failure;
  bool output_failure = false;  // a variant or its result could not be written
  auto start_worker = [&](Worker& w) {
    int to[2], from[2];
    if (pipe2(to, O_CLOEXEC) != 0 || pipe2(from, O_CLOEXEC) != 0) {
      failure = fmt::format("cannot start a worker: {}", std::strerror(errno));
      return;
    }
    std::fflush(nullptr);
    pid_t pid = fork();
    if (pid == 0) {
      close(to[1]);
      close(from[0]);
      for (const Worker& other : workers)  // other workers' pipes are not this one's
        if (other.pid > 0) close(other.tasks), close(other.done);
      worker(to[0], from[1]);
    }
    close(to[0]);
    close(from[1]);
    if (pid < 0) {
      close(to[1]);
      close(from[0]);
      failure = fmt::format("cannot start a worker: {}", std::strerror(errno));
      return;
    }
    w = Worker{pid, to[1], from[0], nullptr, {}, false};
  };
  auto stop_worker = [&](Worker& w, bool kill_it) {
    if (w.pid <= 0) return;
    if (kill_it) kill(w.pid, SIGKILL);
    close(w.tasks);
    close(w.done);
    int status = 0;
    waitpid(w.pid, &status, 0);
    w.pid = -1;
  };
  auto give = [&](Worker& w) {
    if (!failure.empty()) return;
    std::optional<size_t> task = dealer.next(static_cast<size_t>(&w - workers.data()));
    if (!task) return;
    const Variant* v = todo[*task];
    std::string tmp = tmp_dir(*v);
    fs::remove_all(tmp, ec);
    fs::create_directories(tmp, ec);
    uint64_t index = v->index;
    w.variant = v;
    w.started = std::chrono::steady_clock::now();
    w.killed = false;
    if (write(w.tasks, &index, sizeof index) != sizeof index) failure = "a worker stopped taking variants";
  };
  // The variant a worker was running when it died: an error row, unless an interrupt stopped it.
  auto lost = [&](Worker& w, int status) {
    const Variant* v = w.variant;
    w.variant = nullptr;
    std::string tmp = tmp_dir(*v);
    bool stopped = WIFSIGNALED(status) && !w.killed &&
                   (WTERMSIG(status) == SIGINT || WTERMSIG(status) == SIGTERM || WTERMSIG(status) == SIGHUP);
    if (stopped) {  // Ctrl-C or scancel: not done; a resumed run does it
      fs::remove_all(tmp, ec);
      return;
    }
    VariantRow row = base_row(*v);
    row.message = w.killed ? fmt::format("timed out after {:g} s (--variant-timeout)", options_.variant_timeout)
                  : WIFSIGNALED(status) ? fmt::format("crashed: signal {} ({})", WTERMSIG(status), strsignal(WTERMSIG(status)))
                                        : fmt::format("the variant's process exited with status {}", WEXITSTATUS(status));
    if (std::string said = last_line(tmp + "/log.txt"); !said.empty()) row.message += ": " + said;
    if (std::string err = write_file(tmp + "/result.json", result_json(row, header_)); !err.empty()) {
      fs::remove_all(tmp, ec);
      failure = err;
      output_failure = true;
    } else if (std::string err = commit_variant(*v); !err.empty()) {
      failure = err;
      output_failure = true;
    }
    progress.update(++done);
  };
  for (Worker& w : workers) {
    if (dealer.left() == 0 || !failure.empty()) break;
    start_worker(w);
    if (w.pid > 0) give(w);
  }
  auto busy = [&] { return std::any_of(workers.begin(), workers.end(), [](const Worker& w) { return w.variant != nullptr; }); };
  while (busy() && failure.empty()) {
    if (options_.interrupted && *options_.interrupted) break;
    std::vector<pollfd> fds;
    std::vector<Worker*> owners;
    int wait_ms = 200;
    auto now = std::chrono::steady_clock::now();
    for (Worker& w : workers) {
      if (!w.variant) continue;
      fds.push_back({w.done, POLLIN, 0});
      owners.push_back(&w);
      if (options_.variant_timeout > 0 && !w.killed) {
        auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            w.started + std::chrono::duration<double>(options_.variant_timeout) - now);
        wait_ms = std::clamp(static_cast<int>(left.count()) + 1, 1, wait_ms);
      }
    }
    poll(fds.data(), fds.size(), wait_ms);  // EINTR on an interrupt: the loop looks at the flag
    for (size_t i = 0; i < fds.size(); ++i) {
      Worker& w = *owners[i];
      if (!(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      uint64_t index = 0;
      if ((fds[i].revents & POLLIN) && read(w.done, &index, sizeof index) == sizeof index && index == w.variant->index) {
        const Variant* v = w.variant;
        w.variant = nullptr;
        if (std::string err = commit_variant(*v); !err.empty()) {
          failure = err;
          output_failure = true;
        }
        progress.update(++done);
        give(w);
        continue;
      }
      // The worker died: record its variant, start another worker for the rest.
      int status = 0;
      close(w.tasks);
      close(w.done);
      waitpid(w.pid, &status, 0);
      w.pid = -1;
      lost(w, status);
      if (dealer.left() > 0 && failure.empty() && !(options_.interrupted && *options_.interrupted)) {
        start_worker(w);
        if (w.pid > 0) give(w);
      }
    }
    if (options_.variant_timeout > 0)
      for (Worker& w : workers)
        if (w.variant && !w.killed &&
            std::chrono::steady_clock::now() - w.started > std::chrono::duration<double>(options_.variant_timeout)) {
          kill(w.pid, SIGKILL);
          w.killed = true;
        }
    progress.update(done);
  }
  bool interrupted = options_.interrupted && *options_.interrupted;
  for (Worker& w : workers) {
    bool running = w.variant != nullptr;
    stop_worker(w, running);  // idle workers end when their task pipe closes
    if (running) fs::remove_all(tmp_dir(*w.variant), ec);
    w.variant = nullptr;
  }
  progress.finish(done);
  if (!failure.empty()) {
    out.end = output_failure ? SweepOutcome::End::OutputError : SweepOutcome::End::Failed;
    out.message = failure;
    return out;
  }
  if (interrupted) {
    out.end = SweepOutcome::End::Interrupted;
    out.message = fmt::format("interrupted: {} of {} variants are done in '{}'; run the same command again to go on",
                              out.resumed + done, mine.size(), out.out);
    return out;
  }

  std::vector<VariantRow> rows;
  for (const Variant* v : mine) {
    auto row = read_result(fmt::format("{}/{}/result.json", out.out, set_.folder(*v)), header_);
    if (!row) {
      out.end = SweepOutcome::End::Failed;
      out.message = row.error() + " (delete that variant's folder to run it again)";
      return out;
    }
    (row->status == "pass" ? out.pass : row->status == "fail" ? out.fail : out.error)++;
    rows.push_back(std::move(*row));
  }
  for (const auto& [name, content] : {std::pair{"results.csv", results_csv(header_, rows)}, {"results.json", results_json(header_, rows)}})
    if (std::string err = write_file_atomic(out.out + "/" + name, content); !err.empty()) {
      out.end = SweepOutcome::End::OutputError;
      out.message = err;
      return out;
    }
  return out;
}

}  // namespace

SweepOutcome run_sweep(const std::string& path, const SweepOptions& options, Sources& sources, Diagnostics& diag) {
  Study study(options, sources, diag);
  if (!study.prepare(path)) {
    SweepOutcome out;
    out.end = SweepOutcome::End::InputError;
    return out;
  }
  return study.run();
}

SweepOutcome merge_sweep(const std::vector<std::string>& dirs, const std::string& out_dir) {
  SweepOutcome out;
  out.out = out_dir;
  auto refuse = [&](std::string message) {
    out.end = SweepOutcome::End::InputError;
    out.message = std::move(message);
    return out;
  };
  std::optional<Manifest> first;
  std::optional<TableHeader> header;
  std::map<size_t, std::pair<std::string, VariantRow>> rows;  // index -> (shard folder, row)
  std::error_code ec;
  for (size_t i = 0; i < dirs.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (fs::equivalent(dirs[i], dirs[j], ec)) return refuse(fmt::format("'{}' is named twice; merge each shard once", dirs[i]));
  for (const std::string& dir : dirs) {
    if (fs::equivalent(dir, out_dir, ec)) return refuse(fmt::format("--out '{}' is one of the folders to merge; merge into a new folder", out_dir));
    auto m = read_manifest(dir + "/sweep.json");
    if (!m) return refuse(fs::exists(dir + "/sweep.json") ? m.error() : fmt::format("'{}' is not a sweep folder (it has no sweep.json)", dir));
    if (!first) {
      first = *m;
    } else if (m->sweep_sha256 != first->sweep_sha256 || m->inputs_sha256 != first->inputs_sha256 || m->variants != first->variants) {
      return refuse(fmt::format("'{}' holds results of a different sweep than '{}' (sweep '{}' vs '{}': the sweep file or its "
                                "inputs differ); merge only shards of one sweep", dir, dirs[0], m->sweep, first->sweep));
    }
    auto h = read_header(dir + "/results.json");
    if (!h) return refuse(fmt::format("'{}' has no complete table (shard {} did not finish?): {}", dir, m->shard.empty() ? "-" : m->shard, h.error()));
    if (!header) header = *h;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      std::string result = (entry.path() / "result.json").string();
      if (!entry.is_directory() || entry.path().filename().string().starts_with(".") || !fs::exists(result)) continue;
      auto row = read_result(result, *header);
      if (!row) return refuse(row.error());
      if (auto it = rows.find(row->index); it != rows.end())
        return refuse(fmt::format("variant {} is in both '{}' and '{}'; merge each shard once", row->index, it->second.first, dir));
      rows.emplace(row->index, std::pair{dir, std::move(*row)});
    }
  }
  std::vector<size_t> missing;
  for (size_t i = 0; i < first->variants; ++i)
    if (!rows.count(i)) missing.push_back(i);
  if (!missing.empty()) {
    std::vector<size_t> shown(missing.begin(), missing.begin() + std::min<size_t>(missing.size(), 10));
    return refuse(fmt::format("{} of the {} variants of sweep '{}' are in none of the folders (variants {}{}); is a shard "
                              "missing or unfinished?", missing.size(), first->variants, first->sweep, fmt::join(shown, ", "),
                              missing.size() > shown.size() ? ", ..." : ""));
  }
  StagedDir staging(out_dir);
  const std::string& tmp = staging.path();
  std::vector<VariantRow> table;
  for (auto& [index, entry] : rows) {
    fs::copy(fs::path(entry.first) / entry.second.folder, fs::path(tmp) / entry.second.folder, fs::copy_options::recursive, ec);
    if (ec) {
      out.end = SweepOutcome::End::OutputError;
      out.message = fmt::format("cannot copy variant {} into '{}': {}", index, out_dir, ec.message());
      return out;
    }
    (entry.second.status == "pass" ? out.pass : entry.second.status == "fail" ? out.fail : out.error)++;
    table.push_back(std::move(entry.second));
  }
  Manifest whole = *first;
  whole.shard.clear();
  std::string err;
  for (const auto& [name, content] : {std::pair{"sweep.json", manifest_json(whole)}, {"results.csv", results_csv(*header, table)},
                                      {"results.json", results_json(*header, table)}})
    if (err.empty()) err = write_file_atomic(tmp + "/" + name, content);
  if (err.empty()) err = staging.commit();
  if (!err.empty()) {
    out.end = SweepOutcome::End::OutputError;
    out.message = err;
    return out;
  }
  out.variants = out.mine = first->variants;
  return out;
}

}  // namespace sscs
