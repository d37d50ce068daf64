#pragma once
/// A sweep's results on disk: each variant's `result.json` (written last, so a folder with one
/// is complete), the table `results.csv` / `results.json` made from them in variant order, and
/// the manifest `sweep.json` that says which sweep a folder holds. `sscs sweep` and
/// `sscs sweep merge` write the table with the same code, so a merged table is byte-identical
/// to the one run in one piece.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/expected.h"

namespace sscs {

/// One row: a variant's outcome.
struct VariantRow {
  size_t index = 0;
  std::string folder;
  std::vector<std::string> values;  ///< per varied parameter, as results.csv shows it
  std::string status;               ///< pass, fail or error
  size_t passed = 0, failed = 0, warnings = 0;
  std::vector<std::optional<double>> metrics;  ///< nullopt: undefined
  std::optional<double> cycle_time;
  std::optional<size_t> collisions;
  std::string message;              ///< why an error, or a metric that could not be computed
};

/// The columns every row has: parameters (with their units), metrics, and run fields when the
/// sweep simulates.
struct TableHeader {
  std::string sweep;
  std::vector<std::pair<std::string, std::string>> parameters;  ///< name, unit ("" for none)
  std::vector<std::string> metrics;
  bool simulated = false;
};

/// Which sweep a folder holds: `sweep.json`.
struct Manifest {
  std::string sweep;
  std::string sweep_sha256;   ///< of the sweep file's bytes
  std::string inputs_sha256;  ///< of every file the sweep read (vaults, scenarios, types), by content
  /// Every input read: its name (relative to the sweep file, or `<library>/...`) and sha256.
  std::vector<std::pair<std::string, std::string>> inputs;
  size_t variants = 0;
  std::string mode;           ///< grid or random
  std::string version;        ///< of sscs
  std::string shard;          ///< "K/N" for a shard's folder, "" for a whole sweep
};

std::string result_json(const VariantRow& row, const TableHeader& header);
/// Reads a variant's result.json; nullopt (with *error) when it is unreadable or not one.
Expected<VariantRow> read_result(const std::string& path, const TableHeader& header);

std::string manifest_json(const Manifest& m);
Expected<Manifest> read_manifest(const std::string& path);

std::string header_json(const TableHeader& h);

/// results.csv: variant, folder, parameters, status, passed, failed, warnings, metrics,
/// [cycle_time, collisions], message. Numbers with 12 significant digits; undefined ones empty.
std::string results_csv(const TableHeader& header, const std::vector<VariantRow>& rows);
/// results.json: the header and the rows.
std::string results_json(const TableHeader& header, const std::vector<VariantRow>& rows);
/// Reads the header back from a results.json (for merge).
Expected<TableHeader> read_header(const std::string& results_json_path);

}  // namespace sscs
