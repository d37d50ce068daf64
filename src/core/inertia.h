#pragma once
/// Whether a rigid body's mass and inertia are ones a physics engine can integrate.
#include <cmath>
#include <string>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

namespace sscs {

/// "" when a body of `mass` (kg) with inertia tensor `I` (kg m^2, about its centre of mass) is
/// physical: mass above 0, I symmetric with principal moments above 0 that obey the triangle
/// inequality (no moment above the sum of the other two). Else why not, for a message. ODE
/// aborts on a body that is not; vendor URDFs write all-zero inertias on links they never
/// meant to simulate.
inline std::string unphysical_inertia(double mass, const Eigen::Matrix3d& I) {
  if (!(mass > 0) || !std::isfinite(mass)) return fmt::format("its mass is {} kg", mass);
  if (!I.allFinite()) return "its inertia is not finite";
  if (!I.isApprox(I.transpose(), 1e-9)) return "its inertia is not symmetric";
  const Eigen::Vector3d m = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I, Eigen::EigenvaluesOnly).eigenvalues();
  const double scale = m.cwiseAbs().maxCoeff();
  if (scale == 0) return "its inertia is all zero";
  if (!(m.minCoeff() > 1e-12 * scale))
    return fmt::format("its inertia has principal moments {:.4g}, {:.4g}, {:.4g} kg m^2, not all above 0", m[0], m[1], m[2]);
  // Sorted ascending: only the largest can exceed the sum of the others.
  if (m[2] > (m[0] + m[1]) * (1 + 1e-9))
    return fmt::format("its principal moments {:.4g}, {:.4g}, {:.4g} kg m^2 break the triangle inequality (the largest "
                       "above the sum of the others)", m[0], m[1], m[2]);
  return "";
}

}  // namespace sscs
