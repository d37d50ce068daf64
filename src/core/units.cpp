#include "core/units.h"
#include "core/names.h"

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <algorithm>
#include <numbers>

#include <fmt/compile.h>
#include <fmt/format.h>

namespace sscs {

namespace {
struct Unit {
  const char* word;
  Dim dim;
  double to_si;
};
constexpr Unit kUnits[] = {
    {"m", Dim::Length, 1.0},        {"mm", Dim::Length, 1e-3},        {"cm", Dim::Length, 1e-2},
    {"km", Dim::Length, 1e3},       {"in", Dim::Length, 0.0254},      {"ft", Dim::Length, 0.3048},
    {"yd", Dim::Length, 0.9144},    {"deg", Dim::Angle, kRadPerDeg},        {"rad", Dim::Angle, 1.0},
    {"kg", Dim::Mass, 1.0},         {"g", Dim::Mass, 1e-3},           {"t", Dim::Mass, 1e3},
    {"lb", Dim::Mass, 0.45359237},  {"s", Dim::Time, 1.0},            {"ms", Dim::Time, 1e-3},
    {"min", Dim::Time, 60.0},       {"h", Dim::Time, 3600.0},         {"m/s", Dim::Velocity, 1.0},
    {"mm/s", Dim::Velocity, 1e-3},  {"deg/s", Dim::AngularVelocity, kRadPerDeg},
    {"rad/s", Dim::AngularVelocity, 1.0},                             {"Hz", Dim::Frequency, 1.0},
    {"%", Dim::Fraction, 0.01},
};

}  // namespace

const char* dim_name(Dim dim) {
  switch (dim) {
    case Dim::None: return "number";
    case Dim::Length: return "length";
    case Dim::Angle: return "angle";
    case Dim::Mass: return "mass";
    case Dim::Time: return "time";
    case Dim::Velocity: return "velocity";
    case Dim::AngularVelocity: return "angular velocity";
    case Dim::Frequency: return "frequency";
    case Dim::Fraction: return "fraction";
  }
  return "?";
}

std::string a_dim(Dim dim) {
  std::string n = dim_name(dim);
  return (n[0] == 'a' || n[0] == 'e' || n[0] == 'i' || n[0] == 'o' || n[0] == 'u' ? "an " : "a ") + n;
}

const char* file_unit(Dim dim) {
  switch (dim) {
    case Dim::None: return "";
    case Dim::Length: return "m";
    case Dim::Angle: return "deg";
    case Dim::Mass: return "kg";
    case Dim::Time: return "s";
    case Dim::Velocity: return "m/s";
    case Dim::AngularVelocity: return "deg/s";
    case Dim::Frequency: return "Hz";
    case Dim::Fraction: return "";
  }
  return "";
}

double file_unit_to_si(Dim dim) {
  if (dim == Dim::Angle || dim == Dim::AngularVelocity) return kRadPerDeg;
  return 1.0;
}

std::optional<double> parse_number(std::string_view text) {
  text = trim_blanks(text);
  if (text.empty()) return std::nullopt;
  if (text.front() == '+') text.remove_prefix(1);
  double value = 0;
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || ptr != text.data() + text.size()) return std::nullopt;
  if (!std::isfinite(value)) return std::nullopt;
  return value;
}

namespace {

/// The length of the number at the start of `text` (sign, digits, point, exponent), without a
/// dangling exponent ("1e" before "ex"), 0 when it starts with none.
size_t number_prefix(std::string_view text) {
  size_t i = !text.empty() && (text.front() == '+' || text.front() == '-') ? 1 : 0;
  const size_t start = i;
  while (i < text.size() && ((text[i] >= '0' && text[i] <= '9') || text[i] == '.' || text[i] == 'e' || text[i] == 'E' ||
                             ((text[i] == '-' || text[i] == '+') && i > start && (text[i - 1] == 'e' || text[i - 1] == 'E'))))
    ++i;
  while (i > start && (text[i - 1] == 'e' || text[i - 1] == 'E' || text[i - 1] == '-' || text[i - 1] == '+')) --i;
  return i > start ? i : 0;
}

}  // namespace

std::string nonfinite_number(std::string_view text) {
  text = trim_blanks(text);
  std::string_view bare = text;
  if (!bare.empty() && (bare.front() == '+' || bare.front() == '-')) bare.remove_prefix(1);
  for (std::string_view w : {".nan", ".NaN", ".NAN", "nan", "NaN", "NAN", ".inf", ".Inf", ".INF", "inf", "Inf",
                             "INF", "infinity", "Infinity"})
    if (bare == w) return "it is not a finite number";
  // A number, alone or before one word (a unit), that a double cannot hold.
  const size_t n = number_prefix(text);
  if (n == 0) return "";
  std::string_view rest = trim_blanks(text.substr(n));
  if (!std::all_of(rest.begin(), rest.end(), [](char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '/' || c == '%'; }))
    return "";
  std::string_view number = text.substr(0, n);
  if (number.front() == '+') number.remove_prefix(1);
  double v = 0;
  auto [ptr, ec] = std::from_chars(number.data(), number.data() + number.size(), v);
  if (ec != std::errc::result_out_of_range || ptr != number.data() + number.size()) return "";
  // Out of range: beyond the largest double, or closer to zero than the smallest (an exponent
  // far below zero).
  const size_t e = number.find_first_of("eE");
  const bool tiny = e != std::string_view::npos && e + 1 < number.size() && number[e + 1] == '-';
  return tiny ? fmt::format("{} is too close to zero for a number (the smallest is about 2.2e-308); write 0 if that is meant", number)
              : fmt::format("{} is beyond the range of numbers (about ±1.8e308)", number);
}

std::optional<Quantity> parse_quantity(std::string_view text, std::string* unknown_unit) {
  text = trim_blanks(text);
  if (auto n = parse_number(text)) return Quantity{*n, Dim::None, false};
  // Split the longest numeric prefix from the unit word.
  size_t number_len = number_prefix(text);
  if (number_len == 0) return std::nullopt;
  auto number = parse_number(text.substr(0, number_len));
  if (!number) return std::nullopt;
  std::string_view word = trim_blanks(text.substr(number_len));
  if (word.empty()) return std::nullopt;
  for (const Unit& u : kUnits)
    if (word == u.word) return Quantity{*number * u.to_si, u.dim, true, u.to_si};
  // A number followed by a single word that is not an expression: an unknown unit.
  bool is_word = std::all_of(word.begin(), word.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '/' || c == '%';
  });
  if (is_word && unknown_unit) *unknown_unit = std::string(word);
  return std::nullopt;
}

double stable(double v) {
  if (!std::isfinite(v) || v == 0) return v;
  // Most report values are short decimals (0.8029, 204): a double that is the nearest to a
  // decimal of at most 12 significant digits is its own 12-digit rounding.
  if (std::abs(v) < 1e6) {
    double n = std::nearbyint(v * 1e6);
    if (n / 1e6 == v) return v;
  }
  // to_chars and from_chars round exactly, as printf("%.12g") and strtod do, at a fraction of the cost
  // (reports call this for every number).
  char buf[32];
  auto end = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 12).ptr;  // printf("%.12g")
  double r = 0;
  std::from_chars(buf, end, r);
  return r == 0 ? 0.0 : r;  // no "-0"
}

std::optional<UnitWord> unit_word_at(std::string_view text) {
  std::optional<UnitWord> best;
  for (const Unit& u : kUnits) {
    std::string_view w = u.word;
    if (text.starts_with(w) && (!best || w.size() > best->word.size())) best = UnitWord{w, u.dim, u.to_si};
  }
  return best;
}

std::vector<std::string> unit_words() {
  std::vector<std::string> out;
  for (const Unit& u : kUnits) out.emplace_back(u.word);
  return out;
}

DimExponents exponents(Dim dim) {
  switch (dim) {
    case Dim::Length: return {1, 0, 0, 0};
    case Dim::Mass: return {0, 1, 0, 0};
    case Dim::Time: return {0, 0, 1, 0};
    case Dim::Angle: return {0, 0, 0, 1};
    case Dim::Velocity: return {1, 0, -1, 0};
    case Dim::AngularVelocity: return {0, 0, -1, 1};
    case Dim::Frequency: return {0, 0, -1, 0};
    case Dim::None:
    case Dim::Fraction: return {0, 0, 0, 0};
  }
  return {0, 0, 0, 0};
}

std::optional<Dim> dim_with(const DimExponents& e) {
  for (Dim d : {Dim::None, Dim::Length, Dim::Mass, Dim::Time, Dim::Angle, Dim::Velocity, Dim::AngularVelocity, Dim::Frequency})
    if (exponents(d) == e) return d;
  return std::nullopt;
}

std::string known_units(Dim dim) {
  std::string out;
  for (const Unit& u : kUnits)
    if (dim == Dim::None || u.dim == dim) {
      if (!out.empty()) out += ", ";
      out += u.word;
    }
  return out;
}

std::string number_text(double v) { return fmt::format("{}", stable(v)); }

std::optional<double> within_bounds(double v, double lo, double hi) {
  auto slack = [](double bound) { return 1e-9 * std::max(1.0, std::abs(bound)); };
  if (v < lo) return v >= lo - slack(lo) ? std::optional(lo) : std::nullopt;
  if (v > hi) return v <= hi + slack(hi) ? std::optional(hi) : std::nullopt;
  return v;
}

std::string with_unit(double si, Dim dim) {
  const char* unit = file_unit(dim);
  const std::string number = number_text(si_to_file(si, dim));
  return *unit ? number + " " + unit : number;
}

}  // namespace sscs
