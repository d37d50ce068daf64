#include "geometry/primitive_depth.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

// The depth of two convex solids A and B is the distance from the origin to the boundary of their
// Minkowski difference D = A − B, which is the least, over unit directions n, of its support
// function h_D(n) = h_A(n) + h_B(−n) (negative when they are apart). All three primitives are
// centrally symmetric, so with d = c_A − c_B and g the support function of a shape centred at the
// origin (even in n), h_D(n) = d·n + g_A(n) + g_B(n), and n and −n are taken together as
//   F(n) = g_A(n) + g_B(n) − |d·n|,
// the overlap of the two shapes' shadows on the line n. Every direction evaluated gives an upper
// bound of the depth; the work is to evaluate F where its minimum lies.
//
// F is smooth except on the great circles perpendicular to a box edge or a cylinder axis (and at
// the axes themselves), which cut the sphere into cells. The minimum lies on a point where circles
// cross (a face normal, a cross product of two edge directions, an axis), or at a stationary point
// of F along an arc of a circle or inside a cell. On each arc or cell F is a linear term q·n (q:
// d plus the half-extents with the signs of that cell) plus the rims' r·|P_a n| terms, and its
// stationary points are found by solving for them: along an arc, a quartic whose real roots are
// isolated exactly; inside a cell (only two cylinders need it: see box_cylinder), a
// one-parameter root search along one rim (the only part that samples). Boxes against boxes are
// the 15 separating axes; spheres are closed form. Everything is worked in the frame of the
// first shape, and the pair is put in a fixed order first, so swapping the arguments gives the same
// bits.

namespace sscs {

namespace {

using Vec = Eigen::Vector3d;

/// A cell of the sphere of directions: where n·dirs[i] has the sign signs[i] for each i < count,
/// or where −n does (F takes n and −n together). A stationary point solved for with one cell's
/// linear term is only a stationary point of F if it lies in that cell (to within rounding).
struct Cell {
  std::array<Vec, 4> dirs;
  std::array<double, 4> signs{};
  int count = 0;
  Cell& with(const Vec& dir, double sign) {
    dirs[count] = dir, signs[count++] = sign;
    return *this;
  }
  bool holds(const Vec& n) const {
    bool pos = true, neg = true;
    for (int i = 0; i < count; ++i) {
      const double s = signs[i] * n.dot(dirs[i]);
      pos = pos && s >= -1e-9;
      neg = neg && s <= 1e-9;
    }
    return pos || neg;
  }
};

/// Keeps the least F over the directions offered (not necessarily unit; none when zero).
template <class F>
struct Least {
  const F& f;
  double value = INFINITY;
  void offer(const Vec& v) {
    const double n2 = v.squaredNorm();
    if (!(n2 > 1e-200)) return;
    value = std::min(value, f(v / std::sqrt(n2)));
  }
  /// Offers v if it lies in the cell.
  void offer_in(const Cell& cell, const Vec& v) {
    const double n2 = v.squaredNorm();
    if (!(n2 > 1e-200)) return;
    const Vec n = v / std::sqrt(n2);
    if (cell.holds(n)) value = std::min(value, f(n));
  }
  bool apart() const { return value <= 0; }
};
template <class F>
Least<F> least(const F& f) {
  return Least<F>{f};
}

/// The part of v perpendicular to the unit vector e, perpendicular to working precision.
Vec perpendicular_part(const Vec& v, const Vec& e) {
  const Vec p = v - v.dot(e) * e;
  return p - p.dot(e) * e;
}

/// Some unit vector perpendicular to the unit vector e.
Vec any_perpendicular(const Vec& e) {
  return (std::abs(e.x()) < 0.6 ? Vec::UnitX() : Vec::UnitY()).cross(e).normalized();
}

// --- Real roots of a polynomial of degree ≤ 4 on an interval ---------------------------------------
// Between consecutive roots of the derivative (found the same way, one degree down) the
// polynomial is monotone, so each root is bracketed and found by Newton's method kept inside its
// bracket: no root is missed, and a double root is caught where the polynomial turns at zero.

double poly(const double* c, int deg, double x) {
  double y = c[deg];
  for (int i = deg - 1; i >= 0; --i) y = y * x + c[i];
  return y;
}

/// The root in [lo, hi] of a polynomial monotone there with a sign change (flo: its value at lo);
/// `scale` bounds its coefficients' magnitudes, and so the rounding in evaluating it on [-1, 1].
double bracketed_root(const double* c, const double* dc, int deg, double lo, double hi, double flo, double scale) {
  double x = 0.5 * (lo + hi);
  for (int it = 0; it < 100; ++it) {
    const double fx = poly(c, deg, x);
    if (std::abs(fx) <= 4e-16 * scale) return x;  // as near zero as it can be told
    ((fx < 0) == (flo < 0) ? lo : hi) = x;
    double next = x - fx / poly(dc, deg - 1, x);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // Newton left the bracket: bisect
    if (std::abs(next - x) <= 1e-15 * (1 + std::abs(x))) return next;
    x = next;
  }
  return x;
}

constexpr int kMaxRoots = 8;

/// The real roots in [lo, hi] of c[0] + c[1] x + … + c[deg] x^deg (deg ≤ 4), ascending, some
/// possibly twice; returns how many were written to out.
int poly_roots(const double* c, int deg, double lo, double hi, double* out) {
  if (deg <= 0) return 0;
  if (deg == 1 || (deg == 2 && c[2] == 0)) {
    if (c[1] == 0) return 0;
    const double x = -c[0] / c[1];
    if (!(x >= lo && x <= hi)) return 0;
    out[0] = x;
    return 1;
  }
  if (deg == 2) {  // in closed form, without cancellation
    const double disc = c[1] * c[1] - 4 * c[2] * c[0];
    if (disc < 0) return 0;
    const double h = -0.5 * (c[1] + std::copysign(std::sqrt(disc), c[1]));
    double x[2] = {h / c[2], h != 0 ? c[0] / h : h / c[2]};
    if (x[0] > x[1]) std::swap(x[0], x[1]);
    int n = 0;
    for (const double r : x)
      if (r >= lo && r <= hi) out[n++] = r;
    return n;
  }
  double dc[4];
  for (int i = 0; i < deg; ++i) dc[i] = (i + 1) * c[i + 1];
  double knots[kMaxRoots + 2];
  int nk = 0;
  knots[nk++] = lo;
  nk += poly_roots(dc, deg - 1, lo, hi, knots + 1);
  knots[nk++] = hi;
  double scale = 0;
  for (int i = 0; i <= deg; ++i) scale += std::abs(c[i]);
  int n = 0;
  auto add = [&](double x) {
    if (n < kMaxRoots) out[n++] = x;
  };
  double fa = poly(c, deg, knots[0]);
  if (fa == 0) add(knots[0]);
  for (int k = 0; k + 1 < nk; ++k) {
    const double fb = poly(c, deg, knots[k + 1]);
    if (fb == 0) {
      add(knots[k + 1]);
    } else if (fa != 0 && (fa < 0) != (fb < 0)) {
      add(bracketed_root(c, dc, deg, knots[k], knots[k + 1], fa, scale));
    } else if (k + 2 < nk && std::abs(fb) <= 1e-12 * scale) {
      add(knots[k + 1]);  // turns at (all but) zero: a double root
    }
    fa = fb;
  }
  return n;
}

// --- Stationary points along an arc: an edge against a rim -----------------------------------------

/// Offers the directions n ⊥ e in the cell where q·n + r|P_a n| is stationary along the great
/// circle ⊥ e (P_a: the projection off the unit axis a). That is where an edge along e (or a
/// cylinder's side, e its axis) meets the rim of radius r round a: F along such an arc is
/// q·n + r|P_a n| plus a constant. With the rim point u(φ) = cos φ e1 + sin φ f1 (e1: e off a, normalised; f1 = a × e1)
/// and its tangent t(φ), the arc's normal there is e × t, and it is stationary where the support
/// point's part off e is along it: α cos φ + β sin φ + m sin φ cos φ = 0, a quartic in cos φ.
template <class L>
void edge_rim(const Vec& e, const Vec& a, double r, const Vec& q, const Cell& cell, L& least) {
  // The rim's term varies by r·κ²/2 at most on the circle (κ: e's part off a), so when e is
  // (nearly) the axis the stationary points are those of q·n alone: ±(q's part off e).
  const Vec qe = perpendicular_part(q, e);
  if (qe.squaredNorm() > 1e-200) least.offer_in(cell, qe);
  else least.offer(any_perpendicular(e));
  const Vec ea = perpendicular_part(e, a);
  const double kappa = ea.norm();
  if (kappa < 1e-6 || r <= 0) return;
  const Vec e1 = ea / kappa, f1 = a.cross(e1);
  const double alpha = q.dot(f1), beta = kappa * q.dot(e) - q.dot(e1), m = r * kappa * kappa;
  // (β + m x)² (1 − x²) = α² x², from (β + m cos φ) sin φ = −α cos φ squared.
  const double c[5] = {beta * beta, 2 * beta * m, m * m - beta * beta - alpha * alpha, -2 * beta * m, -m * m};
  double xs[kMaxRoots];
  const int n = poly_roots(c, 4, -1, 1, xs);
  const double tol = 1e-9 * (std::abs(alpha) + std::abs(beta) + m);
  for (int i = 0; i < n; ++i) {
    const double x = xs[i], s = std::sqrt(std::max(0.0, 1 - x * x));
    // Squaring let in sin φ of the wrong sign: keep the one that solves the equation.
    const double plus = std::abs(alpha * x + (beta + m * x) * s), minus = std::abs(alpha * x - (beta + m * x) * s);
    for (const double sg : {s, -s}) {
      const double residual = sg == s ? plus : minus, other = sg == s ? minus : plus;
      if (residual > tol && residual > other) continue;
      const Vec u = x * e1 + sg * f1, t = -sg * e1 + x * f1;
      const Vec normal = e.cross(t);  // the arc's normal at the rim point
      if (normal.squaredNorm() > 1e-6) least.offer_in(cell, normal);
      else least.offer_in(cell, perpendicular_part(q + r * u, e));  // the same, but t ∥ e
      if (s == 0) break;
    }
  }
}

// --- Stationary points inside a cell: two rims -----------------------------------------------------

constexpr int kRimSamples = 64;

const std::array<std::array<double, 2>, kRimSamples>& rim_table() {
  static const auto table = [] {
    std::array<std::array<double, 2>, kRimSamples> t{};
    for (int k = 0; k < kRimSamples; ++k) {
      const double phi = 2 * std::numbers::pi * k / kRimSamples;
      t[k] = {std::cos(phi), std::sin(phi)};
    }
    return t;
  }();
  return table;
}

/// Offers the directions where q·n + r1|P_z n| + r2|P_a n| is stationary on the sphere: where the
/// rim of radius r1 round z meets the rim of radius r2 round a (the cells of two cylinders). For the
/// first rim's point u1(φ) = (cos φ, sin φ, 0), w = q + r1 u1, the second rim's point must be
/// u2 = s·(w off a)/|…| (s = ±1: nearest or farthest), and then the support point p = w + r2 u2
/// is along n exactly where G_s(φ) = t1·p = 0 (t1: the first rim's tangent). G_s is a smooth
/// function of φ with a handful of roots; it is sampled round the rim, each sign change is solved
/// to full precision, and each place where |G_s| dips towards zero between samples is searched for
/// a pair of close roots (and offered anyway). When G_s vanishes all round (the cylinders coaxial)
/// every rim point is stationary, all with the same F: one is offered.
template <class L>
void rim_rim(const Vec& q, double r1, const Vec& a, double r2, const Cell& cell, L& least) {
  struct At {
    Vec t1, w, wa;  // wa: w off a
    double rho;
  };
  auto at = [&](double c, double s) {
    At p;
    p.t1 = Vec(-s, c, 0);
    p.w = q + r1 * Vec(c, s, 0);
    p.wa = perpendicular_part(p.w, a);
    p.rho = std::max(p.wa.norm(), 1e-300);
    return p;
  };
  auto g = [&](const At& p, double s) { return p.t1.dot(q) + s * r2 * p.t1.dot(p.wa) / p.rho; };
  auto offer = [&](double phi, double s) {
    const At p = at(std::cos(phi), std::sin(phi));
    const Vec u2 = s * p.wa / p.rho;
    const Vec normal = p.t1.cross(a.cross(u2));  // normal to both rims' tangents
    if (normal.squaredNorm() > 1e-6) least.offer_in(cell, normal);
    else least.offer_in(cell, p.w + r2 * u2);  // the support point: the same, but the tangents are parallel
  };
  auto root = [&](double s, double lo, double hi, double glo, double ghi) {
    // Illinois (regula falsi that halves a stale end): a bracket that stays a bracket. F is
    // stationary at the root, so an error of 1e-10 in φ costs it nothing (~1e-20).
    int side = 0;
    double x = lo;
    for (int it = 0; it < 80 && hi - lo > 1e-10; ++it) {
      const double last = x;
      x = (lo * ghi - hi * glo) / (ghi - glo);
      if (!(x > lo && x < hi)) x = 0.5 * (lo + hi);
      if (std::abs(x - last) < 1e-12) break;
      const double gx = g(at(std::cos(x), std::sin(x)), s);
      if (gx == 0) break;
      if ((gx < 0) == (ghi < 0)) {
        hi = x, ghi = gx;
        if (side == -1) glo *= 0.5;
        side = -1;
      } else {
        lo = x, glo = gx;
        if (side == +1) ghi *= 0.5;
        side = +1;
      }
    }
    offer(x, s);
  };
  const auto& table = rim_table();
  const double h = 2 * std::numbers::pi / kRimSamples;
  std::array<At, kRimSamples> pts;
  for (int k = 0; k < kRimSamples; ++k) pts[k] = at(table[k][0], table[k][1]);
  for (const double s : {1.0, -1.0}) {
    std::array<double, kRimSamples> gs;
    double largest = 0;
    for (int k = 0; k < kRimSamples; ++k) largest = std::max(largest, std::abs(gs[k] = g(pts[k], s)));
    if (largest <= 1e-12 * (q.norm() + r1 + r2)) {
      offer(0, s);
      continue;
    }
    for (int k = 0; k < kRimSamples; ++k) {
      const double g0 = gs[k], g1 = gs[(k + 1) % kRimSamples], gm = gs[(k + kRimSamples - 1) % kRimSamples];
      const double phi = h * k;
      if (g0 == 0) offer(phi, s);
      if (g0 != 0 && g1 != 0 && (g0 < 0) != (g1 < 0)) root(s, phi, phi + h, g0, g1);
      // |G| dips here between samples of its own sign: a parabola through the three samples
      // says where it turns; if G changes sign there, there are two roots close together.
      if (g0 != 0 && (g0 < 0) == (g1 < 0) && (g0 < 0) == (gm < 0) && std::abs(g0) < std::abs(gm) &&
          std::abs(g0) <= std::abs(g1)) {
        const double curve = gm - 2 * g0 + g1;
        if (!(std::abs(curve) > 0)) continue;
        const double dx = std::clamp(0.5 * h * (gm - g1) / curve, -h, h);
        const double gx = g(at(std::cos(phi + dx), std::sin(phi + dx)), s);
        if (gx != 0 && (gx < 0) != (g0 < 0)) {
          root(s, phi - h, phi + dx, gm, gx);
          root(s, phi + dx, phi + h, gx, g1);
        } else {
          offer(phi + dx, s);
        }
      }
    }
  }
}

// --- The pairs ---------------------------------------------------------------------------------------

/// Two boxes, in the frame of the first: half sizes ha, hb, the second's axes the columns of R.
/// Their difference is a zonotope, whose faces are normal to the 15 separating axes.
double box_box(const Vec& ha, const Eigen::Matrix3d& R, const Vec& hb, const Vec& d) {
  auto f = [&](const Vec& n) { return ha.dot(n.cwiseAbs()) + hb.dot((R.transpose() * n).cwiseAbs()) - std::abs(d.dot(n)); };
  auto m = least(f);
  for (int i = 0; i < 3; ++i) {
    m.offer(Vec::Unit(i));
    m.offer(R.col(i));
  }
  // e_i × v, exactly: no rounding for nearly parallel edges beyond that of R itself.
  for (int j = 0; j < 3; ++j) {
    const Vec v = R.col(j);
    m.offer(Vec(0, -v.z(), v.y()));
    m.offer(Vec(v.z(), 0, -v.x()));
    m.offer(Vec(-v.y(), v.x(), 0));
  }
  return std::max(0.0, m.value);
}

/// A box (half sizes hb, in its frame) and a cylinder (axis a, radius r, half length hl). Inside a
/// cell F's stationary point is where a rim meets a box corner, a corner of D too (its normals
/// fill an arc), and the nearest point of D's boundary from inside is never a corner: the ball
/// that reaches it would have to touch D in every one of those normals' planes. Nor is it needed
/// to tell the two apart: the directions that separate them form a convex cone (F is convex and
/// homogeneous), which holds that arc's ends if it holds its middle, and the ends lie on circles.
double box_cylinder(const Vec& hb, const Vec& a, double r, double hl, const Vec& d) {
  auto f = [&](const Vec& n) { return hb.dot(n.cwiseAbs()) + hl * std::abs(n.dot(a)) + r * n.cross(a).norm() - std::abs(d.dot(n)); };
  auto m = least(f);
  // Where circles cross: faces, the axis, and edge × axis.
  const Vec ek_x_a[3] = {Vec(0, -a.z(), a.y()), Vec(a.z(), 0, -a.x()), Vec(-a.y(), a.x(), 0)};
  for (int k = 0; k < 3; ++k) {
    m.offer(Vec::Unit(k));
    m.offer(ek_x_a[k]);
  }
  m.offer(a);
  m.offer(d);
  if (m.apart()) return 0;
  // A box corner against the cylinder's side: along the circle ⊥ a, F is v·n + r, stationary
  // at ±(v off a).
  for (int corner = 0; corner < 8; ++corner) {
    const Vec sign(corner & 1 ? 1 : -1, corner & 2 ? 1 : -1, corner & 4 ? 1 : -1);
    const Vec va = perpendicular_part(d + sign.cwiseProduct(hb), a);
    const Cell cell = Cell().with(Vec::UnitX(), sign.x()).with(Vec::UnitY(), sign.y()).with(Vec::UnitZ(), sign.z());
    if (va.squaredNorm() > 1e-200) m.offer_in(cell, va);
    else m.offer(any_perpendicular(a));
  }
  // A box edge (along e_k) against a rim, along the circles ⊥ e_k.
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    for (int signs = 0; signs < 8; ++signs) {
      const double si = signs & 1 ? 1 : -1, sj = signs & 2 ? 1 : -1, sa = signs & 4 ? 1 : -1;
      // The cell meets the circle only if n·a can take the sign sa in the quarter where n·e_i,
      // n·e_j take si, sj: at one of the quarter's ends.
      if (std::max(sa * si * a[i], sa * sj * a[j]) < -1e-9) continue;
      const Vec q = d + si * hb[i] * Vec::Unit(i) + sj * hb[j] * Vec::Unit(j) + sa * hl * a;
      edge_rim(Vec::Unit(k), a, r, q, Cell().with(Vec::Unit(i), si).with(Vec::Unit(j), sj).with(a, sa), m);
    }
  }
  return std::max(0.0, m.value);
}

/// Two cylinders, in the frame of the first (axis z, radius r1, half length h1); the second has
/// axis a, radius r2, half length h2.
double cylinder_cylinder(double r1, double h1, const Vec& a, double r2, double h2, const Vec& d) {
  auto f = [&](const Vec& n) {
    return h1 * std::abs(n.z()) + r1 * std::sqrt(n.x() * n.x() + n.y() * n.y()) + h2 * std::abs(n.dot(a)) +
           r2 * n.cross(a).norm() - std::abs(d.dot(n));
  };
  auto m = least(f);
  const Vec z = Vec::UnitZ();
  m.offer(z);
  m.offer(a);
  m.offer(Vec(-a.y(), a.x(), 0));  // z × a
  m.offer(d);
  if (m.apart()) return 0;
  // One's side against the other's rim, along the circles ⊥ each axis.
  for (const double end : {1.0, -1.0}) edge_rim(z, a, r2, d + end * h2 * a, Cell().with(a, end), m);
  for (const double end : {1.0, -1.0}) edge_rim(a, z, r1, d + end * h1 * z, Cell().with(z, end), m);
  if (m.apart()) return 0;
  // Rim against rim, inside the cells.
  for (const double e1 : {1.0, -1.0})
    for (const double e2 : {1.0, -1.0}) rim_rim(d + e1 * h1 * z + e2 * h2 * a, r1, a, r2, Cell().with(z, e1).with(a, e2), m);
  return std::max(0.0, m.value);
}

/// A sphere of radius rs whose centre is p in a box's frame (half sizes hb).
double box_sphere(const Vec& hb, double rs, const Vec& p) {
  const Vec ap = p.cwiseAbs();
  const Vec out = (ap - hb).cwiseMax(0.0);
  if (out.isZero()) return rs + (hb - ap).minCoeff();  // inside: r + the way out through the nearest face
  return std::max(0.0, rs - out.norm());
}

/// A sphere of radius rs whose centre is p in a cylinder's frame (radius r, half length hl).
double cylinder_sphere(double r, double hl, double rs, const Vec& p) {
  const double rho = std::sqrt(p.x() * p.x() + p.y() * p.y()), z = std::abs(p.z());
  const double dr = std::max(0.0, rho - r), dz = std::max(0.0, z - hl);
  if (dr == 0 && dz == 0) return rs + std::min(r - rho, hl - z);
  return std::max(0.0, rs - std::sqrt(dr * dr + dz * dz));
}

int rank(Shape::Kind k) {
  switch (k) {
    case Shape::Kind::Box: return 0;
    case Shape::Kind::Cylinder: return 1;
    case Shape::Kind::Sphere: return 2;
    case Shape::Kind::Mesh: break;
  }
  return 3;
}

/// A bounding sphere's radius about the shape's centre.
double reach(const Shape& s) {
  switch (s.kind) {
    case Shape::Kind::Box: return 0.5 * s.box_size.norm();
    case Shape::Kind::Cylinder: return std::hypot(s.radius, 0.5 * s.length);
    default: return s.radius;
  }
}

/// What orders a pair: kind, sizes, placement.
std::array<double, 16> order_key(const Shape& s, const Eigen::Isometry3d& X) {
  std::array<double, 16> k{};
  k[0] = rank(s.kind);
  if (s.kind == Shape::Kind::Box) k[1] = s.box_size.x(), k[2] = s.box_size.y(), k[3] = s.box_size.z();
  else k[1] = s.radius, k[2] = s.kind == Shape::Kind::Cylinder ? s.length : 0;
  for (int i = 0; i < 12; ++i) k[4 + i] = X.matrix()(i % 3, i / 3);
  return k;
}

/// The depth with a's kind ranked no later than b's.
double ordered_depth(const Shape& a, const Eigen::Isometry3d& Xa, const Shape& b, const Eigen::Isometry3d& Xb) {
  const Eigen::Matrix3d Rat = Xa.linear().transpose();
  const Vec d = Rat * (Xa.translation() - Xb.translation());  // c_a − c_b in a's frame
  if (!(d.norm() < reach(a) + reach(b))) return 0;
  using K = Shape::Kind;
  if (a.kind == K::Sphere) return std::max(0.0, a.radius + b.radius - d.norm());
  if (b.kind == K::Sphere) {
    return a.kind == K::Box ? box_sphere(0.5 * a.box_size, b.radius, -d)
                            : cylinder_sphere(a.radius, 0.5 * a.length, b.radius, -d);
  }
  const Eigen::Matrix3d R = Rat * Xb.linear();  // b's axes in a's frame
  if (a.kind == K::Box && b.kind == K::Box) return box_box(0.5 * a.box_size, R, 0.5 * b.box_size, d);
  if (a.kind == K::Box) return box_cylinder(0.5 * a.box_size, R.col(2), b.radius, 0.5 * b.length, d);
  return cylinder_cylinder(a.radius, 0.5 * a.length, R.col(2), b.radius, 0.5 * b.length, d);
}

}  // namespace

bool is_primitive(const Shape& s) {
  return s.kind == Shape::Kind::Box || s.kind == Shape::Kind::Cylinder || s.kind == Shape::Kind::Sphere;
}

double primitive_penetration_depth(const Shape& a, const Eigen::Isometry3d& X_world_a, const Shape& b,
                                   const Eigen::Isometry3d& X_world_b) {
  if (!is_primitive(a) || !is_primitive(b))
    throw std::invalid_argument("primitive_penetration_depth: a mesh is not a primitive");
  if (order_key(b, X_world_b) < order_key(a, X_world_a)) return ordered_depth(b, X_world_b, a, X_world_a);
  return ordered_depth(a, X_world_a, b, X_world_b);
}

}  // namespace sscs
