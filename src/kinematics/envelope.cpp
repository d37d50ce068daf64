#include "kinematics/envelope.h"

#include <cmath>
#include <numbers>
#include <random>

#include "kinematics/ik.h"

namespace sscs {

namespace {

/// The ranges the chain's joints sweep: their limits; an unlimited revolute joint a turn, an
/// unlimited prismatic end 0 (`unbounded` then says so).
void joint_ranges(const Chain& chain, Eigen::VectorXd& lo, Eigen::VectorXd& hi, bool& unbounded) {
  const int n = chain.size();
  lo.resize(n);
  hi.resize(n);
  unbounded = false;
  for (int k = 0; k < n; ++k) {
    lo[k] = chain.lower(k);
    hi[k] = chain.upper(k);
    if (chain.revolute(k)) {
      if (!std::isfinite(lo[k])) lo[k] = -std::numbers::pi;
      if (!std::isfinite(hi[k])) hi[k] = std::numbers::pi;
    } else if (!std::isfinite(lo[k]) || !std::isfinite(hi[k])) {
      unbounded = true;
      lo[k] = std::isfinite(lo[k]) ? lo[k] : 0;
      hi[k] = std::isfinite(hi[k]) ? hi[k] : 0;
    }
  }
}

}  // namespace

std::vector<Eigen::Vector3d> reach_points(const Device& device, const Eigen::VectorXd& q, int count) {
  Chain chain(device);
  Eigen::VectorXd lo, hi;
  bool unbounded;
  joint_ranges(chain, lo, hi, unbounded);
  std::mt19937_64 rng(38);
  std::vector<Eigen::Vector3d> out;
  Eigen::VectorXd cq = chain.from_device(q);
  for (int i = 0; i < count; ++i) {
    for (int k = 0; k < chain.size(); ++k) cq[k] = std::uniform_real_distribution<double>(lo[k], hi[k])(rng);
    out.push_back(chain.forward(cq).translation());
  }
  return out;
}

Eigen::AlignedBox3d reach_envelope(const Device& device, const Eigen::VectorXd& q) {
  Chain chain(device);
  const int n = chain.size();
  Eigen::AlignedBox3d box;
  Eigen::VectorXd lo, hi;
  bool unbounded;
  joint_ranges(chain, lo, hi, unbounded);
  auto add = [&](const Eigen::VectorXd& cq) { box.extend(chain.forward(cq).translation()); };
  Eigen::VectorXd cq = chain.from_device(q);
  add(cq);
  if (n <= 7)
    for (int corner = 0; corner < (1 << n); ++corner) {
      for (int k = 0; k < n; ++k) cq[k] = (corner >> k) & 1 ? hi[k] : lo[k];
      add(cq);
    }
  // A grid over the ranges (ends and middles included: a vehicle's yaw 0 at its x limit is where
  // its forks reach farthest), as fine as 50,000 configurations allow; then random samples.
  int values = 2;
  while (n > 0 && std::pow(values + 1, n) <= 50000 && values < 21) ++values;
  if (values % 2 == 0) --values;  // odd: the middle of every range is on the grid
  if (n > 0 && std::pow(values, n) <= 50000) {
    long total = 1;
    for (int k = 0; k < n; ++k) total *= values;
    for (long i = 0; i < total; ++i) {
      long rest = i;
      for (int k = 0; k < n; ++k, rest /= values) cq[k] = lo[k] + (hi[k] - lo[k]) * static_cast<double>(rest % values) / (values - 1);
      add(cq);
    }
  }
  if (n > 3) {
    std::mt19937_64 rng(1);
    for (int i = 0; i < 20000; ++i) {
      for (int k = 0; k < n; ++k) cq[k] = std::uniform_real_distribution<double>(lo[k], hi[k])(rng);
      add(cq);
    }
  }
  if (unbounded) {
    // Along an unlimited prismatic axis the tool goes on for ever: say so with infinite bounds.
    for (int k = 0; k < n; ++k) {
      if (chain.revolute(k) || (std::isfinite(chain.lower(k)) && std::isfinite(chain.upper(k)))) continue;
      Eigen::VectorXd a = chain.from_device(q), b = a;
      b[k] += 1;
      Eigen::Vector3d dir = chain.forward(b).translation() - chain.forward(a).translation();
      for (int axis = 0; axis < 3; ++axis) {
        if (std::abs(dir[axis]) < 1e-9) continue;
        if (!std::isfinite(chain.lower(k))) (dir[axis] > 0 ? box.min() : box.max())[axis] = dir[axis] > 0 ? -INFINITY : INFINITY;
        if (!std::isfinite(chain.upper(k))) (dir[axis] > 0 ? box.max() : box.min())[axis] = dir[axis] > 0 ? INFINITY : -INFINITY;
      }
    }
  }
  return box;
}

}  // namespace sscs
