#pragma once
/// Physical dimensions, unit literals ("300 mm", "90 deg") and conversion to SI.
#include <array>
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <vector>
#include <string_view>

namespace sscs {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kRadPerDeg = kPi / 180;  ///< degrees to radians
inline constexpr double kDegPerRad = 180 / kPi;  ///< radians to degrees
inline constexpr double kStandardGravity = 9.80665;  ///< m/s^2

enum class Dim : uint8_t {
  None,             ///< a plain number
  Length,           ///< m
  Angle,            ///< rad
  Mass,             ///< kg
  Time,             ///< s
  Velocity,         ///< m/s
  AngularVelocity,  ///< rad/s
  Frequency,        ///< Hz
  Fraction,         ///< "50%" is 0.5
};

const char* dim_name(Dim dim);
/// "a length", "an angle": for messages.
std::string a_dim(Dim dim);

/// The unit a plain number means in a file, and the unit reports print: m, deg, kg, s, ...
const char* file_unit(Dim dim);
/// Factor from the file unit to SI: 1 for all but angles (deg -> rad) and fractions.
double file_unit_to_si(Dim dim);

/// The largest length (a location, a size) sscs accepts, in metres: 1000 km. Geometry far
/// beyond it loses the precision collision queries need (and FCL fails near 1e155).
constexpr double kMaxLengthSi = 1e6;
/// The largest angle (an orientation) sscs accepts, in degrees: beyond it a double cannot reduce
/// the angle to a turn precisely (1e300 degrees came out as 93.4).
constexpr double kMaxAngleDeg = 1e6;

/// A value converted to SI with the dimension its unit gave it.
struct Quantity {
  double si = 0;
  Dim dim = Dim::None;
  bool has_unit = false;  ///< written with a unit ("2 ft"), not a plain number
  double unit_si = 0;     ///< the SI value of one of the unit written ("mm": 0.001); 0 when plain
};

/// Parses a plain number ("1.5", "-2e3"). Rejects anything else, including inf and nan.
std::optional<double> parse_number(std::string_view text);

/// Why `text` is a number no double holds: "" when it is not one. `.inf`, `nan` and the like
/// ("it is not a finite number"), and a number, alone or before a unit word ("1e999 m",
/// "1e-400"), beyond a double's range or too close to zero for one.
std::string nonfinite_number(std::string_view text);

/// Parses "1.5", "300 mm", "90deg", "50%". A plain number has Dim::None and its value unchanged;
/// the caller converts it with file_unit_to_si once it knows the dimension. nullopt when the text
/// is neither; *unknown_unit is set when it is a number followed by a word that is no unit.
std::optional<Quantity> parse_quantity(std::string_view text, std::string* unknown_unit = nullptr);

/// A unit word at the start of `text` ("m/s" before "m"), as it would stand after a number: the
/// longest known word there, with its dimension and the SI value of one of it; nullopt for none.
struct UnitWord {
  std::string_view word;
  Dim dim = Dim::None;
  double to_si = 1;
};
std::optional<UnitWord> unit_word_at(std::string_view text);
/// Every unit word sscs reads, as written in files ("m", "mm", ..., "%").
std::vector<std::string> unit_words();

/// The exponents of a dimension in the base quantities length, mass, time and angle (a velocity
/// is {1, 0, -1, 0}); an angle counts as its own base so that `yaw + 0.3 m` is refused.
using DimExponents = std::array<int8_t, 4>;
DimExponents exponents(Dim dim);
/// The Dim with these exponents, if sscs names one (Dim::None for all zero).
std::optional<Dim> dim_with(const DimExponents& e);

/// The unit words sscs knows, for messages.
std::string known_units(Dim dim);

/// Rounds to 12 significant digits so reports stay stable across compilers and diff well.
double stable(double v);

/// SI value -> the number printed in reports (in file units).
inline double si_to_file(double si, Dim dim) { return si / file_unit_to_si(dim); }

/// An SI value as reports print it: in the file unit, with the unit ("90 deg", "1.5 m", "3").
std::string with_unit(double si, Dim dim);

/// A value in file units as messages and listings print it: to 12 significant digits, no more
/// than it takes (-22.9183118052, 0.3, 1e+21), so two values that differ print differently
/// ("{:g}" printed a limit and a value below it both as -22.9183).
std::string number_text(double v);

/// `v` in [lo, hi], allowing the slack of a bound that was printed to 12 significant digits in
/// file units and read back (a relative 1e-9): `v` moved onto the range, or nullopt when it lies
/// outside by more. So a joint limit copied from `sscs types` is accepted as that limit.
std::optional<double> within_bounds(double v, double lo, double hi);

}  // namespace sscs
