#include <charconv>
#include <cmath>
#include <filesystem>

#include "cli/subcommands.h"
#include "core/pose.h"
#include "pipeline/html_report.h"
#include "pipeline/run_scenario.h"
#include "report/compare.h"

namespace sscs::cli {

int run_simulate(const Common& common, const SimulateArgs& args) {
  RunRequest request;
  request.out = args.out;
  request.bundle = args.bundle;
  request.frames = !args.no_frames;
  request.video = args.video;
  request.shadows = args.shadows;
  request.see_through = args.walls == "see-through";
  CompileOptions options;
  if (!common.apply(options, {args.scenario})) return kInputError;
  std::string why = !args.video.empty() && args.no_frames ? "--video needs frames; it cannot go with --no-frames"
                    : !args.video.empty() && std::filesystem::path(args.video).extension() != ".mp4"
                        ? fmt::format("--video expects a .mp4 file, found '{}'", args.video)
                    : !args.bundle.empty() && std::filesystem::path(args.bundle).extension() != ".zip"
                        ? fmt::format("--bundle expects a .zip file, found '{}'", args.bundle)
                        : html_target_refusal(args.html, {args.out, args.bundle, args.video});
  if (why.empty() && args.wall_limit) {
    // Decimal only (strtod read "0x10" as 16 s); an empty value is an error, not "no limit".
    const std::string& text = *args.wall_limit;
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), request.wall_limit, std::chars_format::general);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size() || !std::isfinite(request.wall_limit) ||
        !(request.wall_limit > 0))
      why = fmt::format("--wall-limit expects a number of seconds above 0, found '{}'", printable(text));
  }
  if (!why.empty()) {
    std::cerr << "sscs: error: " << why << "\n";
    return kInputError;
  }
  PreparedScenario ps;
  if (!ps.prepare(args.scenario, options)) {
    std::cerr << ps.diag.format(ps.sources, common.color_for(stderr));
    return kInputError;
  }
  report_diagnostics(ps.diag, ps.sources, common);  // warnings
  if (request.out.empty() && request.bundle.empty()) request.out = "run-" + ps.spec->name;
  if (why = run_request_refusal(ps, request); why.empty()) why = run_targets_refusal(request.out, request.bundle, args.force);
  if (!why.empty()) {
    std::cerr << "sscs: error: " << why << "\n";
    return kInputError;
  }
  if (!common.quiet) request.progress = isatty(fileno(stderr)) ? RunOptions::Progress::Live : RunOptions::Progress::Lines;
  request.progress_to = &std::cerr;
  request.interrupted = &g_interrupted;
  Expected<RunSummary> ran = [&] {
    InterruptGuard interrupts;
    return run_scenario(ps, request);
  }();
  if (!ran) {
    std::cerr << "sscs: error: " << ran.error() << "\n";
    return kInternalError;
  }
  const RunSummary& summary = *ran;
  if (summary.interrupted) {
    std::cerr << "sscs: interrupted; nothing written\n";
    return 128 + SIGINT;
  }
  const std::string& out = request.out;
  const std::string& bundle = request.bundle;
  std::string where = out.empty() ? bundle : bundle.empty() ? out : fmt::format("{} and {}", out, bundle);
  // A run that stopped says why and when, and has no cycle time.
  std::string status = run_status_name(summary.status);
  if (!summary.stopped_by.empty())
    status += fmt::format(" ({} at {:g} s{}{}), no cycle time", summary.stopped_by, stable(summary.stopped_at),
                          summary.stop_message.empty() ? "" : ": ", printable(within_window(summary.stop_message)));
  else if (!summary.unfinished.empty() && !summary.campaign)  // (a campaign's figure is its makespan)
    status += fmt::format(", no cycle time ({})", printable(within_window(summary.unfinished)));
  else if (!summary.campaign)
    status += fmt::format(", cycle time {:g} s", stable(summary.cycle_time));
  // A campaign says what became of its jobs: failed ones and ones never started are what a
  // gate must see (a campaign that stored nothing read "ok, cycle time 0 s").
  if (const auto& c = summary.campaign)
    status += fmt::format(", {} jobs done, {} failed, {} not started, makespan {:g} s, {:g} jobs/h", c->done, c->failed, c->not_started,
                          stable(c->makespan), stable(c->throughput));
  std::cout << fmt::format("{}: {}, {} collisions, {} events; written to {}\n", ps.spec->name, status, summary.collisions,
                           summary.events, where);
  if (!args.html.empty()) {
    // The page is made from what the run wrote, as `sscs report RUN --html` makes it.
    // The run's files are read as `sscs report` reads them: confined to the run's own folder.
    Expected<std::shared_ptr<OpenedRun>> written = OpenedRun::open(out.empty() ? bundle : out);
    CompileOptions run_options;
    Expected<std::string> html = !written ? Unexpected{written.error()}
                                 : !common.apply(run_options, {(*written)->dir()}) ? Unexpected{"the options do not apply to the run"}
                                                                                    : run_html(**written, run_options);
    std::string err = html ? write_file_atomic(args.html, *html) : html.error();
    if (!err.empty()) {
      std::cerr << "sscs: error: the HTML report: " << err << "\n";
      return kInputError;
    }
    if (!common.quiet) std::cout << fmt::format("HTML report: {}\n", args.html);
  }
  return summary.status == RunStatus::Ok ? kOk : kViolations;
}

int run_compare(const std::vector<std::string>& paths, const std::string& format) {
  Expected<std::vector<RunRecord>> runs = read_runs(paths);
  if (!runs) {
    std::cerr << "sscs: error: " << runs.error() << "\n";
    return kInputError;
  }
  std::cout << (format == "json" ? compare_json(*runs) : format == "csv" ? compare_csv(*runs) : compare_text(*runs));
  return kOk;
}


}  // namespace sscs::cli
