#include "kinematics/closest.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>
#include "core/units.h"

namespace sscs {

namespace {

/// Metres of position error a radian of rotation error weighs: orientation comes first.
constexpr double kAngleWeight = 1000;
/// Starts over the joint box per joint of the chain, and how many of the best are refined.
constexpr int kStartsPerJoint = 96;
constexpr int kRefined = 16;
constexpr int kIterations = 200;
/// closest_free: the accepted starts improved, and the smallest step of a joint (m or rad).
constexpr int kFreeStarts = 6, kFreeStartsTurning = 16;  // (a device with a revolute joint)
constexpr double kFreeStep = 1e-5;
/// closest_free's rays from the seed: how many directions, and the step they are marched in
/// (m or rad) before the first free pose on each is halved down to kFreeStep.
constexpr int kRays = 128;
constexpr double kRayStep = 0.02;

/// The i-th point of the Halton sequence in dimension `dim` (prime bases): evenly spread,
/// deterministic starts over the joint box.
double halton(int i, int dim) {
  static constexpr int kPrimes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53};
  const int base = kPrimes[dim % 16];
  double f = 1, r = 0;
  for (int n = i + 1; n > 0; n /= base) {
    f /= base;
    r += f * (n % base);
  }
  return r;
}

/// The searched range of chain joint k: its limits, an unlimited revolute joint a turn either
/// way, an unlimited prismatic one 50 m either way.
std::pair<double, double> range(const Chain& chain, int k) {
  const double span = chain.revolute(k) ? kPi : 50.0;
  return {std::isfinite(chain.lower(k)) ? chain.lower(k) : -span, std::isfinite(chain.upper(k)) ? chain.upper(k) : span};
}

struct Residual {
  Eigen::Matrix<double, 6, 1> e;  ///< position error, then the weighted rotation error
  double cost = 0;                ///< 0.5 |e|^2
};

class Search {
 public:
  Search(const Chain& chain, const Eigen::Isometry3d& target, bool orientation)
      : chain_(chain), target_(target), rows_(orientation ? 6 : 3), n_(chain.size()), J_(6, chain.size()) {}

  Residual residual(const Eigen::VectorXd& q, bool jacobian) {
    const Eigen::Isometry3d T = jacobian ? chain_.forward(q, J_) : chain_.forward(q);
    Residual r;
    r.e = pose_error(T, target_);
    r.e.tail<3>() *= kAngleWeight;
    r.cost = 0.5 * r.e.head(rows_).squaredNorm();
    return r;
  }

  /// Bound-constrained Levenberg-Marquardt from q to a local minimum of the cost: a joint at a
  /// limit the gradient pushes it past is held there, the others take the step. With `accept`,
  /// a step is taken only to a configuration it accepts (a shorter one is tried, as for a step
  /// that does not lower the cost): from a free pose, down the slope as far as free poses go.
  Eigen::VectorXd refine(Eigen::VectorXd q, const std::function<bool(const Eigen::VectorXd&)>& accept = {}) {
    Residual r = residual(q, true);
    double damping = 1e-3;
    for (int it = 0; it < kIterations && n_ > 0; ++it) {
      Eigen::MatrixXd Jr = J_.topRows(rows_);
      Jr.bottomRows(rows_ - 3) *= kAngleWeight;
      const Eigen::VectorXd g = Jr.transpose() * r.e.head(rows_);  // the descent direction's sign: dq ~ +g
      std::vector<int> free;
      for (int k = 0; k < n_; ++k) {
        auto [lo, hi] = range(chain_, k);
        const bool held = (q[k] <= lo + 1e-12 && g[k] < 0) || (q[k] >= hi - 1e-12 && g[k] > 0);
        if (!held) free.push_back(k);
      }
      if (free.empty()) break;
      Eigen::MatrixXd Jf(rows_, free.size());
      for (size_t i = 0; i < free.size(); ++i) Jf.col(i) = Jr.col(free[i]);
      Eigen::MatrixXd H = Jf.transpose() * Jf;
      const Eigen::VectorXd gf = Jf.transpose() * r.e.head(rows_);
      const double scale = std::max(1e-12, H.diagonal().maxCoeff());
      bool stepped = false;
      while (damping < 1e6) {
        Eigen::MatrixXd Hd = H;
        Hd.diagonal().array() += damping * scale;
        const Eigen::VectorXd dq = Hd.ldlt().solve(gf);
        Eigen::VectorXd next = q;
        for (size_t i = 0; i < free.size(); ++i) {
          auto [lo, hi] = range(chain_, free[i]);
          next[free[i]] = std::clamp(q[free[i]] + dq[i], lo, hi);
        }
        const Residual rn = residual(next, true);
        if (rn.cost < r.cost && (!accept || accept(next))) {
          const double gain = r.cost - rn.cost;
          q = next;
          r = rn;
          damping = std::max(1e-12, damping * 0.2);
          stepped = true;
          if (gain <= 1e-20 + 1e-14 * r.cost) return q;  // converged
          break;
        }
        damping *= 8;
      }
      if (!stepped) {
        residual(q, true);  // J_ of q again
        break;
      }
    }
    return q;
  }

  int size() const { return n_; }
  int rows() const { return rows_; }

 private:
  const Chain& chain_;
  const Eigen::Isometry3d target_;
  const int rows_, n_;
  Eigen::Matrix<double, 6, Eigen::Dynamic> J_;
};

/// The starts of a search: the middle of the joint box, the seed (clamped into it), and a
/// Halton set over it.
std::vector<Eigen::VectorXd> spread_starts(const Chain& chain, const Eigen::VectorXd& seed) {
  const int n = chain.size();
  std::vector<Eigen::VectorXd> starts;
  Eigen::VectorXd mid(n);
  for (int k = 0; k < n; ++k) {
    auto [lo, hi] = range(chain, k);
    mid[k] = (lo + hi) / 2;
  }
  starts.push_back(mid);
  if (seed.size() == n) {
    Eigen::VectorXd s = seed;
    for (int k = 0; k < n; ++k) s[k] = std::clamp(s[k], range(chain, k).first, range(chain, k).second);
    starts.push_back(s);
  }
  for (int i = 0; i < kStartsPerJoint * std::max(1, n); ++i) {
    Eigen::VectorXd q(n);
    for (int k = 0; k < n; ++k) {
      auto [lo, hi] = range(chain, k);
      q[k] = lo + (hi - lo) * halton(i, k);
    }
    starts.push_back(q);
  }
  return starts;
}

}  // namespace

ClosestReach closest_reach(const Chain& chain, const Eigen::Isometry3d& target, bool orientation, const Eigen::VectorXd& seed,
                           const std::function<bool(const Eigen::VectorXd&)>& accept) {
  Search search(chain, target, orientation);
  const std::vector<Eigen::VectorXd> starts = spread_starts(chain, seed);
  std::vector<std::pair<double, size_t>> ranked;
  for (size_t i = 0; i < starts.size(); ++i) ranked.emplace_back(search.residual(starts[i], false).cost, i);
  std::stable_sort(ranked.begin(), ranked.end());
  // Refined, the best of them: by cost, then (ties: mirror images) by the joint vector, so the
  // answer does not depend on the order of the starts.
  struct Candidate {
    double cost;
    Eigen::VectorXd q;
  };
  std::vector<Candidate> refined;
  for (size_t i = 0; i < ranked.size() && static_cast<int>(i) < kRefined; ++i) {
    Eigen::VectorXd q = search.refine(starts[ranked[i].second]);
    refined.push_back({search.residual(q, false).cost, q});
  }
  std::stable_sort(refined.begin(), refined.end(), [](const Candidate& a, const Candidate& b) { return a.cost < b.cost; });
  ClosestReach out;
  for (const Candidate& c : refined) {
    if (accept && !accept(c.q)) continue;
    const Residual r = search.residual(c.q, false);
    out.found = true;
    out.q = c.q;
    out.position_error = r.e.head<3>().norm();
    out.angle_error = orientation ? r.e.tail<3>().norm() / kAngleWeight : 0.0;
    break;
  }
  return out;
}

ClosestReach closest_free(const Chain& chain, const Eigen::Isometry3d& target, bool orientation, const Eigen::VectorXd& seed,
                         const std::function<bool(const Eigen::VectorXd&)>& accept, bool rays) {
  Search search(chain, target, orientation);
  const int n = chain.size();
  ClosestReach out;
  double best = INFINITY;
  // Pattern search from the best few of `starts` (accepted, by cost): one joint at a time, a step
  // either way taken when accepted and better; the step halves when none is, from a tenth of the
  // joint's range down to kFreeStep.
  auto improve = [&](std::vector<std::pair<double, Eigen::VectorXd>> starts) {
    std::stable_sort(starts.begin(), starts.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    // A device that turns: down the slope first, all joints at once, through free poses only;
    // then one joint at a time (the pattern search slides along an obstacle, where the slope runs
    // into it); again, while either gains (an arm turned to match past a drum: 2.62 m with the
    // pattern search alone, 1.15 m so, and mirror images within 3 mm of each other where they
    // were 0.27 m apart). A device of slides alone: the pattern search, exact for it (the slope
    // through free poses cost the store's check with five levels 3.4x, for 7 µm on its margins).
    bool turns = false;
    for (int k = 0; k < n; ++k) turns = turns || chain.revolute(k);
    for (size_t s = 0; s < starts.size() && static_cast<int>(s) < (turns ? kFreeStartsTurning : kFreeStarts); ++s) {
      auto [cost, q] = starts[s];
      for (double before = INFINITY; cost < before;) {
        before = cost;
        if (turns) {
          q = search.refine(q, accept);
          cost = search.residual(q, false).cost;
        }
        std::vector<double> step(n);
        for (int k = 0; k < n; ++k) step[k] = (range(chain, k).second - range(chain, k).first) / 10;
        for (bool any = true; any;) {
          any = false;
          for (int k = 0; k < n; ++k) {
            if (step[k] < kFreeStep) continue;
            any = true;
            bool moved = false;
            for (double sign : {1.0, -1.0}) {
              Eigen::VectorXd next = q;
              next[k] = std::clamp(q[k] + sign * step[k], range(chain, k).first, range(chain, k).second);
              if (next[k] == q[k]) continue;
              const double c = search.residual(next, false).cost;
              if (c < cost && accept(next)) {
                q = next;
                cost = c;
                moved = true;
                break;
              }
            }
            if (!moved) step[k] /= 2;
          }
        }
        if (!turns || cost >= before * (1 - 1e-9)) break;  // (no gain worth another round)
      }
      if (cost < best) {
        best = cost;
        const Residual r = search.residual(q, false);
        out.found = true;
        out.q = q;
        out.position_error = r.e.head<3>().norm();
        out.angle_error = orientation ? r.e.tail<3>().norm() / kAngleWeight : 0.0;
      }
    }
  };
  std::vector<std::pair<double, Eigen::VectorXd>> starts;  // the accepted spread starts
  for (const Eigen::VectorXd& q : spread_starts(chain, seed))
    if (accept(q)) starts.emplace_back(search.residual(q, false).cost, q);
  if (accept(seed)) starts.emplace_back(search.residual(seed, false).cost, seed);
  improve(std::move(starts));
  if (!rays) return out;
  // Then rays from the seed (the closest pose, or one that reaches the target in collision): on
  // each the first free pose, marched to in kRayStep and halved down to kFreeStep, no farther out
  // than the best found so far; the best of those improved as above. A free pocket the pattern
  // search cannot walk into from the spread starts is found so (a drum between two beams 0.122 m
  // too close: from above it stalls 0.7 m off, where sideways 0.586 m is free).
  auto inside = [&](const Eigen::VectorXd& q) {
    for (int k = 0; k < n; ++k)
      if (q[k] < range(chain, k).first || q[k] > range(chain, k).second) return false;
    return true;
  };
  double farthest = 0;  // beyond the joint box no ray goes, nor beyond the best pose found
  for (int k = 0; k < n; ++k) farthest += std::pow(range(chain, k).second - range(chain, k).first, 2);
  farthest = out.found ? (out.q - seed).norm() : std::sqrt(farthest);
  std::vector<std::pair<double, Eigen::VectorXd>> hits;
  for (int i = 0; i < kRays + 2 * n; ++i) {
    Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
    if (i < 2 * n) {
      u[i / 2] = i % 2 ? -1 : 1;  // each joint alone, either way
    } else {
      for (int k = 0; k < n; ++k) u[k] = 2 * halton(i - 2 * n, k + 3) - 1;
      if (u.norm() < 0.2) continue;
      u.normalize();
    }
    double before = 0;
    for (double t = kRayStep; t < farthest; t += kRayStep) {
      if (!inside(seed + t * u)) break;
      if (!accept(seed + t * u)) {
        before = t;
        continue;
      }
      double lo = before, hi = t;  // hi free; halved while a free pose is nearer
      while (hi - lo > kFreeStep) {
        const double mid = (lo + hi) / 2;
        (accept(seed + mid * u) ? hi : lo) = mid;
      }
      const Eigen::VectorXd q = seed + hi * u;
      hits.emplace_back(search.residual(q, false).cost, q);
      farthest = std::min(farthest, hi);
      break;
    }
  }
  improve(std::move(hits));
  return out;
}

}  // namespace sscs
