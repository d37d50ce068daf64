#pragma once
/// A sweep's variants: each `vary` entry expanded into its values (an axis), and the variants
/// as choices of one value per axis, in a stable order: every machine that expands the same
/// sweep file gets the same variants with the same indices and folder names.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/units.h"
#include "load/sweep.h"

namespace sscs {

/// One value of a varied parameter (or file).
struct AxisValue {
  std::string set_text;  ///< what `--set NAME=TEXT` would take ("1.1 m", "4"); for files the resolved path
  std::string column;    ///< in results.csv: a plain number in file units, a string, a file as written
  std::string label;     ///< in folder names: "1.1m", "arm6", a file's stem
  SourceMark mark;       ///< where it was written (for a range: the `from` of its entry)
  bool number = false;
  double si = 0;
};

struct Axis {
  const VarySpec* spec = nullptr;
  Dim dim = Dim::None;  ///< of numbers with units (None for plain numbers, strings and files)
  bool has_unit = false;
  std::vector<AxisValue> values;
};

struct Variant {
  size_t index = 0;                ///< 0-based, in sweep order
  std::vector<uint32_t> choice;    ///< per axis: the index of its value
};

class VariantSet {
 public:
  std::vector<Axis> axes;
  std::vector<Variant> variants;

  /// The variant's folder name: its index, zero-padded to the width of the largest index, and
  /// its values, e.g. "007-aisle=1.3m-rows=4" (only [A-Za-z0-9._=-]; at most 120 characters).
  std::string folder(const Variant& v) const;
  const AxisValue& value(const Variant& v, size_t axis) const { return axes[axis].values[v.choice[axis]]; }
};

/// The largest grid sscs expands (a random sweep may draw from a larger one).
constexpr uint64_t kMaxGridVariants = 10'000'000;

/// Expands the sweep's axes and variants: a grid (every combination, the last `vary` entry
/// changing fastest) or `n` distinct grid points drawn with `seed`, listed in grid order.
/// Problems (units that disagree, an empty range, n larger than the grid) go to `diag`.
std::optional<VariantSet> expand_variants(const SweepSpec& spec, Diagnostics& diag);

/// The two halves of expand_variants: the values of each `vary` entry that expands (one that
/// does not is reported and left out, so the others can still be checked against the vault),
/// and the variants the mode draws from them.
std::vector<Axis> expand_axes(const SweepSpec& spec, Diagnostics& diag);
std::optional<VariantSet> expand_variants(const SweepSpec& spec, std::vector<Axis> axes, Diagnostics& diag);
/// A random mode's `n` and `seed`, each a whole number (n ≥ 1), or nullopt with the errors in `diag`.
std::optional<std::pair<uint64_t, uint64_t>> random_draw(const SweepSpec& spec, Diagnostics& diag);

/// The values of a range {from, to, step} in SI: from, from + step, ... up to `to`, which is
/// included when it falls on a step within a relative 1e-9 of the step; each value rounded to 12
/// significant digits (so 0.1 steps give 1.3, not 1.3000000000000003).
std::vector<double> range_values(double from, double to, double step);

}  // namespace sscs
