// The exact penetration depth of two solid primitives: closed-form cases worked by hand, and a
// property test against a brute-force reference that shares nothing with the code under test but
// the definition, depth = max(0, min over unit n of h_A(n) + h_B(−n)) with h the support function
// written from the shapes' definitions: the least over 200,000 directions, refined by walks that
// need no knowledge of where the minimum can lie.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/primitive_depth.h"

namespace sscs::testing {
namespace {

using Vec = Eigen::Vector3d;
using Iso = Eigen::Isometry3d;

Shape box(double x, double y, double z) {
  Shape s;
  s.kind = Shape::Kind::Box;
  s.box_size = Vec(x, y, z);
  return s;
}
Shape cylinder(double radius, double length) {
  Shape s;
  s.kind = Shape::Kind::Cylinder;
  s.radius = radius;
  s.length = length;
  return s;
}
Shape sphere(double radius) {
  Shape s;
  s.kind = Shape::Kind::Sphere;
  s.radius = radius;
  return s;
}
Iso at(double x, double y, double z, const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  Iso X = Iso::Identity();
  X.linear() = R;
  X.translation() = Vec(x, y, z);
  return X;
}
Eigen::Matrix3d turn(double degrees, const Vec& axis) {
  return Eigen::AngleAxisd(degrees * std::numbers::pi / 180, axis.normalized()).toRotationMatrix();
}

double depth(const Shape& a, const Iso& Xa, const Shape& b, const Iso& Xb) {
  return primitive_penetration_depth(a, Xa, b, Xb);
}

// --- Worked by hand ----------------------------------------------------------------------------------

// Two coaxial cylinders (axis z, radii r1 and r2, overlapping by `axial` along the axis): for
// n = (sin θ, 0, cos θ), h_A(n) + h_B(−n) = axial·|cos θ| + (r1 + r2)·|sin θ| (the centres' offset
// is along z, and its term folds into `axial`). That is concave on each quarter turn, so its least
// value is at an end: along the axis (axial) or across it (r1 + r2). Depth = min(axial, r1 + r2).

TEST(PrimitiveDepth, DrumStandingInAnOverpackLeavesSidewaysNotUpwards) {
  // A 55-gallon drum (r 0.286, 0.851 tall) standing on the floor of a solid 85-gallon overpack
  // (r 0.3555, 0.97 tall), coaxial. Along the axis it must rise 0.97 or sink 0.851 to clear;
  // sideways it moves 0.286 + 0.3555 = 0.6415, the depth (FCL says 0.851).
  const Shape drum = cylinder(0.286, 0.851), overpack = cylinder(0.3555, 0.97);
  EXPECT_NEAR(depth(overpack, at(0, 0, 0.97 / 2), drum, at(0, 0, 0.851 / 2)), 0.6415, 1e-9);
  EXPECT_NEAR(depth(drum, at(2, 3, 0.851 / 2), overpack, at(2, 3, 0.97 / 2)), 0.6415, 1e-9);
}

TEST(PrimitiveDepth, SmallDrumInsideALargerOneLeavesSideways) {
  // A 30-gallon drum (r 0.2325, 0.7 tall) 5 cm up inside a 55-gallon one (r 0.286, 0.851 tall):
  // it spans z 0.05..0.75 of 0..0.851. Along the axis: rise 0.851 − 0.05 = 0.801 or sink
  // 0.75 − 0 = 0.75; sideways 0.2325 + 0.286 = 0.5185, the depth (FCL says 0.787).
  const Shape small = cylinder(0.2325, 0.7), large = cylinder(0.286, 0.851);
  EXPECT_NEAR(depth(large, at(0, 0, 0.851 / 2), small, at(0, 0, 0.05 + 0.35)), 0.5185, 1e-9);
  // The same pair lying on its side, turned about the vertical.
  const Eigen::Matrix3d R = turn(30, Vec::UnitZ()) * turn(90, Vec::UnitX());
  const Vec up = R * Vec::UnitZ();
  const Vec c = Vec(1, -2, 0.4) + (0.4 - 0.851 / 2) * up;  // centre below the larger one's by 0.0255
  EXPECT_NEAR(depth(small, at(c.x(), c.y(), c.z(), R), large, at(1, -2, 0.4, R)), 0.5185, 1e-9);
}

TEST(PrimitiveDepth, CoaxialCylindersLeaveAlongTheAxisOrSideways) {
  // r 0.3 (1 long) and r 0.2 (0.6 long), the second's centre at height z: axial overlap
  // (1 + 0.6)/2 − |z| = 0.8 − |z|, sideways 0.5.
  const Shape a = cylinder(0.3, 1), b = cylinder(0.2, 0.6);
  for (double z : {0.0, 0.1, 0.25, 0.3, 0.35, 0.5, 0.7, 0.79, 0.8, 0.9, -0.45}) {
    SCOPED_TRACE(z);
    EXPECT_NEAR(depth(a, at(0, 0, 0), b, at(0, 0, z)), std::max(0.0, std::min(0.8 - std::abs(z), 0.5)), 1e-9);
    // Upside down is the same cylinder.
    EXPECT_NEAR(depth(a, at(0, 0, 0), b, at(0, 0, z, turn(180, Vec::UnitX()))), std::max(0.0, std::min(0.8 - std::abs(z), 0.5)), 1e-9);
  }
}

TEST(PrimitiveDepth, AxisAlignedBoxesOverlapByTheirLeastOverlapAlongAnAxis) {
  // 2 x 1 x 0.5 and a unit cube at (1.2, 0.3, 0.1): overlaps along x 1.5 − 1.2 = 0.3, along y
  // 1 − 0.3 = 0.7, along z 0.75 − 0.1 = 0.65. The difference of two aligned boxes is a box, so
  // its nearest face is along an axis.
  EXPECT_NEAR(depth(box(2, 1, 0.5), at(0, 0, 0), box(1, 1, 1), at(1.2, 0.3, 0.1)), 0.3, 1e-12);
  // Contained: a 0.2 cube at the centre of a 1 x 2 x 3 box leaves by x: 0.5 + 0.1.
  EXPECT_NEAR(depth(box(1, 2, 3), at(0, 0, 0), box(0.2, 0.2, 0.2), at(0, 0, 0)), 0.6, 1e-12);
  // Yawed by 90 degrees about z, the 2 x 1 box is 1 x 2: along y 1.5 − 0.3 = 1.2, along x
  // 1 − 1.2 < 0: apart.
  EXPECT_EQ(depth(box(2, 1, 0.5), at(0, 0, 0, turn(90, Vec::UnitZ())), box(1, 1, 1), at(1.2, 0.3, 0.1)), 0);
}

TEST(PrimitiveDepth, SpheresOverlapByTheirRadiiLessTheirDistance) {
  EXPECT_NEAR(depth(sphere(0.5), at(0, 0, 0), sphere(0.3), at(0.3, 0.4, 0)), 0.3, 1e-12);  // 0.8 − 0.5
  EXPECT_NEAR(depth(sphere(0.5), at(1, 1, 1), sphere(0.3), at(1, 1, 1)), 0.8, 1e-12);
  EXPECT_EQ(depth(sphere(0.5), at(0, 0, 0), sphere(0.3), at(0.8, 0, 0)), 0);  // touching
  EXPECT_EQ(depth(sphere(0.5), at(0, 0, 0), sphere(0.3), at(0, 0.9, 0)), 0);
}

TEST(PrimitiveDepth, SphereInsideASolidLeavesThroughTheNearestFace) {
  // Inside a 2 x 1 x 1 box, at (0.3, 0.1, 0): faces 0.7, 0.4, 0.5 away; depth 0.2 + 0.4.
  EXPECT_NEAR(depth(box(2, 1, 1), at(0, 0, 0), sphere(0.2), at(0.3, 0.1, 0)), 0.6, 1e-12);
  // Its centre 0.1 outside the +x face: 0.3 − 0.1.
  EXPECT_NEAR(depth(sphere(0.3), at(1.1, 0, 0), box(2, 1, 1), at(0, 0, 0)), 0.2, 1e-12);
  // Off an edge: the centre (1.1, 0.6, 0) is √(0.01 + 0.01) from the edge.
  EXPECT_NEAR(depth(box(2, 1, 1), at(0, 0, 0), sphere(0.3), at(1.1, 0.6, 0)), 0.3 - std::sqrt(0.02), 1e-12);
  // Inside a cylinder (r 0.5, 2 long) at 0.3 off the axis and 0.9 up: the side is 0.2 away, the
  // top 0.1; depth 0.15 + 0.1. Off its rim by (0.1, 0.1): 0.15 − √0.02.
  EXPECT_NEAR(depth(cylinder(0.5, 2), at(0, 0, 0), sphere(0.15), at(0, 0.3, 0.9)), 0.25, 1e-12);
  EXPECT_NEAR(depth(cylinder(0.5, 2), at(0, 0, 0), sphere(0.15), at(0.6, 0, 1.1)), 0.15 - std::sqrt(0.02), 1e-12);
}

TEST(PrimitiveDepth, CylinderLyingAcrossABoxLiftsOff) {
  // A 1 x 1 x 0.2 slab (top at z 0.1) and a rod (r 0.1, 2 long) lying across it, yawed 30 degrees,
  // its axis at z 0.15: its underside is at 0.05, 0.05 into the slab. Sliding it off sideways
  // takes at least 0.5 + 0.1 (the rod's ends overhang), so it lifts off by 0.05. (For n in the
  // vertical plane across the rod, F(θ) = 0.05 cos θ + (0.1 + half the slab's width along n)
  // sin θ grows from θ = 0; along the rod F = 0.05 cos θ + 1.5 sin θ or so, the same.)
  const Eigen::Matrix3d lying = turn(30, Vec::UnitZ()) * turn(90, Vec::UnitY());
  EXPECT_NEAR(depth(box(1, 1, 0.2), at(0, 0, 0), cylinder(0.1, 2), at(0, 0, 0.15, lying)), 0.05, 1e-9);
  EXPECT_NEAR(depth(cylinder(0.1, 2), at(0.2, -0.1, 0.15, lying), box(1, 1, 0.2), at(0, 0, 0)), 0.05, 1e-9);
  // Resting on it (touching): no depth.
  EXPECT_NEAR(depth(box(1, 1, 0.2), at(0, 0, 0), cylinder(0.1, 2), at(0, 0, 0.2, lying)), 0, 1e-12);
}

TEST(PrimitiveDepth, ShapesApartOrTouchingHaveNoDepth) {
  // Touching is 0 up to rounding.
  EXPECT_NEAR(depth(box(1, 1, 1), at(0, 0, 0), box(1, 1, 1), at(1, 0, 0)), 0, 1e-12);          // face to face
  EXPECT_NEAR(depth(box(1, 1, 1), at(0, 0, 0), box(1, 1, 1), at(1, 1, 1)), 0, 1e-12);          // corner to corner
  EXPECT_NEAR(depth(cylinder(0.5, 1), at(0, 0, 0), cylinder(0.5, 1), at(1, 0, 0)), 0, 1e-12);  // side to side
  EXPECT_NEAR(depth(cylinder(0.5, 1), at(0, 0, 0), cylinder(0.5, 1), at(0, 0, 1)), 0, 1e-12);  // end to end
  EXPECT_EQ(depth(cylinder(0.5, 1), at(0, 0, 0), box(1, 1, 1), at(0, 0, 3)), 0);
  // Apart, their bounding spheres overlapping.
  EXPECT_EQ(depth(cylinder(0.5, 1), at(0, 0, 0), cylinder(0.5, 1), at(0.85, 0.85, 0.2, turn(70, Vec(1, 2, 3)))), 0);
  EXPECT_EQ(depth(box(1, 1, 1), at(0, 0, 0), box(1, 1, 1), at(1.4, 0.3, -0.2, turn(33, Vec(1, -2, 3)))), 0);
}

TEST(PrimitiveDepth, MeshesAreNotPrimitives) {
  Shape mesh;
  mesh.kind = Shape::Kind::Mesh;
  EXPECT_TRUE(is_primitive(box(1, 1, 1)));
  EXPECT_TRUE(is_primitive(cylinder(1, 1)));
  EXPECT_TRUE(is_primitive(sphere(1)));
  EXPECT_FALSE(is_primitive(mesh));
  EXPECT_THROW(depth(mesh, at(0, 0, 0), box(1, 1, 1), at(0, 0, 0)), std::invalid_argument);
}

// --- The brute-force reference -----------------------------------------------------------------------

/// The support function of a placed shape, from its definition (homogeneous in n).
double support(const Shape& s, const Iso& X, const Vec& n) {
  const Vec c = X.translation();
  const Eigen::Matrix3d R = X.linear();
  switch (s.kind) {
    case Shape::Kind::Box:
      return c.dot(n) + 0.5 * (s.box_size.x() * std::abs(n.dot(R.col(0))) + s.box_size.y() * std::abs(n.dot(R.col(1))) +
                               s.box_size.z() * std::abs(n.dot(R.col(2))));
    case Shape::Kind::Cylinder: {
      const Vec a = R.col(2);
      const double na = n.dot(a);
      return c.dot(n) + 0.5 * s.length * std::abs(na) + s.radius * (n - na * a).norm();
    }
    default: return c.dot(n) + s.radius * n.norm();
  }
}

struct Pair {
  Shape a, b;
  Iso Xa, Xb;
  /// h_a(n) + h_b(−n): how far the shadows on n overlap.
  double overlap(const Vec& n) const { return support(a, Xa, n) + support(b, Xb, -n); }
  std::string describe() const {
    auto one = [](const Shape& s, const Iso& X) {
      std::ostringstream o;
      o.precision(17);
      o << (s.kind == Shape::Kind::Box ? "box " : s.kind == Shape::Kind::Cylinder ? "cylinder " : "sphere ");
      if (s.kind == Shape::Kind::Box) o << s.box_size.transpose();
      else o << s.radius << " " << s.length;
      o << " at\n" << X.matrix().topRows(3) << "\n";
      return o.str();
    };
    return one(a, Xa) + one(b, Xb);
  }
};

/// N directions spread evenly over the sphere (a Fibonacci lattice).
std::vector<Vec> fibonacci(int n) {
  std::vector<Vec> v;
  v.reserve(n);
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1 - (2 * i + 1.0) / n, r = std::sqrt(1 - z * z);
    v.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  return v;
}

/// The least value of a convex function of one variable on [lo, hi], and where (golden section).
template <class F>
std::pair<double, double> golden_min(const F& f, double lo, double hi, int iterations) {
  const double g = (std::sqrt(5.0) - 1) / 2;
  double c = hi - g * (hi - lo), d = lo + g * (hi - lo), fc = f(c), fd = f(d);
  for (int i = 0; i < iterations; ++i) {
    if (fc <= fd) hi = d, d = c, fd = fc, c = hi - g * (hi - lo), fc = f(c);
    else lo = c, c = d, fc = fd, d = lo + g * (hi - lo), fd = f(d);
  }
  return fc <= fd ? std::pair{fc, c} : std::pair{fd, d};
}

/// The unit normal of the boundary of D = A − B where the ray from the origin along the unit n
/// leaves it: the m minimising h_D(m) over the plane m·n = 1 (h_D(m) there is the distance along
/// the ray to the plane of normal m, and the ray's exit is the nearest such plane). A convex
/// problem, solved by nested golden sections near n (`iterations` each: 48 resolve 1e-11).
Vec exit_normal(const Pair& p, const Vec& n, int iterations) {
  const Vec b1 = (std::abs(n.x()) < 0.6 ? Vec::UnitX() : Vec::UnitY()).cross(n).normalized(), b2 = n.cross(b1);
  const double w = 0.3;
  auto along = [&](double x) {
    return golden_min([&](double y) { return p.overlap(n + x * b1 + y * b2); }, -w, w, iterations);
  };
  const double x = golden_min([&](double x) { return along(x).first; }, -w, w, iterations).second;
  return (n + x * b1 + along(x).second * b2).normalized();
}

/// From n, casts a ray, takes the normal where it leaves D, and repeats. Each step lowers the
/// overlap (it is the sequential linearisation of maximising |y| over the polar of D), and it
/// settles on a nearest point of D's boundary whatever the edges and kinks on the way, where a
/// local search on the overlap itself can stall in a crease. Returns the overlap and direction.
std::pair<double, Vec> walk(const Pair& p, Vec n, int iterations, int steps) {
  double value = p.overlap(n);
  for (int step = 0; step < steps; ++step) {
    Vec next = exit_normal(p, n, iterations);
    double v = p.overlap(next);
    if (!(v < value - 1e-15)) break;
    // Where the boundary curves with the origin near its centre of curvature the steps shrink
    // geometrically; go on along the step's great circle while the overlap keeps falling.
    const Vec dir = next - n;
    auto on = [&](double t) { return p.overlap((n + t * dir).normalized()); };
    double t = 1, vt = v;
    while (t < 1e6 && on(2 * t) < vt) t *= 2, vt = on(t);
    if (t > 1) {
      const auto [vm, tm] = golden_min(on, t / 2, 2 * t, 60);
      if (vm < v) next = (n + tm * dir).normalized(), v = vm;
    }
    n = next, value = v;
  }
  return {value, n};
}

/// The radius of a shape's bounding sphere about its centre.
double reach(const Shape& s) {
  return s.kind == Shape::Kind::Box ? s.box_size.norm() / 2 : std::hypot(s.radius, s.kind == Shape::Kind::Cylinder ? s.length / 2 : 0);
}

/// The depth by brute force: the least overlap over 200,000 directions, then walks (above) from
/// the grid's local minima. Sets grid_least to the grid's least overlap.
double reference_depth(const Pair& p, double* grid_least = nullptr) {
  static const std::vector<Vec> dirs = fibonacci(200000);
  static std::vector<double> values(dirs.size());
  for (size_t i = 0; i < dirs.size(); ++i) values[i] = p.overlap(dirs[i]);
  const double least = *std::min_element(values.begin(), values.end());
  if (grid_least) *grid_least = least;
  if (least <= 0) return 0;
  // The candidates: directions within the grid's resolution of the least (the overlap is
  // Lipschitz in n with constant |c_a − c_b| + both reaches, and every direction is within
  // 0.008 rad of the grid) that no neighbour on the grid (within 0.013 rad, about two grid steps)
  // betters: the grid's local minima. On a Fibonacci lattice the neighbours of point i are
  // points i ± F for Fibonacci numbers F.
  static const std::vector<int> steps = [] {
    std::vector<int> f{1, 2};
    while (f.back() < 200000) f.push_back(f[f.size() - 1] + f[f.size() - 2]);
    return f;
  }();
  const double lipschitz = (p.Xa.translation() - p.Xb.translation()).norm() + reach(p.a) + reach(p.b);
  std::vector<std::pair<double, int>> minima;
  for (int i = 0; i < int(dirs.size()); ++i) {
    if (values[i] > least + 0.008 * lipschitz) continue;
    bool lowest = true;
    for (int f : steps)
      for (int j : {i - f, i + f})
        if (j >= 0 && j < int(dirs.size()) && values[j] < values[i] && (dirs[j] - dirs[i]).squaredNorm() < 0.013 * 0.013)
          lowest = false;
    if (lowest) minima.emplace_back(values[i], i);
  }
  std::sort(minima.begin(), minima.end());
  if (minima.size() > 400) minima.resize(400);
  std::vector<Vec> starts;
  for (const auto& [value, i] : minima) starts.push_back(dirs[i]);
  // Two basins can be closer than the grid resolves, and a long shallow crease (a ring of nearly
  // equal overlaps) has local minima all along it, so there may be hundreds: each gets a short
  // coarse walk, and the best few places they reach (within what the coarse walks resolve)
  // a full one.
  std::vector<std::pair<double, Vec>> reached;
  for (const Vec& n : starts) reached.push_back(walk(p, n, 22, 6));
  std::sort(reached.begin(), reached.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  double best = least;
  std::vector<Vec> done;
  for (const auto& [value, n] : reached) {
    if (value > reached[0].first + 2e-3 || done.size() >= 6) break;
    bool again = false;
    for (const Vec& m : done) again = again || (m - n).norm() < 1e-3;
    if (again) continue;
    done.push_back(n);
    best = std::min(best, walk(p, n, 48, 40).first);
  }
  return std::max(0.0, std::min(best, reached[0].first));
}

// --- Random placements -------------------------------------------------------------------------------

struct Random {
  std::mt19937_64 rng;
  explicit Random(uint64_t seed) : rng(seed) {}
  double uniform(double lo, double hi) { return lo + (hi - lo) * double(rng() >> 11) * 0x1.0p-53; }
  Vec direction() {
    const double z = uniform(-1, 1), t = uniform(0, 2 * std::numbers::pi), r = std::sqrt(1 - z * z);
    return Vec(r * std::cos(t), r * std::sin(t), z);
  }
  /// A uniformly random rotation, or (when `square`) one of the 24 that keep the axes on axes,
  /// perhaps turned a hair off.
  Eigen::Matrix3d rotation(bool square) {
    if (!square) {
      const double u1 = uniform(0, 1), u2 = uniform(0, 2 * std::numbers::pi), u3 = uniform(0, 2 * std::numbers::pi);
      return Eigen::Quaterniond(std::sqrt(u1) * std::cos(u3), std::sqrt(1 - u1) * std::sin(u2), std::sqrt(1 - u1) * std::cos(u2),
                                std::sqrt(u1) * std::sin(u3))
          .toRotationMatrix();
    }
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    for (int i = 0; i < 3; ++i) R = turn(90 * int(rng() % 4), Vec::Unit(i)) * R;
    const double hair[] = {0, 0, 1e-9, 1e-6};
    return Eigen::AngleAxisd(hair[rng() % 4], direction()).toRotationMatrix() * R;
  }
  Shape shape(int kind) {
    if (kind == 0) return box(uniform(0.05, 2), uniform(0.05, 2), uniform(0.05, 2));
    if (kind == 1) return cylinder(uniform(0.05, 2), uniform(0.05, 2));
    return sphere(uniform(0.05, 2));
  }
};

/// Case i of a seeded series: every pair of kinds in turn, sizes 0.05 to 2 m; one in four
/// contained (centres within 1 cm), one in four offset along one of the first shape's axes, the
/// rest anywhere their bounding spheres overlap; one in three at right angles (or a hair off).
Pair random_pair(Random& r, int i) {
  static const int kinds[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
  Pair p;
  p.a = r.shape(kinds[i % 6][0]);
  p.b = r.shape(kinds[i % 6][1]);
  if (i % 2) std::swap(p.a, p.b);
  const bool square = i % 3 == 0;
  const Eigen::Matrix3d Ra = r.rotation(square), Rb = square ? Eigen::Matrix3d(r.rotation(true) * Ra) : r.rotation(false);
  const Vec ca(r.uniform(-3, 3), r.uniform(-3, 3), r.uniform(-3, 3));
  const double reach_both = reach(p.a) + reach(p.b);
  Vec offset;
  switch ((i / 6) % 4) {
    case 0: offset = r.uniform(0, 0.01) * r.direction(); break;
    case 1: offset = r.uniform(-0.8, 0.8) * reach_both * Ra.col(int(r.rng() % 3)); break;
    default: offset = r.uniform(0, 0.8) * reach_both * r.direction();
  }
  p.Xa = at(ca.x(), ca.y(), ca.z(), Ra);
  p.Xb = at(ca.x() + offset.x(), ca.y() + offset.y(), ca.z() + offset.z(), Rb);
  return p;
}

// The reference costs about 4 ms a case (40 under ASan): a sanitizer build, there for memory
// errors rather than answers, checks the first tenth of the cases.
#if defined(__SANITIZE_ADDRESS__)
#define SSCS_PRIMITIVE_DEPTH_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SSCS_PRIMITIVE_DEPTH_ASAN 1
#endif
#endif
#ifdef SSCS_PRIMITIVE_DEPTH_ASAN
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

TEST(PrimitiveDepth, RandomPairsAgreeWithABruteForceReference) {
  Random r(20240531);
  const int n = kSanitized ? 200 : 2000;
  int overlapping = 0;
  double worst = 0;
  for (int i = 0; i < n; ++i) {
    const Pair p = random_pair(r, i);
    const double got = depth(p.a, p.Xa, p.b, p.Xb);
    double grid_least = 0;
    const double want = reference_depth(p, &grid_least);
    overlapping += want > 1e-6;
    worst = std::max(worst, std::abs(got - want));
    EXPECT_NEAR(got, want, 1e-6) << "case " << i << ":\n" << p.describe();
    // The depth is a minimum over directions: never more than any one direction's overlap.
    EXPECT_LE(got, std::max(0.0, grid_least) + 1e-12) << "case " << i << ":\n" << p.describe();
    EXPECT_GE(got, 0);
  }
  EXPECT_GT(overlapping, n / 2);
  // The contract's 1e-9: the reference resolves these cases to about 1e-11.
  EXPECT_LT(worst, 1e-9);
  std::ostringstream shown;
  shown << worst;
  RecordProperty("worst_error_m", shown.str());
}

TEST(PrimitiveDepth, BoxCornerAtADrumsRim) {
  // A 1 x 0.3 x 2 box's corner pointing at the top rim of a drum (r 0.5, 2 tall) along n0,
  // halfway between the drum's up and its outward radial there, the box rolled about its corner's
  // diagonal n0 so that the corner's normals reach neither. Only directions near n0 separate
  // the two: no face normal, axis, edge × axis or line of centres does, nor any direction inside
  // a cell (the corner-to-rim one is a corner of A − B). Apart by a hair, or touching: no depth;
  // pushed in: as the reference says.
  const Vec u = Vec(1, 1, 0).normalized(), up = Vec::UnitZ(), n0 = (u + up).normalized();
  const Vec rim = 0.5 * u + up;
  const Vec tau = (up - up.dot(n0) * n0).normalized(), sigma = n0.cross(tau);
  Eigen::Matrix3d R;  // columns 30, 150 and 270 degrees round n0 from tau, 54.7 degrees off it
  for (int k = 0; k < 3; ++k) {
    const double psi = (30 + 120 * k) * std::numbers::pi / 180;
    R.col(k) = n0 / std::sqrt(3.0) + std::sqrt(2.0 / 3) * (std::cos(psi) * tau + std::sin(psi) * sigma);
  }
  if (R.determinant() < 0) R.col(0).swap(R.col(1));
  ASSERT_NEAR((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 0, 1e-12);
  const Shape drum = cylinder(0.5, 2), slab = box(1, 0.3, 2);
  auto slab_at = [&](double gap) {
    const Vec c = rim + gap * n0 + R * Vec(0.5, 0.15, 1);  // its corner −R(0.5, 0.15, 1) at the rim
    return at(c.x(), c.y(), c.z(), R);
  };
  EXPECT_EQ(depth(drum, at(0, 0, 0), slab, slab_at(1e-7)), 0);
  EXPECT_EQ(depth(slab, slab_at(1e-9), drum, at(0, 0, 0)), 0);
  EXPECT_NEAR(depth(drum, at(0, 0, 0), slab, slab_at(0)), 0, 1e-12);
  for (double push : {1e-6, 1e-3, 0.05}) {
    const Pair p{drum, slab, at(0, 0, 0), slab_at(-push)};
    const double got = depth(p.a, p.Xa, p.b, p.Xb);
    EXPECT_GT(got, 0);
    EXPECT_NEAR(got, reference_depth(p), 1e-9) << push;
  }
}

TEST(PrimitiveDepth, DepthIsSymmetricAndInvariantUnderRigidMotionsAndMirroring) {
  Random r(7);
  for (int i = 0; i < 600; ++i) {
    const Pair p = random_pair(r, i);
    const double d = depth(p.a, p.Xa, p.b, p.Xb);
    SCOPED_TRACE(p.describe());
    EXPECT_EQ(depth(p.b, p.Xb, p.a, p.Xa), d);
    // Both moved together.
    const Iso M = at(r.uniform(-5, 5), r.uniform(-5, 5), r.uniform(-5, 5), r.rotation(i % 3 == 0));
    EXPECT_NEAR(depth(p.a, M * p.Xa, p.b, M * p.Xb), d, 1e-9);
    // Both mirrored in the plane x = 0: as improper placements, and as the proper ones that make
    // the same solids (each primitive is symmetric in its own x = 0 plane).
    const Eigen::Matrix3d S = Eigen::Vector3d(-1, 1, 1).asDiagonal();
    auto mirrored = [&](const Iso& X, bool proper) {
      Iso Y = Iso::Identity();
      Y.linear() = proper ? Eigen::Matrix3d(S * X.linear() * S) : Eigen::Matrix3d(S * X.linear());
      Y.translation() = S * X.translation();
      return Y;
    };
    EXPECT_NEAR(depth(p.a, mirrored(p.Xa, false), p.b, mirrored(p.Xb, false)), d, 1e-9);
    EXPECT_NEAR(depth(p.a, mirrored(p.Xa, true), p.b, mirrored(p.Xb, true)), d, 1e-9);
  }
}

}  // namespace
}  // namespace sscs::testing
