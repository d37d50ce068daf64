#include "compile/templates.h"

#include "core/pose.h"

namespace sscs {

double ValueRef::eval(const double* attributes_si, double fallback) const {
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
  for (size_t k = 0; k < attributes.size(); ++k) inputs[k] = attributes[k] < 0 ? NAN : attributes_si[attributes[k]];
  return expr->evaluate(inputs);
}

Eigen::Vector3d VectorRef::eval(const double* attributes_si, double fallback) const {
  return {v[0].eval(attributes_si, fallback), v[1].eval(attributes_si, fallback), v[2].eval(attributes_si, fallback)};
}

Eigen::Isometry3d PoseRef::eval(const double* attributes_si) const {
  return make_pose(xyz.eval(attributes_si, 0), rpy.eval(attributes_si, 0));
}

}  // namespace sscs
