#pragma once
/// What the subcommands of the command line share: the options every one takes, each one's
/// arguments, the exit statuses, and the runners the table in commands.cpp calls.
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <fmt/format.h>

#include "compile/compile.h"
#include "core/data_dirs.h"
#include "core/diagnostics.h"
#include "core/files.h"

namespace sscs {
struct SweepOutcome;
}

namespace sscs::cli {

/// Exit statuses of cli.md.
constexpr int kOk = 0, kViolations = 1, kInputError = 2, kInternalError = 3;

/// Options every subcommand takes.
struct Common {
  std::vector<std::string> library;
  std::vector<std::string> plugins;
  std::vector<std::string> package_paths;
  std::vector<std::string> set;
  bool quiet = false;
  bool allow_vault_plugins = false;
  std::vector<std::string> roots;  // --root
  bool allow_outside_root = false;
  std::string color = "auto";

  /// The options every command takes; `with_set` false for commands that read no vault (types).
  void add_to(CLI::App* app, bool with_set = true) {
    app->add_option("--library", library, "extra type-library folder (repeatable)");
    app->add_option("--plugins", plugins, "load the plugins in this folder (repeatable)");
    app->add_flag("--allow-vault-plugins", allow_vault_plugins, "also load the folders a vault's plugins: key names");
    app->add_option("--package-path", package_paths, "folder of ROS packages for URDF package:// references (repeatable)");
    app->add_option("--root", roots, "a folder files named inside input files may come from, besides the project root "
                                     "(the git work tree holding the input, else its folder); repeatable");
    app->add_flag("--allow-outside-root", allow_outside_root, "let input files name files outside the project root");
    if (with_set) app->add_option("--set", set, "parameter override NAME=VALUE (repeatable)");
    app->add_flag("--quiet", quiet, "print only summaries and errors");
    app->add_option("--color", color, "colour output: auto, always or never")
        ->check(CLI::IsMember({"auto", "always", "never"}));
  }
  /// Confines what files named inside `input` may read: its project root first (the one messages
  /// name), the --root folders, the standard library and the folders given as options.
  void confine_to(const std::string& input) const { confine_to_projects({project_root_of(input)}); }
  /// The same for the project roots `projects` (of the files an editor has open: `sscs lsp`).
  void confine_to_projects(const std::vector<std::string>& projects) const {
    if (allow_outside_root) return;
    std::vector<std::string> allowed = projects;
    allowed.insert(allowed.end(), roots.begin(), roots.end());
    allowed.push_back(data_dir("library"));
    for (const auto* dirs : {&library, &plugins, &package_paths}) allowed.insert(allowed.end(), dirs->begin(), dirs->end());
    for (const std::string& dir : ros_package_path()) allowed.push_back(dir);
    confine_reads(allowed);
  }
  bool color_for(FILE* stream) const {
    if (color == "always") return true;
    if (color == "never") return false;
    return isatty(fileno(stream)) && std::getenv("NO_COLOR") == nullptr;
  }
  /// The options in `options`, and the folders files named inside `inputs` (the files or run
  /// folder the command line names) may come from: the project root, the standard library and
  /// the folders given as options. A malformed --set NAME=VALUE is an input error.
  bool apply(CompileOptions& options, const std::vector<std::string>& inputs) const {
    for (const auto& [option, dirs] : {std::pair{"--root", &roots}, std::pair{"--package-path", &package_paths}})
      for (const std::string& r : *dirs) {
        std::error_code ec;
        if (!std::filesystem::is_directory(r, ec)) {
          std::cerr << fmt::format("sscs: error: {} '{}' is no folder\n", option, r);
          return false;
        }
      }
    std::vector<std::string> projects;  // every input's (each call replaced the last one's)
    for (const std::string& input : inputs) projects.push_back(project_root_of(input));
    if (!inputs.empty()) confine_to_projects(projects);
    for (const std::string& s : set) {
      auto eq = s.find('=');
      if (eq == std::string::npos || eq == 0) {
        std::cerr << fmt::format("sscs: error: --set expects NAME=VALUE, found '{}'\n", s);
        return false;
      }
      options.overrides.emplace_back(s.substr(0, eq), s.substr(eq + 1));
    }
    options.library_dirs = library;
    options.plugin_dirs = plugins;
    options.allow_vault_plugins = allow_vault_plugins;
    options.package_paths = package_paths;
    return true;
  }
};

struct ServeArgs {
  std::string file;
  std::string host = "127.0.0.1";  ///< loopback unless asked
  int port = 8765;                 ///< 0: any free port (printed)
};

struct CheckArgs {
  std::vector<std::string> vaults;
  std::string format;
  std::string out;
  bool strict = false;
  std::string baseline;
  std::string html;  ///< --html FILE: the self-contained HTML report too
};

struct RenderArgs {
  std::string vault, out, eye, target, camera, size = "1280x720";
  std::string walls = "auto";  ///< auto | solid | see-through
  bool shadows = false;
  double fov = 0;  ///< 0: not given (45, or the named camera's)
};

struct ReplayArgs {
  std::string run, out, camera, size;
  std::string walls = "solid";  ///< solid | see-through
  bool shadows = false;
  bool force = false;  // replace an earlier replay in --out
};

struct SimulateArgs {
  std::string scenario;
  std::string out;     // default: run-<scenario name> unless only a bundle is asked for
  std::string bundle;
  bool no_frames = false;
  std::string video;
  std::string walls = "solid";  ///< solid | see-through
  bool shadows = false;
  bool force = false;  // replace an existing run folder or bundle
  std::optional<std::string> wall_limit;  // s of wall-clock time (none when not given)
  std::string html;  // --html FILE: the run's HTML report
};

struct SweepArgs {
  std::string sweep;
  std::string out;
  unsigned jobs = 0;
  std::string shard;
  bool force = false;
  bool resume = true;
  double variant_timeout = 0;
  double variant_memory = 0;
  std::vector<std::string> merge_dirs;
  std::string html;  // --html FILE: the results' HTML report
};


/// Writes the diagnostics to stderr, warnings then errors; true when there were errors (the
/// command then stops, having written nothing).
bool report_diagnostics(const Diagnostics& diag, const Sources& sources, const Common& common);
/// "WIDTHxHEIGHT" within 16..8192; false (with the message printed) otherwise.
bool parse_size(const std::string& text, int& width, int& height);
/// Why `--html FILE` may not be written, or "" when it may (checked before anything is written):
/// not a .html file, a folder, in no folder, or one of the command's other `outputs`.
std::string html_target_refusal(const std::string& html, const std::vector<std::string>& outputs);
/// "x,y,z" -> a vector; false when it is not three numbers.
bool parse_vec3(const std::string& text, Eigen::Vector3d& v);

/// Set by SIGINT and SIGTERM while an InterruptGuard lives.
extern volatile std::sig_atomic_t g_interrupted;
/// While alive, SIGINT and SIGTERM set g_interrupted (a run stops cleanly, writing nothing half);
/// the handlers before it come back when it goes.
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

 private:
  struct sigaction old_int_ = {}, old_term_ = {};
};


// The subcommands (check.cpp, render.cpp, simulate.cpp, sweep.cpp): each returns its exit status.
int run_check(const Common& common, const CheckArgs& args);
/// `sscs serve VAULT`: the live design view (serve.cpp); returns when stopped (Ctrl-C).
int run_serve(const Common& common, const ServeArgs& args);
int run_lsp(const Common& common);
int run_types(const Common& common, const std::string& format, const std::string& out);
int run_export(const Common& common, const std::string& vault, const std::string& out);
int run_render(const Common& common, const RenderArgs& args);
int run_replay(const Common& common, const ReplayArgs& args);
/// `sscs report RUN|SWEEP|REPORT.json --html FILE`: the HTML report of an existing output.
int run_report(const Common& common, const std::string& input, const std::string& html);
int run_simulate(const Common& common, const SimulateArgs& args);
int run_compare(const std::vector<std::string>& paths, const std::string& format);
int run_sweep_command(const Common& common, const SweepArgs& args);
/// The exit status and summary line of a sweep or a merge (`verb`: "swept", "merged").
int report_sweep(const SweepOutcome& o, const char* verb);

}  // namespace sscs::cli
