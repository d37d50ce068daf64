#pragma once
/// Sweep files (cli.md, Sweeps) as written: the vault (and scenario) a study varies, the
/// parameters it varies and how, and the metrics it computes per variant. Values stay text with
/// marks; the sweep stage expands them into variants against the compiled vault.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/source.h"
#include "load/spec.h"

namespace sscs {

/// One entry of `vary`: a range `{from, to, step}` or a list `{values: [...]}`. The names `vault`
/// and `scenario` vary whole files, `library` a type-library folder added for the variant (a
/// device type per variant); their values are paths, relative to the sweep file.
struct VarySpec {
  std::string name;
  SourceMark mark;  ///< of the name
  bool range = false;
  Scalar from, to, step;
  std::vector<Scalar> values;
  bool files() const { return name == "vault" || name == "scenario" || name == "library"; }
};

struct MetricSpec {
  std::string name;
  SourceMark mark;  ///< of the name
  Scalar expr;
};

struct SweepSpec {
  std::string path;
  std::string name;
  SourceMark mark;
  std::string description;
  Scalar vault, scenario;              ///< as written (either may be absent); `campaign:` is read into scenario
  bool campaign = false;               ///< the run file was given as `campaign:`
  std::string vault_path, scenario_path;  ///< resolved against the sweep file's folder
  std::vector<VarySpec> vary;
  bool random = false;                 ///< mode: {random: {n, seed}}; else grid
  Scalar n, seed;
  SourceMark mode_mark;
  std::vector<MetricSpec> metrics;
};

/// Loads a sweep file: every problem found is reported to `diag`.
std::optional<SweepSpec> load_sweep(const std::string& path, Sources& sources, Diagnostics& diag);
/// Loads a sweep already registered in `sources` (tests load sweeps from strings this way).
std::optional<SweepSpec> load_sweep(uint32_t file, Sources& sources, Diagnostics& diag);

}  // namespace sscs
