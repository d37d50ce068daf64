#include "compile/templates.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>
#include <fmt/format.h>

#include "core/pose.h"
#include "core/units.h"

namespace sscs {

double ValueRef::eval(const double* attributes_si, double fallback, const double* counters) const {
  if (!present) return fallback;
  if (!expr) return constant;
  // Few names (a shape's size reads one or two attributes): on the stack.
  std::array<double, 16> small;
  std::vector<double> large;
  double* inputs = small.data();
  if (attributes.size() > small.size()) {
    large.resize(attributes.size());
    inputs = large.data();
  }
  for (size_t k = 0; k < attributes.size(); ++k) {
    const int a = attributes[k];
    inputs[k] = a < 0 ? NAN : a < kCounter ? attributes_si[a] : counters ? counters[a - kCounter] : NAN;
  }
  return expr->evaluate(inputs);
}

Eigen::Vector3d VectorRef::eval(const double* attributes_si, double fallback, const double* counters) const {
  return {v[0].eval(attributes_si, fallback, counters), v[1].eval(attributes_si, fallback, counters),
          v[2].eval(attributes_si, fallback, counters)};
}

Eigen::Isometry3d PoseRef::eval(const double* attributes_si, const double* counters) const {
  return make_pose(xyz.eval(attributes_si, 0, counters), rpy.eval(attributes_si, 0, counters));
}

std::string RepeatTemplate::problem(const double* attributes_si) const {
  double copies = 1;
  for (const Counter& c : counters) {
    const double n = c.count.eval(attributes_si, NAN);
    if (!(n >= 0 && n <= kMaxCopies && n == std::floor(n)))
      return fmt::format("the count of repeat counter '{}' ({}) is {}, expected a whole number from 0 to {:g}", c.name, c.count.text,
                         number_text(n), kMaxCopies);
    copies *= n;
  }
  if (copies > kMaxCopies)
    return fmt::format("its repeat makes {:g} copies, more than the {:g} sscs makes of one entry", copies, kMaxCopies);
  for (const Counter& c : counters)
    if (!c.pitch.eval(attributes_si, 0).allFinite())
      return fmt::format("the pitch of repeat counter '{}' is not a finite length", c.name);
  return {};
}

Eigen::Vector3d RepeatTemplate::offset(const double* attributes_si, const double* at) const {
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  for (size_t k = 0; k < counters.size(); ++k)
    if (counters[k].pitch.v[0].present || counters[k].pitch.v[1].present || counters[k].pitch.v[2].present)
      d += (at[k] - 1) * counters[k].pitch.eval(attributes_si, 0);
  return d;
}

std::string FrameTemplate::name_of(const double* at) const {
  std::string out;
  for (size_t i = 0; i < name.size(); ++i) {
    size_t end = name[i] == '{' ? name.find('}', i) : std::string::npos;
    if (end == std::string::npos) {
      out += name[i];
      continue;
    }
    const std::string counter = name.substr(i + 1, end - i - 1);
    for (size_t k = 0; k < repeat->counters.size(); ++k)
      if (repeat->counters[k].name == counter) out += fmt::format("{}", static_cast<long long>(at[k]));
    i = end;
  }
  return out;
}

namespace {
/// The counters' values of the copy of repeated frame `f` named `copy`, read back from the name:
/// when every counter is in the pattern and each `{counter}` is followed by a character that is
/// no digit (or ends it), a copy's name gives its counters, one copy a name. Else (or when `copy`
/// does not fit the pattern) nullopt.
std::optional<std::vector<double>> counters_in(const FrameTemplate& f, std::string_view copy) {
  const std::string& name = f.name;
  const auto& counters = f.repeat->counters;
  std::vector<double> at(counters.size(), NAN);
  size_t c = 0;  // in copy
  for (size_t i = 0; i < name.size(); ++i) {
    const size_t end = name[i] == '{' ? name.find('}', i) : std::string::npos;
    if (end == std::string::npos) {
      if (c >= copy.size() || copy[c] != name[i]) return std::nullopt;
      ++c;
      continue;
    }
    const std::string_view counter = std::string_view(name).substr(i + 1, end - i - 1);
    size_t k = 0;
    while (k < counters.size() && counters[k].name != counter) ++k;
    if (k == counters.size()) return std::nullopt;  // (no counter of that name: left as written)
    if (end + 1 < name.size() && std::isdigit(static_cast<unsigned char>(name[end + 1]))) return std::nullopt;
    size_t digits = c;
    while (digits < copy.size() && std::isdigit(static_cast<unsigned char>(copy[digits]))) ++digits;
    if (digits == c || digits - c > 9) return std::nullopt;
    const double value = std::stod(std::string(copy.substr(c, digits - c)));
    if (!std::isnan(at[k]) && at[k] != value) return std::nullopt;
    at[k] = value;
    c = digits;
    i = end;
  }
  if (c != copy.size() || std::any_of(at.begin(), at.end(), [](double v) { return std::isnan(v); })) return std::nullopt;
  return at;
}
}  // namespace

std::optional<Eigen::Isometry3d> FrameTemplate::find(const double* attributes_si, std::string_view copy) const {
  if (!repeat) return name == copy ? std::optional(pose.eval(attributes_si)) : std::nullopt;
  // A copy's name is the pattern with numbers for its counters: compare before making them all.
  if (copy.substr(0, name.find('{')) != std::string_view(name).substr(0, name.find('{'))) return std::nullopt;
  auto pose_of = [&](const double* at) {
    Eigen::Isometry3d X = pose.eval(attributes_si, at);
    X.translation() += repeat->offset(attributes_si, at);
    return X;
  };
  // The name read back (143 drums at a rack's slots made every slot's name for each drum): the
  // copy of those counters, if the repeat makes it and names it so.
  if (const std::optional<std::vector<double>> at = counters_in(*this, copy)) {
    if (!repeat->problem(attributes_si).empty()) return std::nullopt;
    for (size_t k = 0; k < at->size(); ++k)
      if (!((*at)[k] >= 1 && (*at)[k] <= repeat->counters[k].count.eval(attributes_si, 0))) return std::nullopt;
    if (name_of(at->data()) != copy) return std::nullopt;  // (`slot_01` is no copy's name)
    return pose_of(at->data());
  }
  std::optional<Eigen::Isometry3d> found;
  repeat->each(attributes_si, [&](const double* at) {
    if (name_of(at) == copy) found = pose_of(at);  // (a pattern without its counters names every copy alike: the last)
  });
  return found;
}

}  // namespace sscs
