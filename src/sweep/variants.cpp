#include "sweep/variants.h"

#include <cmath>
#include <filesystem>
#include <random>
#include <set>

#include <fmt/format.h>

#include "core/files.h"

namespace fs = std::filesystem;

namespace sscs {

namespace {

constexpr size_t kMaxAxisValues = 1'000'000;

std::string number_text(double si, Dim dim) {
  const char* unit = file_unit(dim);
  double x = stable(si_to_file(si, dim));
  return *unit ? fmt::format("{:.12g} {}", x, unit) : fmt::format("{:.12g}", x);
}

std::string column_text(double si, Dim dim) { return fmt::format("{:.12g}", stable(si_to_file(si, dim))); }

/// Folder-name characters only: letters, digits, '.', '-'; anything else becomes '_', spaces vanish.
std::string label_of(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (c == ' ') continue;
    bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '-';
    out += ok ? c : '_';
  }
  return out.empty() ? "_" : out;
}

/// A quantity of a range end or step; reports what is wrong at its mark.
std::optional<Quantity> range_quantity(const Scalar& s, const VarySpec& v, std::string_view key, Diagnostics& diag) {
  if (!s.present) return std::nullopt;  // reported as missing by the loader
  std::string unknown;
  auto q = s.quoted ? std::nullopt : parse_quantity(s.text, &unknown);
  if (!q) {
    diag.error(s.mark, unknown.empty()
                           ? fmt::format("expected a number or a quantity (e.g. 1.5 m) for {} of '{}', found '{}'", key, v.name, s.text)
                           : fmt::format("unknown unit '{}' in '{}' for {} of '{}'; known units are: {}", unknown, s.text, key,
                                         v.name, known_units(Dim::None)));
  }
  return q;
}

std::optional<Axis> range_axis(const VarySpec& v, Diagnostics& diag) {
  auto from = range_quantity(v.from, v, "from", diag);
  auto to = range_quantity(v.to, v, "to", diag);
  auto step = range_quantity(v.step, v, "step", diag);
  if (!from || !to || !step) return std::nullopt;
  Axis axis;
  axis.spec = &v;
  // Plain numbers take the dimension of the ends written with units.
  const Scalar* first_unit = nullptr;
  for (auto [q, s] : {std::pair{&*from, &v.from}, {&*to, &v.to}, {&*step, &v.step}}) {
    if (!q->has_unit) continue;
    if (!first_unit) {
      first_unit = s;
      axis.dim = q->dim;
      axis.has_unit = true;
    } else if (q->dim != axis.dim) {
      diag.error(s->mark, fmt::format("'{}' is {}, but '{}' is {}: the range of '{}' mixes dimensions", s->text,
                                      a_dim(q->dim), first_unit->text, a_dim(axis.dim), v.name));
      return std::nullopt;
    }
  }
  // The range is stepped in the file unit of its dimension (degrees, not radians), so values
  // are round where the user wrote round numbers. A plain number takes the unit written on the
  // first value that has one: {from: 100 mm, to: 300 mm, step: 100} steps by 100 mm.
  double unit = file_unit_to_si(axis.dim);
  const double plain_unit = first_unit ? parse_quantity(first_unit->text)->unit_si : unit;
  auto in_file_unit = [&](const Quantity& q) { return (q.has_unit ? q.si : q.si * plain_unit) / unit; };
  double a = in_file_unit(*from), b = in_file_unit(*to), d = in_file_unit(*step);
  if (!(d > 0)) {
    diag.error(v.step.mark, fmt::format("the step of '{}' must be greater than 0, found '{}'", v.name, v.step.text));
    return std::nullopt;
  }
  if (b < a) {
    diag.error(v.to.mark, fmt::format("the range of '{}' ends ('{}') before it starts ('{}')", v.name, v.to.text, v.from.text));
    return std::nullopt;
  }
  if ((b - a) / d >= kMaxAxisValues) {
    diag.error(v.step.mark, fmt::format("the range of '{}' has more than {} values; use a larger step", v.name, kMaxAxisValues));
    return std::nullopt;
  }
  for (double x : range_values(a, b, d)) {
    AxisValue value;
    value.number = true;
    value.si = x * unit;
    value.set_text = number_text(value.si, axis.dim);
    value.column = column_text(value.si, axis.dim);
    value.label = label_of(value.set_text);
    value.mark = v.from.mark;
    axis.values.push_back(value);
  }
  return axis;
}

std::optional<Axis> list_axis(const VarySpec& v, const std::string& sweep_path, Diagnostics& diag) {
  Axis axis;
  axis.spec = &v;
  const Scalar* first_unit = nullptr;
  std::set<std::string> seen;
  for (const Scalar& s : v.values) {
    AxisValue value;
    value.mark = s.mark;
    if (!seen.insert(s.text).second) {
      diag.error(s.mark, fmt::format("'{}' is listed twice in the values of '{}'", s.text, v.name));
      continue;
    }
    if (v.files()) {
      fs::path p(s.text);
      value.set_text = join_path(fs::path(sweep_path).parent_path().string(), p.string());
      value.column = s.text;
      value.label = label_of(p.stem().string());
      axis.values.push_back(value);
      continue;
    }
    auto q = s.quoted ? std::nullopt : parse_quantity(s.text);
    if (q && q->has_unit) {
      if (!first_unit) {
        first_unit = &s;
        axis.dim = q->dim;
        axis.has_unit = true;
      } else if (q->dim != axis.dim) {
        diag.error(s.mark, fmt::format("'{}' is {}, but '{}' is {}: the values of '{}' mix dimensions", s.text, a_dim(q->dim),
                                       first_unit->text, a_dim(axis.dim), v.name));
        continue;
      }
    }
    value.number = q.has_value();
    value.si = q ? q->si : 0;
    value.set_text = s.text;
    value.column = q && q->has_unit ? column_text(q->si, q->dim) : s.text;
    value.label = label_of(s.text);
    axis.values.push_back(value);
  }
  // Plain numbers beside numbers with units are in the file unit of that dimension.
  if (axis.has_unit)
    for (size_t i = 0; i < axis.values.size(); ++i) {
      AxisValue& value = axis.values[i];
      auto q = parse_quantity(value.set_text);
      if (value.number && q && !q->has_unit) value.si = q->si * file_unit_to_si(axis.dim);
    }
  return axis;
}

/// Mixed-radix digits of grid point `g`, the last axis fastest.
std::vector<uint32_t> choice_of(uint64_t g, const std::vector<Axis>& axes) {
  std::vector<uint32_t> choice(axes.size());
  for (size_t a = axes.size(); a-- > 0;) {
    uint64_t n = axes[a].values.size();
    choice[a] = static_cast<uint32_t>(g % n);
    g /= n;
  }
  return choice;
}

}  // namespace

std::vector<double> range_values(double from, double to, double step) {
  std::vector<double> out;
  double span = (to - from) / step;
  auto count = static_cast<size_t>(std::floor(span + 1e-9 * std::max(1.0, span))) + 1;
  out.reserve(count);
  for (size_t i = 0; i < count; ++i) out.push_back(stable(from + static_cast<double>(i) * step));
  return out;
}

std::string VariantSet::folder(const Variant& v) const {
  size_t width = fmt::format("{}", variants.empty() ? 0 : variants.size() - 1).size();
  std::string name = fmt::format("{:0{}}", v.index, width);
  for (size_t a = 0; a < axes.size(); ++a) name += fmt::format("-{}={}", label_of(axes[a].spec->name), value(v, a).label);
  if (name.size() > 120) name.resize(120);
  return name;
}

std::optional<std::pair<uint64_t, uint64_t>> random_draw(const SweepSpec& spec, Diagnostics& diag) {
  auto whole = [&](const Scalar& s, std::string_view what, double min) -> std::optional<uint64_t> {
    auto x = parse_number(s.text);
    if (!x || *x != std::floor(*x) || *x < min || *x > 9e15) {
      diag.error(s.mark, fmt::format("expected a whole number of at least {} for {}, found '{}'", min, what, s.text));
      return std::nullopt;
    }
    return static_cast<uint64_t>(*x);
  };
  auto n = whole(spec.n, "random n", 1);
  auto seed = whole(spec.seed, "random seed", 0);
  if (!n || !seed) return std::nullopt;
  return std::pair{*n, *seed};
}

std::vector<Axis> expand_axes(const SweepSpec& spec, Diagnostics& diag) {
  std::vector<Axis> axes;
  for (const VarySpec& v : spec.vary) {
    auto axis = v.range ? range_axis(v, diag) : list_axis(v, spec.path, diag);
    if (axis && !axis->values.empty()) axes.push_back(std::move(*axis));
  }
  return axes;
}

std::optional<VariantSet> expand_variants(const SweepSpec& spec, Diagnostics& diag) {
  auto axes = expand_axes(spec, diag);
  if (axes.empty() || diag.has_errors()) return std::nullopt;
  return expand_variants(spec, std::move(axes), diag);
}

std::optional<VariantSet> expand_variants(const SweepSpec& spec, std::vector<Axis> axes, Diagnostics& diag) {
  VariantSet set;
  set.axes = std::move(axes);
  uint64_t grid = 1;
  for (const Axis& a : set.axes) {
    uint64_t n = a.values.size();
    grid = grid > std::numeric_limits<uint64_t>::max() / n ? std::numeric_limits<uint64_t>::max() : grid * n;
  }
  std::vector<uint64_t> points;
  if (!spec.random) {
    if (grid > kMaxGridVariants) {
      diag.error(spec.mode_mark, fmt::format("the grid has {} variants, more than the {} sscs runs; use mode: {{random: "
                                             "{{n: N, seed: S}}}} or fewer values", grid, kMaxGridVariants));
      return std::nullopt;
    }
    for (uint64_t g = 0; g < grid; ++g) points.push_back(g);
  } else {
    auto draw = random_draw(spec, diag);
    if (!draw) return std::nullopt;
    const auto [n, seed] = *draw;
    if (n > grid || n > kMaxGridVariants) {
      diag.error(spec.n.mark, fmt::format("random n = {} is more than the {} variants of the grid; use mode: grid",
                                          n, grid));
      return std::nullopt;
    }
    // Floyd's sampling of n distinct points: mt19937_64's sequence is fixed by the C++ standard,
    // and `%` (not a library distribution) maps it, so every platform draws the same points.
    std::mt19937_64 rng(seed);
    std::set<uint64_t> chosen;
    for (uint64_t j = grid - n; j < grid; ++j) {
      uint64_t t = rng() % (j + 1);
      if (!chosen.insert(t).second) chosen.insert(j);
    }
    points.assign(chosen.begin(), chosen.end());
  }
  set.variants.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) set.variants.push_back({i, choice_of(points[i], set.axes)});
  return set;
}

}  // namespace sscs
