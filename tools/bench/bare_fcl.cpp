// The baseline of tools/bench/spatial_vs_fcl.py: the same rack boxes as the generated vault,
// in a bare FCL DynamicAABBTree manager, running the same two queries as sscs's no_overlap and
// clearance constraints. With --naive it also times all pairs without a broadphase.
//
// usage: bare_fcl ROWS COLS PITCH_X PITCH_Y MIN_CLEARANCE [--naive N]
#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

namespace {

struct Rack {
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> parts;
};

// The standard rack's default geometry: two uprights and a bottom beam (library/types/rack.yaml).
Rack make_rack(double x, double y) {
  const double L = 2.743, D = 1.067, H = 4.877;
  struct B {
    double sx, sy, sz, cx, cy, cz;
  } boxes[] = {{0.08, D, H, 0.04, D / 2, H / 2}, {0.08, D, H, L - 0.04, D / 2, H / 2}, {L, D, 0.1, L / 2, D / 2, 0.1}};
  Rack r;
  for (const B& b : boxes) {
    fcl::Transform3d X = fcl::Transform3d::Identity();
    X.translation() = fcl::Vector3d(x + b.cx, y + b.cy, b.cz);
    auto o = std::make_unique<fcl::CollisionObjectd>(std::make_shared<fcl::Boxd>(b.sx, b.sy, b.sz), X);
    o->computeAABB();
    r.parts.push_back(std::move(o));
  }
  return r;
}

double signed_distance(const Rack& a, const Rack& b) {
  double best = 1e300;
  for (const auto& x : a.parts)
    for (const auto& y : b.parts) {
      fcl::CollisionRequestd creq(1, true);
      fcl::CollisionResultd cres;
      if (fcl::collide(x.get(), y.get(), creq, cres) > 0) {
        best = std::min(best, -cres.getContact(0).penetration_depth);
        continue;
      }
      fcl::DistanceRequestd dreq(false, false, 1e-9, 1e-9, 1e-9, fcl::GST_INDEP);
      fcl::DistanceResultd dres;
      fcl::distance(x.get(), y.get(), dreq, dres);
      best = std::min(best, dres.min_distance);
    }
  return best;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 6) {
    std::fprintf(stderr, "usage: bare_fcl ROWS COLS PITCH_X PITCH_Y MIN_CLEARANCE [--naive N]\n");
    return 2;
  }
  int rows = std::atoi(argv[1]), cols = std::atoi(argv[2]);
  double px = std::atof(argv[3]), py = std::atof(argv[4]), min = std::atof(argv[5]);
  int naive = argc > 7 && std::strcmp(argv[6], "--naive") == 0 ? std::atoi(argv[7]) : 0;
  auto start = std::chrono::steady_clock::now();
  std::vector<Rack> racks;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) racks.push_back(make_rack(i * px, j * py));
  // Broadphase over each rack's grown bounding box, as sscs does per object.
  auto candidates = [&](double grow) {
    std::vector<std::unique_ptr<fcl::CollisionObjectd>> boxes;
    std::vector<fcl::CollisionObjectd*> reg;
    for (size_t k = 0; k < racks.size(); ++k) {
      fcl::AABBd box = racks[k].parts[0]->getAABB();
      for (const auto& p : racks[k].parts) box += p->getAABB();
      fcl::Vector3d size = box.max_ - box.min_ + fcl::Vector3d::Constant(2 * grow);
      fcl::Transform3d X = fcl::Transform3d::Identity();
      X.translation() = box.center();
      auto o = std::make_unique<fcl::CollisionObjectd>(std::make_shared<fcl::Boxd>(size), X);
      o->setUserData(reinterpret_cast<void*>(k));
      o->computeAABB();
      reg.push_back(o.get());
      boxes.push_back(std::move(o));
    }
    fcl::DynamicAABBTreeCollisionManagerd manager;
    manager.registerObjects(reg);
    manager.setup();
    std::vector<std::pair<size_t, size_t>> pairs;
    manager.collide(&pairs, [](fcl::CollisionObjectd* a, fcl::CollisionObjectd* b, void* d) {
      static_cast<std::vector<std::pair<size_t, size_t>>*>(d)->emplace_back(reinterpret_cast<size_t>(a->getUserData()),
                                                                             reinterpret_cast<size_t>(b->getUserData()));
      return false;
    });
    return pairs;
  };
  size_t overlaps = 0, close = 0;
  for (auto [a, b] : candidates(1e-6))
    if (signed_distance(racks[a], racks[b]) < -1e-6) ++overlaps;
  for (auto [a, b] : candidates(min))
    if (signed_distance(racks[a], racks[b]) < min) ++close;
  double broad = seconds_since(start);
  std::printf("racks %zu overlapping %zu closer-than-min %zu broadphase %.3f s\n", racks.size(), overlaps, close, broad);
  if (naive > 0) {
    // All pairs among the first `naive` racks, scaled to the full count (n^2 growth).
    auto t = std::chrono::steady_clock::now();
    size_t n = std::min<size_t>(naive, racks.size()), hits = 0;
    for (size_t a = 0; a < n; ++a)
      for (size_t b = a + 1; b < n; ++b)
        if (signed_distance(racks[a], racks[b]) < min) ++hits;
    double s = seconds_since(t);
    double scale = (double(racks.size()) * (racks.size() - 1)) / (double(n) * (n - 1));
    std::printf("naive all pairs over %zu racks: %.3f s, estimated for %zu racks: %.1f s\n", n, s, racks.size(), s * scale);
  }
  return 0;
}
