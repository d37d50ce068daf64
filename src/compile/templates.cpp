#include "compile/templates.h"

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

std::optional<Eigen::Isometry3d> FrameTemplate::find(const double* attributes_si, std::string_view copy) const {
  if (!repeat) return name == copy ? std::optional(pose.eval(attributes_si)) : std::nullopt;
  // A copy's name is the pattern with numbers for its counters: compare before making them all.
  if (copy.substr(0, name.find('{')) != std::string_view(name).substr(0, name.find('{'))) return std::nullopt;
  std::optional<Eigen::Isometry3d> found;
  repeat->each(attributes_si, [&](const double* at) {
    if (name_of(at) != copy) return;  // (a pattern without its counters names every copy alike: the last)
    found = pose.eval(attributes_si, at);
    found->translation() += repeat->offset(attributes_si, at);
  });
  return found;
}

}  // namespace sscs
