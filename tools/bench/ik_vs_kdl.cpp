// sscs's inverse kinematics side by side with orocos-kdl's ChainIkSolverPos_NR_JL, on the same
// chains, with the protocol of TRAC-IK's published comparison (trac_ik_examples/ik_tests):
// random joint configurations within limits (fixed seed), the full 6-D pose of each requested at
// 1e-5, at most 5 ms per solve, every solve seeded with the nominal pose midway between the
// limits. KDL runs one Newton iteration per call inside a loop until it succeeds or the 5 ms are
// spent, as in TRAC-IK's harness. Success is verified for both by forward kinematics: every
// component of the position (m) and rotation-vector (rad) error within 1e-5.
//
//   ik_vs_kdl [samples=10000] [type ...]      (types default to arm6 and ur5)
//   ik_vs_kdl [samples] --urdf FILE BASE TIP [--package-path DIR ...]
// The second form benchmarks a vendor's URDF as shipped, from its root link BASE to link TIP,
// without writing a type file. A continuous joint (no limits) is sampled over one turn.
#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <vector>
#include <unistd.h>

#include <fmt/format.h>
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_nr_jl.hpp>
#include <kdl/chainiksolvervel_pinv.hpp>

#include "pipeline/compile_vault.h"
#include "geometry/geometry.h"
#include "kinematics/ik.h"
#include "load/load.h"

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kEps = 1e-5;
constexpr double kTimeout = 0.005;

KDL::Frame to_kdl(const Eigen::Isometry3d& X) {
  KDL::Frame F;
  for (int r = 0; r < 3; ++r) {
    F.p(r) = X.translation()[r];
    for (int c = 0; c < 3; ++c) F.M(r, c) = X.linear()(r, c);
  }
  return F;
}

/// The KDL chain of a device's root-to-tool path, built as kdl_parser builds one from URDF.
KDL::Chain kdl_chain(const sscs::Device& d) {
  std::vector<int> path;
  for (int p = d.tool_part; p >= 0; p = d.parts[p].parent) path.push_back(p);
  std::reverse(path.begin(), path.end());
  KDL::Chain chain;
  for (size_t i = 1; i < path.size(); ++i) {
    const sscs::Joint& j = d.parts[path[i]].joint;
    KDL::Frame F = to_kdl(j.origin);
    KDL::Vector axis = F.M * KDL::Vector(j.axis.x(), j.axis.y(), j.axis.z());
    KDL::Joint joint = j.type == sscs::JointType::Revolute    ? KDL::Joint(j.name, F.p, axis, KDL::Joint::RotAxis)
                       : j.type == sscs::JointType::Prismatic ? KDL::Joint(j.name, F.p, axis, KDL::Joint::TransAxis)
                                                              : KDL::Joint(j.name, KDL::Joint::None);
    chain.addSegment(KDL::Segment(d.parts[path[i]].name, joint, F));
  }
  chain.addSegment(KDL::Segment("tool", KDL::Joint(KDL::Joint::None), to_kdl(d.X_part_tool)));
  return chain;
}

Eigen::Isometry3d from_kdl(const KDL::Frame& F) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    X.translation()[r] = F.p(r);
    for (int c = 0; c < 3; ++c) X.linear()(r, c) = F.M(r, c);
  }
  return X;
}

bool within(const Eigen::Isometry3d& X, const Eigen::Isometry3d& target) {
  return sscs::pose_error(X, target).cwiseAbs().maxCoeff() <= kEps;
}

struct Stats {
  std::vector<double> times;
  int ok = 0;
  void print(const char* who) const {
    std::vector<double> t = times;
    std::sort(t.begin(), t.end());
    double mean = 0;
    for (double x : t) mean += x;
    mean /= t.size();
    std::printf("  %-22s success %6.2f%%   mean %8.4f ms   p50 %8.4f ms   p99 %8.4f ms   max %8.4f ms\n", who, 100.0 * ok / t.size(),
                mean * 1e3, t[t.size() / 2] * 1e3, t[std::min(t.size() - 1, t.size() * 99 / 100)] * 1e3, t.back() * 1e3);
  }
  double mean() const {
    double m = 0;
    for (double x : times) m += x;
    return m / times.size();
  }
};

/// Where joint k is sampled: within its limits; a continuous joint (an infinite limit) over one
/// turn from its finite limit, or around 0 (samples drawn from ±inf were NaN configurations).
std::pair<double, double> sample_range(const sscs::Chain& chain, int k) {
  double lo = chain.lower(k), hi = chain.upper(k);
  if (!std::isfinite(lo) && !std::isfinite(hi)) return {-std::numbers::pi, std::numbers::pi};
  if (!std::isfinite(lo)) return {hi - 2 * std::numbers::pi, hi};
  if (!std::isfinite(hi)) return {lo, lo + 2 * std::numbers::pi};
  return {lo, hi};
}

/// `type` of the standard library (or of `options.library_dirs`), printed as `label` (else its
/// name); `type_file` (a temporary file standing for `--urdf ...`) is named as `label` in errors.
int run(const std::string& type, int samples, const sscs::CompileOptions& options = {}, const std::string& base = "",
        const std::string& label = "", const std::string& type_file = "") {
  const std::string name = label.empty() ? type : label;
  sscs::Sources sources;
  sscs::Diagnostics diag;
  uint32_t file = sources.add("bench.yaml", "sscs: 1\nvault: Bench\nobjects:\n  - {type: " + type + ", name: R}\n");
  auto spec = sscs::load_vault(file, sources, diag);
  std::optional<sscs::Workcell> wc;
  if (spec) wc = sscs::compile_vault(*spec, options, sources, diag);
  sscs::GeometryModel geometry;
  if (wc) geometry = sscs::build_geometry(*wc, diag);
  if (diag.has_errors() || !wc) {
    std::string text = diag.format(sources);
    // An error at the temporary type's `urdf:` line is the URDF's: say which one, not the file.
    for (size_t at; !type_file.empty() && (at = text.find(type_file)) != std::string::npos;)
      text.replace(at, text.find(": ", at) - at, name);
    for (size_t at; !type_file.empty() && (at = text.find("'" + type + "'")) != std::string::npos;)
      text.replace(at, type.size() + 2, "the robot");
    std::fputs(text.c_str(), stderr);
    return 2;
  }
  const sscs::Device& d = *geometry.objects[0].device;
  if (!base.empty() && d.parts[0].name != base) {
    std::fprintf(stderr, "ik_vs_kdl: the chain starts at the URDF's root link '%s', not '%s'\n", d.parts[0].name.c_str(),
                 base.c_str());
    return 2;
  }
  sscs::Chain chain(d);
  const int n = chain.size();
  if (n == 0) {  // base = tip, or only fixed joints between them: there is nothing to solve
    std::fprintf(stderr, "ik_vs_kdl: %s has no joint between its base and its tool: nothing to solve\n", name.c_str());
    return 2;
  }
  KDL::Chain kchain = kdl_chain(d);
  KDL::JntArray ll(n), ul(n), nominal(n);
  Eigen::VectorXd nominal_q(n);
  for (int k = 0; k < n; ++k) {
    ll(k) = chain.lower(k);
    ul(k) = chain.upper(k);
    auto [lo, hi] = sample_range(chain, k);
    nominal(k) = nominal_q[k] = (lo + hi) / 2;
  }
  KDL::ChainFkSolverPos_recursive fk(kchain);
  KDL::ChainIkSolverVel_pinv vik(kchain);
  KDL::ChainIkSolverPos_NR_JL kdl(kchain, ll, ul, fk, vik, 1, kEps);

  std::mt19937_64 rng(42);
  std::vector<Eigen::VectorXd> configs(samples, Eigen::VectorXd(n));
  for (auto& q : configs)
    for (int k = 0; k < n; ++k) {
      auto [lo, hi] = sample_range(chain, k);
      q[k] = std::uniform_real_distribution<double>(lo, hi)(rng);
    }

  // Both models must agree before their solvers are compared.
  double worst = 0;
  for (int i = 0; i < std::min(samples, 100); ++i) {
    KDL::JntArray q(n);
    for (int k = 0; k < n; ++k) q(k) = configs[i][k];
    KDL::Frame F;
    fk.JntToCart(q, F);
    worst = std::max(worst, sscs::pose_error(from_kdl(F), chain.forward(configs[i])).cwiseAbs().maxCoeff());
  }
  std::printf("%s: %d joints, %d samples, KDL and sscs forward kinematics agree to %.1e\n", name.c_str(), n, samples, worst);
  if (worst > 1e-9) return 1;

  Stats ours, theirs;
  sscs::IkOptions opt;
  opt.position_tol = kEps;  // Euclidean norms: at least as strict as the per-component check
  opt.angle_tol = kEps;
  opt.time_limit = kTimeout;
  opt.max_attempts = 1 << 30;  // the time limit ends a solve here, as it does TRAC-IK's
  // How far the polish takes a converged solution: to rounding (1e-9), or only within tolerance.
  int rounding = 0, converged = 0;
  double worst_polished = 0;
  for (const Eigen::VectorXd& q : configs) {
    Eigen::Isometry3d target = chain.forward(q);
    auto t0 = Clock::now();
    sscs::IkResult r = sscs::solve_ik(chain, target, nominal_q, opt);
    double dt = std::chrono::duration<double>(Clock::now() - t0).count();
    ours.times.push_back(dt);
    if (r.ok() && dt <= kTimeout * 1.01 && within(chain.forward(r.q), target)) ++ours.ok;
    if (r.ok()) {
      ++converged;
      double err = std::max(r.position_error, r.angle_error);
      rounding += err <= 1e-9;
      worst_polished = std::max(worst_polished, err);
    }

    KDL::Frame F = to_kdl(target);
    KDL::JntArray result = nominal, seed(n);
    int rc = -1;
    t0 = Clock::now();
    double elapsed = 0;
    do {
      seed = result;
      rc = kdl.CartToJnt(seed, F, result);
      elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
    } while (rc < 0 && elapsed < kTimeout);
    theirs.times.push_back(elapsed);
    Eigen::VectorXd kq(n);
    for (int k = 0; k < n; ++k) kq[k] = result(k);
    if (rc >= 0 && within(chain.forward(kq), target) && d.within_limits([&] {
          Eigen::VectorXd full = Eigen::VectorXd::Zero(d.dof());
          chain.to_device(kq, full);
          return full;
        }()))
      ++theirs.ok;
  }
  ours.print("sscs solve_ik");
  std::printf("  sscs solutions polished to rounding (error <= 1e-9): %.2f%% of %d, worst %.3g\n",
              converged ? 100.0 * rounding / converged : 0.0, converged, worst_polished);
  theirs.print("KDL NR_JL");
  std::printf("  mean time ratio sscs/KDL: %.3f\n", ours.mean() / theirs.mean());
  return 0;
}

}  // namespace

/// The URDF as a device type `bench_robot` whose tool is link `tip`, in a temporary library.
int run_urdf(const std::string& urdf, const std::string& base, const std::string& tip,
             const std::vector<std::string>& package_paths, int samples) {
  namespace fs = std::filesystem;
  fs::path dir = fs::temp_directory_path() / ("ik_vs_kdl-" + std::to_string(::getpid()));
  fs::create_directories(dir / "types");
  std::ofstream(dir / "types" / "bench_robot.yaml") << "sscs: 1\ntype: bench_robot\nkind: device\nurdf: \""
                                                   << fs::absolute(urdf).string() << "\"\ntool: {part: \"" << tip << "\"}\n";
  sscs::CompileOptions options;
  options.library_dirs = {dir.string()};
  options.package_paths = package_paths;
  const fs::path type_file = dir / "types" / "bench_robot.yaml";
  int status = run("bench_robot", samples, options, base, fmt::format("{} ({} to {})", urdf, base, tip), type_file.string());
  std::error_code ec;
  fs::remove_all(dir, ec);
  return status;
}

int main(int argc, char** argv) {
  const char* usage =
      "usage: ik_vs_kdl [SAMPLES] [TYPE ...] [--urdf FILE BASE TIP ...] [--package-path DIR ...]\n"
      "  SAMPLES  random reachable poses per robot, a whole number above 0 (default 10000)\n"
      "  TYPE     a device type of the standard library (default arm6 and ur5 when no --urdf is given)\n";
  int samples = 10000;
  bool samples_given = false;
  std::vector<std::string> types, package_paths;
  std::vector<std::array<std::string, 3>> urdfs;
  auto fail = [&](const std::string& why) {
    std::fprintf(stderr, "ik_vs_kdl: %s\n%s", why.c_str(), usage);
    return 2;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      std::fputs(usage, stdout);
      return 0;
    } else if (a == "--urdf") {
      if (i + 3 >= argc) return fail("--urdf needs three values: FILE BASE TIP");
      urdfs.push_back({argv[i + 1], argv[i + 2], argv[i + 3]});
      i += 3;
    } else if (a == "--package-path") {
      if (i + 1 >= argc) return fail("--package-path needs a folder");
      package_paths.push_back(argv[++i]);
    } else if (a.starts_with("-") && !(a.size() > 1 && std::isdigit(static_cast<unsigned char>(a[1])))) {
      return fail("unknown option '" + a + "'");
    } else if (!a.empty() && (std::isdigit(static_cast<unsigned char>(a[0])) || a[0] == '-' || a[0] == '+')) {
      long n = 0;
      auto [end, ec] = std::from_chars(a.data() + (a[0] == '+'), a.data() + a.size(), n);
      if (ec != std::errc() || end != a.data() + a.size() || n < 1 || n > 100000000)
        return fail("SAMPLES must be a whole number from 1 to 100000000, found '" + a + "'");
      if (samples_given) return fail("SAMPLES given twice");
      samples = static_cast<int>(n);
      samples_given = true;
    } else {
      types.push_back(a);
    }
  }
  if (!urdfs.empty()) {
    int status = 0;
    for (const auto& [file, base, tip] : urdfs) status = std::max(status, run_urdf(file, base, tip, package_paths, samples));
    for (const std::string& t : types) status = std::max(status, run(t, samples));
    return status;
  }
  if (types.empty()) types = {"arm6", "ur5"};
  int status = 0;
  for (const std::string& t : types) status = std::max(status, run(t, samples));
  return status;
}
