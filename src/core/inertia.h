#pragma once
/// Whether a rigid body's mass and inertia are ones a physics engine can integrate.
#include <cmath>
#include <string>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

namespace sscs {

/// "" when a body of `mass` (kg) with inertia tensor `I` (kg m^2, about its centre of mass) is
/// physical: a simulable mass, I symmetric with principal moments above 0 that obey the triangle
/// inequality (no moment above the sum of the other two), radii of gyration of 10 um to 1 km. Else why not, for a message. ODE
/// aborts on a body that is not; vendor URDFs write all-zero inertias on links they never
/// meant to simulate.
/// The masses the physics integrates (1 mg to 10,000 t): beyond them ODE's steps lose all
/// precision or abort.
inline bool simulable_mass(double mass) { return mass >= 1e-6 && mass <= 1e7; }

inline std::string unphysical_inertia(double mass, const Eigen::Matrix3d& I) {
  if (!(mass > 0) || !std::isfinite(mass)) return fmt::format("its mass is {} kg", mass);
  if (!simulable_mass(mass)) return fmt::format("its mass {:g} kg is beyond the 1e-6 to 1e7 kg the physics integrates", mass);
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
  // The radius of gyration sqrt(moment / mass): a body of 20 kg with moments of 1e-15 kg m^2
  // (1e-8 m) or 1e300 makes ODE's steps abort; real links lie between 10 um and 1 km.
  const double k_min = std::sqrt(m[0] / mass), k_max = std::sqrt(m[2] / mass);
  if (k_min < 1e-5 || k_max > 1e3)
    return fmt::format("its radius of gyration ({:.3g} to {:.3g} m) lies beyond the 1e-5 to 1e3 m the physics integrates",
                       k_min, k_max);
  return "";
}

}  // namespace sscs
