#pragma once
/// The sscs command line: a small table of subcommands over libsscs.
namespace sscs {
/// Runs sscs with the given arguments; returns the exit status of cli.md (0, 1, 2, 3).
int run_cli(int argc, char** argv);
}  // namespace sscs
