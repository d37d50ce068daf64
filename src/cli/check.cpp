#include <algorithm>
#include <filesystem>
#include <optional>
#include <sstream>

#include "check/check.h"
#include "cli/subcommands.h"
#include "core/files.h"
#include "core/timer.h"
#include "pipeline/html_report.h"
#include "pipeline/prepare.h"
#include "pipeline/catalogue.h"
#include "pipeline/type_listing.h"
#include "plugin/plugins.h"
#include "report/report.h"

namespace sscs::cli {

namespace {

/// The format named, else the --out extension's, else text.
std::string pick_format(const CheckArgs& a) {
  if (!a.format.empty()) return a.format;
  std::string ext = std::filesystem::path(a.out).extension().string();
  if (ext == ".json") return "json";
  if (ext == ".xml") return "junit";
  if (ext == ".sarif") return "sarif";
  return "text";
}


}  // namespace

int run_check(const Common& common, const CheckArgs& args) {
  if (std::string why = html_target_refusal(args.html, {args.out}); !why.empty()) {
    std::cerr << "sscs: error: " << why << "\n";
    return kInputError;
  }
  std::string format = pick_format(args);
  CompileOptions options;
  if (!common.apply(options, args.vaults)) return kInputError;
  Sources sources;
  Diagnostics diag;
  // --strict: what sscs would skip or assume with a warning (a degenerate URDF shape) is an
  // input error, as a failed warning constraint fails the gate.
  diag.set_strict(args.strict, "(a warning; an error with --strict)");
  std::vector<Workcell> cells;
  std::vector<GeometryModel> geometry;
  std::vector<std::vector<Diagnostic>> input_warnings;
  cells.reserve(args.vaults.size());
  for (const std::string& path : args.vaults) {
    common.confine_to(path);  // each vault reads within its own project, not another's
    const size_t warned = diag.warnings().size();
    // The HTML report draws devices as they look (their visual meshes).
    PreparedVault vault = prepare_vault(path, options, sources, diag, {.visuals = !args.html.empty(), .contacts = nullptr});
    if (vault.wc) {
      geometry.push_back(std::move(vault.geometry));
      cells.push_back(std::move(*vault.wc));
      input_warnings.emplace_back(diag.warnings().begin() + warned, diag.warnings().end());
    }
    if (diag.full()) break;
  }
  // Inputs in the order they are named: the vaults, then the baseline; every error of both.
  std::optional<Baseline> baseline;
  std::string baseline_error;
  if (!args.baseline.empty()) {
    Expected<Baseline> read = read_baseline(args.baseline);
    if (read) baseline = std::move(*read);
    else baseline_error = read.error();
  }
  if (report_diagnostics(diag, sources, common) || !baseline_error.empty()) {
    if (!baseline_error.empty()) std::cerr << "sscs: error: " << baseline_error << "\n";
    return kInputError;  // nothing written
  }
  StageTimer timer;
  std::vector<VaultReport> reports;
  CheckOptions check_options;
  check_options.describe_passes = format != "text" || !args.html.empty();  // the text report prints failures only
  for (size_t i = 0; i < cells.size(); ++i) {
    reports.push_back({&cells[i], args.vaults[i], check(cells[i], geometry[i], check_options), std::nullopt, input_warnings[i], options.overrides});
    if (baseline) reports.back().baseline = compare_with_baseline(cells[i], reports.back().report, *baseline);
  }
  timer.lap("check");
  // The HTML page is made before anything is written: a failure leaves no output.
  std::string html;
  if (!args.html.empty()) {
    std::vector<const GeometryModel*> models;
    for (const GeometryModel& g : geometry) models.push_back(&g);
    html = check_html(reports, sources, models);
    timer.lap("html");
  }
  // A report written over a file it was made from (`--out vault.yaml`) would destroy the input.
  for (const auto& [option, path] : {std::pair{"--out", &args.out}, std::pair{"--html", &args.html}}) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path target = fs::weakly_canonical(*path, ec);
    for (uint32_t f = 1; !path->empty() && f < sources.size(); ++f)
      if (fs::exists(sources.path(f), ec) && fs::weakly_canonical(sources.path(f), ec) == target) {
        std::cerr << fmt::format("sscs: error: {} '{}' is an input of this check ({}); write the report elsewhere\n", option, *path,
                                 sources.path(f));
        return kInputError;
      }
  }
  // JSON, JUnit and SARIF are streamed as they are made (to stdout, or to a temporary file renamed
  // into place when complete): a report of 100,000 results is never held whole in memory.
  auto write_report = [&](std::ostream& out) {
    if (format == "json") {
      write_json(out, reports, sources);
    } else if (format == "junit") {
      write_junit(out, reports, sources, args.strict);
    } else if (format == "sarif") {
      write_sarif(out, reports, sources, args.strict, std::filesystem::current_path().string());
    } else {
      // --quiet shortens what the terminal shows, never a report written to a file.
      bool terminal = args.out.empty();
      out << format_text(reports, sources, {terminal && common.color_for(stdout), terminal && common.quiet, args.strict});
    }
  };
  if (args.out.empty()) {
    write_report(std::cout);
    std::cout << std::flush;
    timer.lap("report");
  } else {
    std::string err = write_file_atomic(args.out, write_report);
    timer.lap("report");
    if (!err.empty()) {
      std::cerr << "sscs: error: " << err << "\n";
      return kInputError;
    }
    if (!common.quiet) {
      // Keep the summary lines on the terminal when the report goes to a file.
      std::cout << format_text(reports, sources, {common.color_for(stdout), true, args.strict});
    }
  }
  if (!args.html.empty()) {
    if (std::string err = write_file_atomic(args.html, html); !err.empty()) {
      std::cerr << "sscs: error: " << err << "\n";
      return kInputError;
    }
    if (!common.quiet) std::cout << fmt::format("HTML report: {}\n", args.html);
  }
  bool violated = std::any_of(reports.begin(), reports.end(), [&](const VaultReport& r) { return r.violated(args.strict); });
  return violated ? kViolations : kOk;
}

int run_types(const Common& common, const std::string& format, const std::string& out) {
  if ((format == "md") != !out.empty()) {
    std::cerr << (out.empty() ? "sscs: error: --format md writes a catalogue and its thumbnails: give --out FILE.md\n"
                              : "sscs: error: --out is for --format md (the catalogue); text and json print to stdout\n");
    return kInputError;
  }
  if (!out.empty() && std::filesystem::path(out).extension() != ".md") {
    std::cerr << fmt::format("sscs: error: --out expects a .md file, found '{}'\n", out);
    return kInputError;
  }
  Sources sources;
  Diagnostics diag;
  std::vector<std::pair<std::string, SourceMark>> dirs = {{standard_library_dir(), {}}};
  for (const std::string& d : common.library) dirs.push_back({d, {}});
  PluginSet plugins;
  for (const std::string& d : common.plugins) plugins.load_folder(d);  // PluginError: exit 3
  std::vector<ObjectType> types = load_library(dirs, sources, diag, common.package_paths, plugins.types());
  // `types` checks a library: a broken type's errors are input errors here (vaults that do not
  // use it are not affected).
  for (const ObjectType& t : types)
    if (t.broken)
      for (const Diagnostic& d : t.problems)
        if (!d.warning) diag.error(d.mark, d.message);
  if (diag.has_errors()) {
    report_diagnostics(diag, sources, common);
    return kInputError;
  }
  CompileOptions instance_options;
  instance_options.package_paths = common.package_paths;
  if (format == "md") {
    std::string err = write_type_catalogue(out, std::move(types), instance_options, sources, diag);
    if (report_diagnostics(diag, sources, common)) return kInputError;
    if (!err.empty()) {
      std::cerr << "sscs: error: " << err << "\n";
      return kInputError;
    }
    if (!common.quiet) std::cout << fmt::format("wrote {} and its thumbnails in {}\n", out, (std::filesystem::path(out).parent_path() / "img" / "library").string());
    return kOk;
  }
  // The listing instances every type: what that finds in the library's files (a mesh that
  // cannot be read, an SRDF naming no link) fails the command, before anything is printed.
  std::ostringstream listing;
  write_type_listing(listing, std::move(types), plugins, instance_options, format == "json", sources, diag);
  if (report_diagnostics(diag, sources, common)) return kInputError;
  std::cout << listing.str();
  return kOk;
}



}  // namespace sscs::cli
