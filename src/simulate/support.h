#pragma once
/// The contact patch a rider stands on (a drum on a carried pallet), and whether it can hold the
/// rider as the carrier moves: the physics welds a resting rider to what carries it while the
/// patch could exert what the weld does, and lets it go back to its contacts when it could not.
#include <optional>
#include <vector>

#include <Eigen/Geometry>

namespace sscs {

class SupportPatch {
 public:
  /// A patch smaller across than this (m) holds nothing still: a drum lying on its side (a line
  /// of contacts) rolls.
  static constexpr double kNarrowest = 0.01;

  /// The patch of the contacts (world points; normals pointing into the rider, away from its
  /// support), kept in the rider's frame (`X_world_rider`). None when the contacts are too few or
  /// too narrow, or do not face one way (within 30 degrees): a rider held at its sides.
  static std::optional<SupportPatch> from_contacts(const std::vector<Eigen::Vector3d>& points,
                                                   const std::vector<Eigen::Vector3d>& normals,
                                                   const Eigen::Isometry3d& X_world_rider);

  /// Whether the patch, with the rider at `X_world_rider`, can exert on the rider the force `f`
  /// and the torque `tau` (about `com`, the rider's centre of mass) with `share` (0..1] of what
  /// it could: the normal force pushing, the tangential force within `share` of the friction
  /// cone (`mu`), the centre of pressure inside the patch's polygon shrunk by `share` about its
  /// centre, and the twist within `share` of what friction over the patch resists.
  bool holds(const Eigen::Vector3d& f, const Eigen::Vector3d& tau, const Eigen::Vector3d& com,
             const Eigen::Isometry3d& X_world_rider, double mu, double share) const;

  /// The polygon's corners, counter-clockwise about the normal, in the rider's frame.
  std::vector<Eigen::Vector3d> corners() const;

 private:
  Eigen::Vector3d normal_;   ///< rider frame, into the rider
  Eigen::Vector3d centre_;   ///< rider frame
  Eigen::Vector3d u_, v_;    ///< the patch plane's axes, rider frame
  std::vector<Eigen::Vector2d> hull_;  ///< (u, v) about centre_, counter-clockwise
  double twist_arm_ = 0;     ///< the mean distance of the corners from the centre (m)
};

}  // namespace sscs
