#include <cmath>

#include "cli/subcommands.h"
#include "pipeline/html_report.h"
#include "sweep/sweep.h"

namespace sscs::cli {

namespace {

/// "K/N" with 0 <= K < N.
bool parse_shard(const std::string& text, unsigned& k, unsigned& n) {
  auto slash = text.find('/');
  if (slash == std::string::npos) return false;
  try {
    size_t a = 0, b = 0;
    unsigned long kk = std::stoul(text.substr(0, slash), &a), nn = std::stoul(text.substr(slash + 1), &b);
    if (a != slash || b != text.size() - slash - 1 || nn == 0 || kk >= nn || nn > 100000) return false;
    k = static_cast<unsigned>(kk);
    n = static_cast<unsigned>(nn);
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

int report_sweep(const SweepOutcome& o, const char* verb) {
  switch (o.end) {
    case SweepOutcome::End::InputError:
      std::cerr << "sscs: error: " << o.message << "\n";
      return kInputError;
    case SweepOutcome::End::Interrupted:
      std::cerr << "sscs: " << o.message << "\n";
      return 128 + SIGINT;
    case SweepOutcome::End::Failed:
      std::cerr << "sscs: error: " << o.message << "\n";
      return kInternalError;
    case SweepOutcome::End::OutputError:  // as every command reports a write that failed
      std::cerr << "sscs: error: " << o.message << "\n";
      return kInputError;
    case SweepOutcome::End::Done:
      break;
  }
  // The summary line is printed even with --quiet: it is the one line a job log needs.
  std::string resumed = o.resumed ? fmt::format(" ({} done before)", o.resumed) : "";
  std::cout << fmt::format("{} {} variants{}: {} pass, {} fail, {} error; results in {}/results.csv\n", verb, o.mine, resumed,
                           o.pass, o.fail, o.error, o.out);
  return o.fail + o.error > 0 ? kViolations : kOk;
}

int run_sweep_command(const Common& common, const SweepArgs& args) {
  if (std::string why = html_target_refusal(args.html, {args.out}); !why.empty()) {
    std::cerr << "sscs: error: " << why << "\n";
    return kInputError;
  }
  SweepOptions options;
  if (!common.apply(options.compile, args.sweep.empty() ? std::vector<std::string>{} : std::vector<std::string>{args.sweep}))
    return kInputError;
  if (!args.shard.empty() && !parse_shard(args.shard, options.shard, options.shards)) {
    std::cerr << fmt::format("sscs: error: --shard expects K/N with 0 <= K < N (e.g. 3/8), found '{}'\n", args.shard);
    return kInputError;
  }
  if (!(args.variant_timeout >= 0) || !std::isfinite(args.variant_timeout)) {  // nan and inf too
    std::cerr << fmt::format("sscs: error: --variant-timeout must be a number of seconds, at least 0, found {}\n",
                             args.variant_timeout);
    return kInputError;
  }
  options.out = args.out;
  options.jobs = args.jobs;
  options.force = args.force;
  options.variant_timeout = args.variant_timeout;
  if (!(args.variant_memory >= 0) || !std::isfinite(args.variant_memory)) {
    std::cerr << fmt::format("sscs: error: --variant-memory must be a number of GB, at least 0, found {}\n",
                             args.variant_memory);
    return kInputError;
  }
  options.variant_memory_gb = args.variant_memory;
  options.interrupted = &g_interrupted;
  if (!common.quiet) options.progress = isatty(fileno(stderr)) ? ProgressBar::Mode::Live : ProgressBar::Mode::Lines;
  Sources sources;
  Diagnostics diag;
  SweepOutcome outcome;
  {
    InterruptGuard interrupts;
    outcome = run_sweep(args.sweep, options, sources, diag);
  }
  if (report_diagnostics(diag, sources, common)) return kInputError;
  const int status = report_sweep(outcome, "swept");
  if (!args.html.empty() && outcome.end == SweepOutcome::End::Done) {
    Expected<std::string> html = sweep_html(outcome.out, args.html);
    std::string err = html ? write_file_atomic(args.html, *html) : html.error();
    if (!err.empty()) {
      std::cerr << "sscs: error: the HTML report: " << err << "\n";
      return kInputError;
    }
    if (!common.quiet) std::cout << fmt::format("HTML report: {}\n", args.html);
  }
  return status;
}


}  // namespace sscs::cli
