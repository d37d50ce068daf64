// A realistic storage rule: interaction between fissile units in storage by the solid-angle
// method, a classic hand method of nuclear criticality safety for arrays of units.
//
// Source: the solid-angle method as given in J. T. Thomas (ed.), "Nuclear Safety Guide,
// TID-7016, Revision 2", NUREG/CR-0095, ORNL/NUREG/CSD-6 (1978), and as summarised in ORNL's
// primer "Hand Calculation Methods for Nuclear Criticality Safety" (2023). In that method the
// total solid angle subtended at the centre of any unit by all the other units must not exceed
//     Omega_allowed = 9 - 10 k_eff   steradians   (at most 6 sr),
// where k_eff is that of the most reactive unit alone (the method applies for k_eff <= 0.8),
// and units must be at least 0.3 m (one foot) apart, edge to edge.
//
// THIS IS A DESIGN-SCREENING AID FOR LAYOUT STUDIES, NOT A CRITICALITY SAFETY EVALUATION. The
// method carries further conditions in its source (reflection, moderation, unit shapes) that a
// criticality safety engineer must confirm; the constants are args so a site's own limits can
// be used.
//
// How sscs applies it: each unit is taken as its world-frame bounding box (which contains the
// drum's cylinder, so the solid angles computed are upper bounds: conservative). The solid angle
// of a box seen from a point outside it is the sum, over the faces that point sees, of the
// exact solid angle of each face rectangle.
//
// In a vault (six bounding-box values per unit; `type:drum.bbox` expands to them for every drum):
//   - name: drum array interaction
//     plugin: {class: solid_angle_spacing, attributes: ["type:drum.bbox"], args: {k_eff: 0.6}}
// Args: k_eff (required), min_spacing (m, default 0.3), a and b of Omega = a - b k_eff (9, 10),
// max_solid_angle (sr, default 6).
// Margin: allowed minus the largest total solid angle (sr); when two units are closer than
// min_spacing, the smallest gap minus min_spacing (m) instead.
#include <sscs/plugin.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

struct Unit {
  std::string name;
  std::array<double, 3> lo, hi;
  std::array<double, 3> centre() const { return {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2}; }
};

std::string fixed(double x, int digits = 2) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  return buf;
}

/// The units from the values: six per unit, "NAME.bbox.min.x" ... "NAME.bbox.max.z" in that order.
std::vector<Unit> units(const sscs::plugin::Inputs& in) {
  static const char* kSuffix[6] = {".bbox.min.x", ".bbox.min.y", ".bbox.min.z", ".bbox.max.x", ".bbox.max.y", ".bbox.max.z"};
  if (in.count % 6 != 0) throw std::runtime_error("expects six bounding-box values per unit (write UNIT.bbox)");
  std::vector<Unit> out;
  for (size_t i = 0; i < in.count; i += 6) {
    Unit u;
    std::string first = in.ref(i);
    u.name = first.substr(0, first.rfind(".bbox.min.x"));
    for (size_t k = 0; k < 6; ++k) {
      if (in.ref(i + k) != u.name + kSuffix[k])
        throw std::runtime_error("expects UNIT.bbox (min x, y, z, max x, y, z); found " + in.ref(i + k));
      (k < 3 ? u.lo[k] : u.hi[k - 3]) = in.value(i + k);
    }
    out.push_back(u);
  }
  return out;
}

/// The solid angle of the rectangle [x1, x2] x [y1, y2] in a plane at distance d > 0 from the
/// viewpoint (coordinates relative to the foot of the perpendicular).
double rectangle(double x1, double x2, double y1, double y2, double d) {
  auto F = [d](double x, double y) { return std::atan2(x * y, d * std::sqrt(x * x + y * y + d * d)); };
  return F(x2, y2) - F(x1, y2) - F(x2, y1) + F(x1, y1);
}

/// The solid angle box `b` subtends at point p (outside it): its faces p sees.
double solid_angle(const Unit& b, const std::array<double, 3>& p) {
  double total = 0;
  for (int a = 0; a < 3; ++a) {
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    for (double plane : {b.lo[a], b.hi[a]}) {
      bool sees = plane == b.lo[a] ? p[a] < plane : p[a] > plane;
      if (!sees) continue;
      total += rectangle(b.lo[u] - p[u], b.hi[u] - p[u], b.lo[v] - p[v], b.hi[v] - p[v], std::abs(p[a] - plane));
    }
  }
  return total;
}

/// Edge-to-edge distance between two boxes (0 when they touch or overlap).
double gap(const Unit& a, const Unit& b) {
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    double g = std::max({0.0, b.lo[k] - a.hi[k], a.lo[k] - b.hi[k]});
    s += g * g;
  }
  return std::sqrt(s);
}

sscs::plugin::Result solid_angle_spacing(const sscs::plugin::Inputs& in) {
  const double k = in.number("k_eff");
  const double min_spacing = in.number("min_spacing", 0.3);
  const double a = in.number("a", 9), b = in.number("b", 10), cap = in.number("max_solid_angle", 6);
  if (k <= 0 || k > 0.8)
    throw std::runtime_error("k_eff " + fixed(k) + " is outside the method's range (0, 0.8]: use a criticality calculation");
  const std::vector<Unit> all = units(in);
  const double allowed = std::min(cap, a - b * k);

  // Spacing first: the solid-angle method presumes units at least min_spacing apart.
  double closest = INFINITY;
  std::string pair;
  for (size_t i = 0; i < all.size(); ++i)
    for (size_t j = i + 1; j < all.size(); ++j)
      if (double g = gap(all[i], all[j]); g < closest) closest = g, pair = all[i].name + " and " + all[j].name;
  if (closest < min_spacing)
    return sscs::plugin::Result::judge(false, closest - min_spacing, "m",
                                       pair + " are " + fixed(closest) + " m apart edge to edge; the solid-angle method needs at least " +
                                           fixed(min_spacing) + " m");

  double worst = 0;
  std::string at = all.empty() ? "" : all[0].name;
  for (const Unit& u : all) {
    double omega = 0;
    for (const Unit& other : all)
      if (&other != &u) omega += solid_angle(other, u.centre());
    if (omega > worst) worst = omega, at = u.name;
  }
  return sscs::plugin::Result::judge(worst <= allowed, allowed - worst, "sr",
                                     "largest total solid angle " + fixed(worst, 3) + " sr, at " + at + " (" +
                                         std::to_string(all.size()) + " units), allowed " + fixed(allowed, 3) +
                                         " sr (" + fixed(a, 1) + " - " + fixed(b, 1) + " k_eff, k_eff " + fixed(k) + ")");
}

}  // namespace

SSCS_PLUGIN(registry) {
  registry.constraint("solid_angle_spacing",
                      "fissile units' interaction by the solid-angle method (TID-7016 Rev. 2): total solid angle "
                      "at each unit <= 9 - 10 k_eff sr, units >= 0.3 m apart",
                      6, SIZE_MAX, solid_angle_spacing);
}
