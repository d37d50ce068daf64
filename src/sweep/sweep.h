#pragma once
/// The sweep stage: a sweep file -> its variants, each compiled (from the specs parsed once),
/// checked and optionally simulated in a process of its own, -> results.csv / results.json.
/// `merge_sweep` joins the folders of shards into the table one unsharded run would write.
#include <csignal>
#include <memory>
#include <string>
#include <vector>

#include "compile/compile.h"
#include "core/diagnostics.h"
#include "core/source.h"
#include "sweep/progress.h"

namespace sscs {

struct SweepOptions {
  std::string out;                 ///< the results folder (default: sweep-<name>)
  unsigned jobs = 0;               ///< variants at once; 0: one per core
  unsigned shard = 0, shards = 1;  ///< run variants whose index % shards == shard
  bool force = false;              ///< redo variants already complete in `out`
  double variant_timeout = 0;      ///< s; 0: none
  double variant_memory_gb = 0;    ///< address space a variant's worker may take; 0: the machine's memory / jobs
  CompileOptions compile;          ///< --library, --plugins, --set (before each variant's values)
  ProgressBar::Mode progress = ProgressBar::Mode::None;
  const volatile std::sig_atomic_t* interrupted = nullptr;
};

struct SweepOutcome {
  /// OutputError: a result could not be written (a full disk): nothing incomplete is kept.
  enum class End { Done, InputError, Interrupted, Failed, OutputError } end = End::Done;
  size_t variants = 0;   ///< in the sweep (all shards)
  size_t mine = 0;       ///< in this shard
  size_t resumed = 0;    ///< complete already, skipped
  size_t pass = 0, fail = 0, error = 0;
  std::string out;
  std::string message;   ///< for InputError without diagnostics, Interrupted and Failed
};

/// Runs a sweep. Input errors of the sweep file and of what it names (vaults, scenarios, values,
/// metrics) are reported to `diag` before anything is written.
SweepOutcome run_sweep(const std::string& path, const SweepOptions& options, Sources& sources, Diagnostics& diag);

/// Joins shard folders into `out`: their variant folders and the table, byte-identical to an
/// unsharded run's. Refuses folders of different sweeps or inputs, and missing or duplicate
/// variants (InputError with the message).
SweepOutcome merge_sweep(const std::vector<std::string>& dirs, const std::string& out);

}  // namespace sscs
