#include "kinematics/ik.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include <Eigen/Cholesky>
#include "core/units.h"

namespace sscs {

namespace {


/// SplitMix64: a tiny, well-mixed generator whose sequence is the same on every platform
/// (std::uniform_real_distribution is not), so restarts and reports are reproducible.
class SplitMix {
 public:
  explicit SplitMix(uint64_t seed) : state_(seed) {}
  double uniform() {  // [0, 1)
    uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-53;
  }

 private:
  uint64_t state_;
};

}  // namespace

Chain::Chain(const Device& device) : Chain(device, device.tool_part, device.X_part_tool) {}

Chain::Chain(const Device& device, int tip_part, const Eigen::Isometry3d& X_part_tip) {
  std::vector<int> path;
  for (int p = tip_part; p >= 0; p = device.parts[p].parent) path.push_back(p);
  std::reverse(path.begin(), path.end());
  Eigen::Isometry3d acc = Eigen::Isometry3d::Identity();
  double bound = 0;
  for (size_t i = 1; i < path.size(); ++i) {
    const Joint& j = device.parts[path[i]].joint;
    if (j.type == JointType::Fixed || j.q < 0) {
      acc = acc * joint_transform(j, 0);
      continue;
    }
    Link link{acc * j.origin, j.axis, j.type == JointType::Revolute, j.lower, j.upper, j.q};
    if (links_.empty()) base_point_ = link.before.translation();
    else bound += link.before.translation().norm();
    if (!link.revolute) bound += std::max(std::abs(j.lower), std::abs(j.upper));
    links_.push_back(link);
    acc.setIdentity();
  }
  tip_ = acc * X_part_tip;  // with no moving joint: the whole chain
  reach_bound_ = bound + tip_.translation().norm();
}

Eigen::VectorXd Chain::from_device(const Eigen::VectorXd& device_q) const {
  Eigen::VectorXd q(size());
  for (int k = 0; k < size(); ++k) q[k] = device_q[links_[k].q];
  return q;
}

void Chain::to_device(const Eigen::VectorXd& chain_q, Eigen::VectorXd& device_q) const {
  for (int k = 0; k < size(); ++k) device_q[links_[k].q] = chain_q[k];
}

Eigen::Isometry3d Chain::forward(const Eigen::VectorXd& q) const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int k = 0; k < size(); ++k) {
    const Link& l = links_[k];
    T = T * l.before;
    if (l.revolute) T.linear() = T.linear() * Eigen::AngleAxisd(q[k], l.axis).toRotationMatrix();
    else T.translation() += T.linear() * (l.axis * q[k]);
  }
  return T * tip_;
}

Eigen::Isometry3d Chain::forward(const Eigen::VectorXd& q, Eigen::Matrix<double, 6, Eigen::Dynamic>& J) const {
  J.resize(6, size());
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int k = 0; k < size(); ++k) {
    const Link& l = links_[k];
    T = T * l.before;
    Eigen::Vector3d z = T.linear() * l.axis;
    // Store the joint's axis and point; the linear rows need the tip, known at the end.
    J.col(k).head<3>() = T.translation();
    J.col(k).tail<3>() = z;
    if (l.revolute) T.linear() = T.linear() * Eigen::AngleAxisd(q[k], l.axis).toRotationMatrix();
    else T.translation() += z * q[k];
  }
  T = T * tip_;
  const Eigen::Vector3d tip = T.translation();
  for (int k = 0; k < size(); ++k) {
    Eigen::Vector3d z = J.col(k).tail<3>();
    if (links_[k].revolute) {
      J.col(k).head<3>() = z.cross(tip - J.col(k).head<3>());
    } else {
      J.col(k).head<3>() = z;
      J.col(k).tail<3>().setZero();
    }
  }
  return T;
}

Eigen::Matrix<double, 6, 1> pose_error(const Eigen::Isometry3d& current, const Eigen::Isometry3d& target) {
  Eigen::Matrix<double, 6, 1> e;
  e.head<3>() = target.translation() - current.translation();
  Eigen::AngleAxisd aa(Eigen::Matrix3d(target.linear() * current.linear().transpose()));
  e.tail<3>() = aa.axis() * aa.angle();
  return e;
}

/// The largest damping (error energy, m²) of a step: above it steps go nearly Gauss-Newton.
constexpr double kMaxDamping = 10;

namespace {
/// A converged solution whose error is at most this (m, rad) is polished to rounding.
constexpr double kRounding = 1e-9;
/// Attempts spent looking for a solution that polishes to rounding when the first did not.
constexpr int kUncleanAttempts = 8;
/// Most polish steps (each one forward kinematics): a few near a singularity, one or two else.
constexpr int kPolishSteps = 40;
}  // namespace

IkResult solve_ik(const Chain& chain, const Eigen::Isometry3d& target, const Eigen::VectorXd& seed,
                  const IkOptions& opt, const std::function<bool(const Eigen::VectorXd&)>& accept) {
  using Clock = std::chrono::steady_clock;
  // An infinite time limit is none (its duration would overflow the clock into the past).
  const bool clocked = std::isfinite(opt.time_limit);
  const auto deadline =
      clocked ? Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(opt.time_limit)) : Clock::time_point::max();
  const int n = chain.size();
  const int rows = opt.orientation ? 6 : 3;
  auto clamp = [&](Eigen::VectorXd& q) {
    for (int k = 0; k < n; ++k) q[k] = std::clamp(q[k], chain.lower(k), chain.upper(k));
  };
  auto errors = [&](const Eigen::Matrix<double, 6, 1>& e, double& pos, double& ang) {
    pos = e.head<3>().norm();
    ang = opt.orientation ? e.tail<3>().norm() : 0.0;
  };
  auto converged = [&](double pos, double ang) { return pos <= opt.position_tol && ang <= opt.angle_tol; };
  // A revolute joint whose range spans more than a turn reaches the same pose a turn away:
  // of those equivalent angles, take the one nearest the seed. A prismatic joint has no turns:
  // shifting it by 2π metres would move the tool (a crane sent to 12 m stopped at 5.7 m).
  auto nearest_turn = [&](Eigen::VectorXd& q) {
    for (int k = 0; k < n; ++k) {
      if (!chain.revolute(k)) continue;
      while (q[k] - seed[k] > kPi && q[k] - 2 * kPi >= chain.lower(k)) q[k] -= 2 * kPi;
      while (seed[k] - q[k] > kPi && q[k] + 2 * kPi <= chain.upper(k)) q[k] += 2 * kPi;
    }
  };

  IkResult result;
  Eigen::VectorXd start = seed;
  clamp(start);
  result.q = start;
  double best_cost = INFINITY;  // of the best unconverged configuration
  bool found = false, rejected = false;
  double found_distance = INFINITY;
  // Whether the solution found polished to rounding. One that did not (pressed against a joint
  // limit on its branch of solutions) is kept, but a few more attempts look for one that does.
  bool found_clean = false;
  int unclean_attempts_left = kUncleanAttempts;

  Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, n);
  Eigen::MatrixXd H(n, n);
  Eigen::VectorXd g(n), dq(n), q(n);
  Eigen::LLT<Eigen::MatrixXd> llt(n);
  SplitMix rng(opt.random_seed);

  // A target farther from the first moving joint than the chain can stretch is out of reach:
  // one attempt from the seed still measures how close the chain gets, for the margin.
  const bool hopeless = n > 0 && (target.translation() - chain.base_point()).norm() > chain.reach_bound() + opt.position_tol;
  const int attempts = n == 0 ? 1 : hopeless ? 1 : opt.max_attempts;
  int extra_left = opt.extra_attempts;

  for (int attempt = 0; attempt < attempts; ++attempt) {
    if (attempt > 0 && clocked && Clock::now() > deadline) {
      result.timed_out = true;
      break;
    }
    ++result.attempts;
    if (attempt == 0) {
      q = start;
    } else {
      for (int k = 0; k < n; ++k) {
        double lo = chain.lower(k), hi = chain.upper(k);
        if (!std::isfinite(lo) || !std::isfinite(hi)) {
          double span = chain.revolute(k) ? kPi : 1.0;  // a turn either way, or a metre
          lo = std::isfinite(lo) ? lo : start[k] - span;
          hi = std::isfinite(hi) ? hi : start[k] + span;
        }
        q[k] = lo + (hi - lo) * rng.uniform();
      }
    }
    double previous = INFINITY;
    int stalled = 0;
    for (int it = 0; it < std::max(1, opt.iterations_per_attempt); ++it) {
      ++result.iterations;
      Eigen::Isometry3d T = chain.forward(q, J);
      Eigen::Matrix<double, 6, 1> e = pose_error(T, target);
      double pos, ang;
      errors(e, pos, ang);
      double cost = 0.5 * e.head(rows).squaredNorm();
      if (cost < best_cost && !found) {
        best_cost = cost;
        result.q = q;
        result.position_error = pos;
        result.angle_error = ang;
      }
      if (converged(pos, ang)) {
        // Polish: a few more steps take the error from "within tolerance" to rounding, so the
        // reported error (and a reach margin) does not depend on where the iterate happened to land.
        // Levenberg-Marquardt steps whose damping adapts: a Gauss-Newton step (almost no
        // damping) converges quadratically; near a singularity, where it overshoots, the damping
        // grows until a step goes downhill and shrinks again after each success.
        double damping = 1e-9;
        for (int k = 0; k < kPolishSteps && n > 0 && (pos > kRounding * 1e-3 || ang > kRounding * 1e-3); ++k) {
          auto Jr = J.topRows(rows);
          H.noalias() = Jr.transpose() * Jr;
          g.noalias() = Jr.transpose() * e.head(rows);
          const double scale = std::max(1e-12, H.diagonal().mean());
          Eigen::MatrixXd Hd = H;
          Hd.diagonal().array() += damping * scale;
          Eigen::VectorXd polished = q + Hd.ldlt().solve(g);
          clamp(polished);
          Eigen::Isometry3d Tp = chain.forward(polished, J);
          Eigen::Matrix<double, 6, 1> ep = pose_error(Tp, target);
          double pp, ap;
          errors(ep, pp, ap);
          if (pp + ap < pos + ang) {
            q = polished;
            e = ep;
            pos = pp;
            ang = ap;
            damping = std::max(1e-12, damping * 0.1);
          } else {
            chain.forward(q, J);  // keep J consistent with q
            damping *= 10;
            if (damping > 1e3) break;  // no step goes downhill: a limit holds it
          }
        }
        Eigen::VectorXd solution = q;
        nearest_turn(solution);
        double distance = (solution - seed).norm();
        const bool clean = pos <= kRounding && ang <= kRounding;
        // Better: polished to rounding where the one found is not, else nearer the seed.
        const bool better = !found || (clean && !found_clean) || (clean == found_clean && distance < found_distance);
        if (better && (!accept || accept(solution))) {
          found = true;
          found_clean = clean;
          found_distance = distance;
          result.q = solution;
          result.position_error = pos;
          result.angle_error = ang;
        } else if (!found) {
          rejected = true;
          result.q = solution;  // the nearest collision, for the report
          result.position_error = pos;
          result.angle_error = ang;
        }
        break;
      }
      if (n == 0) break;
      // Levenberg–Marquardt step with Sugihara's damping: the error's energy plus a small bias,
      // which stays well-conditioned through singularities without slowing convergence. The
      // energy is capped: a vehicle or crane tens of metres from its target would otherwise creep
      // (a damping of 5000 for 100 m), stall and report a reachable pose unreachable.
      auto Jr = J.topRows(rows);
      H.noalias() = Jr.transpose() * Jr;
      H.diagonal().array() += std::min(cost, kMaxDamping) + 1e-6;
      g.noalias() = Jr.transpose() * e.head(rows);
      llt.compute(H);
      dq = llt.solve(g);
      q += dq;
      clamp(q);
      // Little progress over several iterations: a local minimum or a limit; restart.
      if (cost > 0.995 * previous) {
        if (++stalled >= 4) break;
      } else {
        stalled = 0;
      }
      previous = cost;
    }
    if (found && found_clean && extra_left-- <= 0) break;
    if (found && !found_clean && unclean_attempts_left-- <= 0) break;
  }
  result.status = found ? IkResult::Status::Reached : rejected ? IkResult::Status::Rejected : IkResult::Status::Unreachable;
  return result;
}

}  // namespace sscs
