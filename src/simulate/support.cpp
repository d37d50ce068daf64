#include "simulate/support.h"

#include <algorithm>
#include <cmath>

#include "core/units.h"

namespace sscs {

namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

/// The convex hull of `p`, counter-clockwise (Andrew's monotone chain); collinear points dropped.
std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (p.size() < 3) return p;
  std::vector<Eigen::Vector2d> h(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 1] - h[k - 2], p[i] - h[k - 2]) <= 0) --k;
    h[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(h[k - 1] - h[k - 2], p[i] - h[k - 2]) <= 0) --k;
    h[k++] = p[i];
  }
  h.resize(k - 1);
  return h;
}

/// The narrowest width of a convex polygon (counter-clockwise): over its edges, the farthest
/// corner from the edge's line, the smallest of those.
double width(const std::vector<Eigen::Vector2d>& hull) {
  if (hull.size() < 3) return 0;
  double narrowest = INFINITY;
  for (size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d& a = hull[i];
    const Eigen::Vector2d edge = hull[(i + 1) % hull.size()] - a;
    double farthest = 0;
    for (const Eigen::Vector2d& c : hull) farthest = std::max(farthest, cross(edge, c - a) / edge.norm());
    narrowest = std::min(narrowest, farthest);
  }
  return narrowest;
}

}  // namespace

std::optional<SupportPatch> SupportPatch::from_contacts(const std::vector<Eigen::Vector3d>& points,
                                                        const std::vector<Eigen::Vector3d>& normals,
                                                        const Eigen::Isometry3d& X_world_rider) {
  if (points.size() < 3 || normals.size() != points.size()) return std::nullopt;
  Eigen::Vector3d n = Eigen::Vector3d::Zero(), c = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& m : normals) n += m;
  if (n.norm() < 1e-9) return std::nullopt;
  n.normalize();
  const double within = std::cos(30 * kRadPerDeg);
  for (const Eigen::Vector3d& m : normals)
    if (m.dot(n) < within * m.norm()) return std::nullopt;
  for (const Eigen::Vector3d& p : points) c += p;
  c /= static_cast<double>(points.size());
  SupportPatch patch;
  const Eigen::Matrix3d R_rider_world = X_world_rider.linear().transpose();
  patch.normal_ = R_rider_world * n;
  patch.centre_ = X_world_rider.inverse() * c;
  patch.u_ = patch.normal_.unitOrthogonal();
  patch.v_ = patch.normal_.cross(patch.u_);
  std::vector<Eigen::Vector2d> flat;
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector3d d = X_world_rider.inverse() * p - patch.centre_;
    flat.emplace_back(d.dot(patch.u_), d.dot(patch.v_));
  }
  patch.hull_ = convex_hull(std::move(flat));
  if (width(patch.hull_) < kNarrowest) return std::nullopt;
  for (const Eigen::Vector2d& q : patch.hull_) patch.twist_arm_ += q.norm();
  patch.twist_arm_ /= static_cast<double>(patch.hull_.size());
  return patch;
}

bool SupportPatch::holds(const Eigen::Vector3d& f, const Eigen::Vector3d& tau, const Eigen::Vector3d& com,
                         const Eigen::Isometry3d& X_world_rider, double mu, double share) const {
  const Eigen::Vector3d n = X_world_rider.linear() * normal_;
  const Eigen::Vector3d c = X_world_rider * centre_;
  const double N = f.dot(n);
  if (!(N > 0)) return false;  // pulling (or NaN): contacts only push
  if ((f - N * n).norm() > share * mu * N) return false;  // sliding
  // The torque about the patch's centre; the centre of pressure is where the normal force acts
  // that gives its part across the normal.
  const Eigen::Vector3d tau_c = tau + (com - c).cross(f);
  if (std::abs(tau_c.dot(n)) > share * mu * N * twist_arm_) return false;  // twisting
  const Eigen::Vector3d offset = n.cross(tau_c) / N;  // centre of pressure - c
  const Eigen::Vector2d cop(offset.dot(X_world_rider.linear() * u_), offset.dot(X_world_rider.linear() * v_));
  // Inside the polygon shrunk by `share` about the centre (the polygon contains the centre).
  for (size_t i = 0; i < hull_.size(); ++i) {
    const Eigen::Vector2d a = share * hull_[i], b = share * hull_[(i + 1) % hull_.size()];
    if (cross(b - a, cop - a) < 0) return false;  // tipping over this edge
  }
  return true;
}

std::vector<Eigen::Vector3d> SupportPatch::corners() const {
  std::vector<Eigen::Vector3d> out;
  for (const Eigen::Vector2d& q : hull_) out.push_back(centre_ + q.x() * u_ + q.y() * v_);
  return out;
}

}  // namespace sscs
