#include "cli/commands.h"

#include <algorithm>
#include <functional>
#include <iostream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "cli/subcommands.h"
#include "core/files.h"
#include "core/limits.h"
#include "plugin/plugins.h"
#include "render/gl.h"
#include "sweep/sweep.h"

namespace sscs {

using namespace cli;

int run_cli(int argc, char** argv) {
  try {
    CLI::App app{"sscs: the Storage Simulation Construction Set"};
    app.set_version_flag("--version", std::string("sscs ") + SSCS_VERSION);
    app.require_subcommand(1);
    Common common;
    // The subcommands: each its options and what it runs (one of them runs).
    struct Command {
      CLI::App* app;
      std::function<int()> run;
    };
    std::vector<Command> commands;
    auto command = [&](const char* name, const char* help, std::function<int()> run) {
      commands.push_back({app.add_subcommand(name, help), std::move(run)});
      return commands.back().app;
    };

    CheckArgs check_args;
    CLI::App* check_cmd = command("check", "compile each vault and check its constraints", [&] { return run_check(common, check_args); });
    check_cmd->add_option("VAULT", check_args.vaults, "vault files")->required();
    check_cmd->add_option("--format", check_args.format,
                          "text, json, junit or sarif (default: from --out's extension .json/.xml/.sarif, else text)")
        ->check(CLI::IsMember({"text", "json", "junit", "sarif"}));
    check_cmd->add_option("--out", check_args.out, "write the report to this file (atomically)");
    check_cmd->add_flag("--strict", check_args.strict, "failed warnings fail the gate too, and input warnings are input errors");
    check_cmd->add_option("--baseline", check_args.baseline, "classify results against an earlier report (--format json): new failure, fixed, still failing, "
                    "unchanged; exit 1 only for new failures");
    check_cmd->add_option("--html", check_args.html, "also write the self-contained HTML report (table and 3D view) to this file");
    common.add_to(check_cmd);

    ServeArgs serve_args;
    CLI::App* serve_cmd = command("serve", "the live design view: a vault's check report on a local port, checked again and "
                                           "pushed into the open page at every save", [&] { return run_serve(common, serve_args); });
    serve_cmd->add_option("VAULT", serve_args.file, "vault file")->required();
    serve_cmd->add_option("--port", serve_args.port, "port (default 8765; 0: any free one, printed)");
    serve_cmd->add_option("--host", serve_args.host, "address to listen on (default 127.0.0.1: this machine only)");
    common.add_to(serve_cmd);

    CLI::App* lsp_cmd = command("lsp", "a Language Server Protocol server on stdin and stdout for editors: diagnostics as you type, "
                                       "hover, definition, completion, symbols", [&] { return run_lsp(common); });
    common.add_to(lsp_cmd, false);

    std::string types_format = "text", types_out;
    CLI::App* types_cmd = command("types", "list the object types, devices and constraint kinds", [&] { return run_types(common, types_format, types_out); });
    types_cmd->add_option("--format", types_format, "text, json, or md: the catalogue (with thumbnails; needs --out)")
        ->check(CLI::IsMember({"text", "json", "md"}));
    types_cmd->add_option("--out", types_out, "with --format md: the catalogue's file (thumbnails go to img/library/ beside it)");
    common.add_to(types_cmd, /*with_set=*/false);  // types reads no vault: --set would do nothing

    std::string export_vault, export_out;
    CLI::App* export_cmd = command("export", "the composed workcell, or a run with its motion, as one 3D file (glb, gltf, obj, stl)",
                                   [&] { return run_export(common, export_vault, export_out); });
    export_cmd->add_option("VAULT", export_vault, "vault file, or a run folder or bundle (.zip): its motion as a glTF animation")->required();
    export_cmd->add_option("--out", export_out, "output file: .glb, .gltf (with cameras and a run's animation), .obj or .stl")->required();
    common.add_to(export_cmd);

    SimulateArgs sim_args;
    CLI::App* sim_cmd = command("simulate", "run a scenario in ODE physics and write its logs", [&] { return run_simulate(common, sim_args); });
    sim_cmd->add_option("SCENARIO", sim_args.scenario, "scenario file")->required();
    sim_cmd->add_option("--out", sim_args.out, "output folder (default: run-<scenario> unless --bundle), replaced atomically");
    sim_cmd->add_option("--bundle", sim_args.bundle, "write the run as one zip archive too (or only, without --out)");
    sim_cmd->add_flag("--no-frames", sim_args.no_frames, "do not render the scenario's frames");
    sim_cmd->add_option("--video", sim_args.video, "also encode the frames as an H.264 .mp4 through ffmpeg (when installed)");
    sim_cmd->add_flag("--shadows", sim_args.shadows, "frames with shadows of the key light");
    sim_cmd->add_option("--walls", sim_args.walls, "frames with the walls between the eye and the vault solid (default) or see-through")
        ->check(CLI::IsMember({"solid", "see-through"}));
    sim_cmd->add_flag("--force", sim_args.force, "replace an existing run folder or bundle (never replaced without it)");
    sim_cmd->add_option("--wall-limit", sim_args.wall_limit, "seconds of wall-clock time the run may take; past it the run "
                        "stops as failed with a wall_limit event (default: no limit; sim.limit bounds simulated time)");
    sim_cmd->add_option("--html", sim_args.html, "also write the run's self-contained HTML report (animated 3D, events, plots) to this file");
    common.add_to(sim_cmd);

    RenderArgs render_args;
    CLI::App* render_cmd = command("render", "one still image of a vault (PNG, offscreen OpenGL)", [&] { return run_render(common, render_args); });
    render_cmd->add_option("VAULT", render_args.vault, "vault file")->required();
    render_cmd->add_option("--out", render_args.out, "output .png file")->required();
    render_cmd->add_option("--eye", render_args.eye, "camera position x,y,z (m); default: a three-quarter view framing the vault");
    render_cmd->add_option("--target", render_args.target, "point looked at x,y,z (m); default: the vault's centre");
    render_cmd->add_option("--fov", render_args.fov, "vertical field of view, degrees (default 45, or the named camera's)");
    render_cmd->add_option("--camera", render_args.camera, "a named camera of the vault (its cameras: mapping)");
    render_cmd->add_flag("--shadows", render_args.shadows, "shadows of the key light");
    render_cmd->add_option("--walls", render_args.walls,
                           "walls between the eye and the vault: see-through or solid; auto (default): see-through for the "
                           "default view and a camera named overview")
        ->check(CLI::IsMember({"auto", "solid", "see-through"}));
    render_cmd->add_option("--size", render_args.size, "WIDTHxHEIGHT in pixels (default 1280x720)");
    common.add_to(render_cmd);

    ReplayArgs replay_args;
    CLI::App* replay_cmd = command("replay", "render a recorded run's frames again, from its logs", [&] { return run_replay(common, replay_args); });
    replay_cmd->add_option("RUN", replay_args.run, "run folder written by sscs simulate")->required();
    replay_cmd->add_option("--out", replay_args.out, "output folder (frames/ and index.csv)")->required();
    replay_cmd->add_option("--camera", replay_args.camera, "camera file (sscs: 1, cameras: [...]); default: the run's cameras");
    replay_cmd->add_option("--size", replay_args.size, "WIDTHxHEIGHT (default: the run's frame size)");
    replay_cmd->add_flag("--shadows", replay_args.shadows, "frames with shadows of the key light");
    replay_cmd->add_option("--walls", replay_args.walls, "frames with the walls between the eye and the vault solid (default) or see-through")
        ->check(CLI::IsMember({"solid", "see-through"}));
    replay_cmd->add_flag("--force", replay_args.force, "replace an earlier replay in --out (nothing else is ever replaced)");
    common.add_to(replay_cmd);

    std::string report_input, report_html;
    CLI::App* report_cmd = command("report", "the self-contained HTML report of an existing run, sweep or check report",
                                   [&] { return run_report(common, report_input, report_html); });
    report_cmd->add_option("INPUT", report_input, "a run folder or bundle (.zip), a sweep folder, or a check's JSON report")->required();
    report_cmd->add_option("--html", report_html, "the HTML file to write")->required();
    common.add_to(report_cmd);

    std::vector<std::string> compare_runs;
    std::string compare_format = "text";
    CLI::App* compare_cmd = command("compare", "summaries of simulation runs side by side", [&] { return run_compare(compare_runs, compare_format); });
    compare_cmd->add_option("RUN", compare_runs, "run folders or bundles (.zip) written by sscs simulate")->required();
    compare_cmd->add_option("--format", compare_format, "text, json or csv")->check(CLI::IsMember({"text", "json", "csv"}));

    SweepArgs sweep_args;
    std::string merge_out;
    CLI::App* merge_cmd = nullptr;
    CLI::App* sweep_cmd = command("sweep", "run a parameter study: every variant checked (and simulated), one table", [&] {
      if (merge_cmd->parsed()) return report_sweep(merge_sweep(sweep_args.merge_dirs, merge_out), "merged");
      if (sweep_args.sweep.empty()) {
        std::cerr << "sscs: error: sweep needs a sweep file (sscs sweep SWEEP) or merge (sscs sweep merge DIR... --out DIR)\n";
        return kInputError;
      }
      if (!sweep_args.resume) sweep_args.force = true;
      return run_sweep_command(common, sweep_args);
    });
    sweep_cmd->add_option("SWEEP", sweep_args.sweep, "sweep file");
    sweep_cmd->add_option("--out", sweep_args.out, "results folder (default: sweep-<name>); a rerun into it resumes");
    sweep_cmd->add_option("--jobs,-j", sweep_args.jobs, "variants at once (default: one per core)")->check(CLI::Range(1u, 4096u));
    sweep_cmd->add_option("--shard", sweep_args.shard, "K/N: run only the variants whose index % N == K (a Slurm array task)");
    sweep_cmd->add_flag("--resume,!--no-resume", sweep_args.resume, "skip variants already complete in --out (the default)");
    sweep_cmd->add_flag("--force", sweep_args.force, "redo every variant (clears --out)");
    sweep_cmd->add_option("--variant-timeout", sweep_args.variant_timeout, "seconds a variant may take before it is stopped and recorded as error (default: no limit)");
    sweep_cmd->add_option("--variant-memory", sweep_args.variant_memory, "GB of memory a variant may take before it is recorded as error (default: the machine's memory shared by the jobs, at least 1)");
    sweep_cmd->add_option("--html", sweep_args.html, "also write the results' self-contained HTML report (table, plots) to this file");
    common.add_to(sweep_cmd);
    merge_cmd = sweep_cmd->add_subcommand("merge", "join shard folders into one table, as one run would have written it");
    merge_cmd->add_option("DIR", sweep_args.merge_dirs, "shard folders (--out of each sscs sweep --shard K/N)")->required();
    merge_cmd->add_option("--out", merge_out, "the merged folder")->required();

    // A word where the command goes that is no command: say so, not "A subcommand is required".
    std::vector<std::string> names;
    for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
    if (argc > 1 && argv[1][0] != '-' && std::find(names.begin(), names.end(), argv[1]) == names.end()) {
      std::cerr << fmt::format("sscs: error: '{}' is not a command; the commands are {} (sscs --help)\n", printable(argv[1]),
                               fmt::join(names, ", "));
      return kInputError;
    }
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      int code = app.exit(e);
      return code == 0 ? kOk : kInputError;
    }
    if (std::string error = limit_environment_error(); !error.empty()) {
      std::cerr << "sscs: error: " << error << "\n";
      return kInputError;
    }
    for (const Command& c : commands)
      if (c.app->parsed()) return c.run();
    return kInputError;
  } catch (const OutputError& e) {  // a full disk, an unwritable folder: the same in every command
    std::cerr << "sscs: error: " << e.what() << "\n";
    return kInputError;
  } catch (const PluginError& e) {
    std::cerr << "sscs: error: " << e.what() << "\n";
    return kInternalError;
  } catch (const gl::RenderUnavailable& e) {
    std::cerr << "sscs: error: " << e.what() << "\n";
    return kInternalError;
  } catch (const std::exception& e) {
    std::cerr << "sscs: internal error: " << e.what() << "\n";
    return kInternalError;
  }
}

}  // namespace sscs
