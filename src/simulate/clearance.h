#pragma once
/// A run's clearance tracker: the closest approach, over the run, of each object that moves to
/// each other object within reach, with when and which parts. Lifting a load off what it stands
/// on and setting it down on what it lands on are the job, not a clearance: the moves that do it
/// are excused for that pair alone (the move after the grasp, the move that ended at the
/// release), never for the run, and never a penetration deeper than a contact (a drum lowered
/// through the drum it then landed on is -0.57 m, not the 0.02 m of some other pair).
#include <algorithm>
#include <functional>
#include <map>
#include <set>
#include <unordered_map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "compile/workcell.h"
#include "geometry/collision.h"
#include "geometry/geometry.h"
#include "simulate/summary_file.h"

namespace sscs {

/// How a run's files name object `o`'s part `part`: `Device.part`, else `Object`; `floor` for -1.
std::string run_part_name(const Workcell& wc, const GeometryModel& geometry, int o, int part);

class ClearanceTracker {
 public:
  /// Deeper than this into each other is no contact but a penetration, never excused (m).
  static constexpr double kContact = 0.005;

  ClearanceTracker(const Workcell& wc, const GeometryModel& geometry);
  /// Places a device's parts, or a free object, where the motion has them now.
  void move_parts(int device, const std::vector<Eigen::Isometry3d>& X_world_part) { nearby_.move_parts(device, X_world_part); }
  void move(int object, const Eigen::Isometry3d& X_world_object) { nearby_.move(object, X_world_object); }
  /// The objects within `gap` of `object`, placed at `X_world_object` (what a load stands on when
  /// it is lifted), but `skip`.
  std::vector<int> within(int object, const Eigen::Isometry3d& X_world_object, const std::vector<int>& skip, double gap);
  /// How far `p_world` is from `object`'s solids, the object placed at `X_world_object` (where a
  /// tool is from what it is to grasp).
  double distance_to_point(int object, const Eigen::Isometry3d& X_world_object, const Eigen::Vector3d& p_world) {
    nearby_.move(object, X_world_object);
    return nearby_.distance_to_point(object, p_world).value_or(INFINITY);
  }
  /// The signed distance of two objects where they are now (minus the depth when they
  /// interpenetrate); nullopt when one has no solid.
  std::optional<double> distance(int a, int b) { return nearby_.distance(a, b); }
  /// The collision world the tracker measures in (fast mode's glide asks it what is near).
  CollisionWorld& world() { return nearby_; }

  /// Measures at time `t` how close `moving` (its `parts` only, when given) comes to every other
  /// object within reach but `skip`; keeps each pair's closest approaches.
  void measure(double t, int moving, const std::vector<int>& skip, const std::vector<char>& parts = {});
  /// Measures at time `t` how deep `a` goes into `b` (a device into the load it takes or let
  /// go, which it may touch): only a penetration deeper than a contact is kept.
  void measure_penetration(double t, int a, int b);
  /// The pair's approaches from `from` to `to` are the job (a load's set-down on what it landed
  /// on, its lift off what it stood on): not counted, but for penetrations. `to` may lie ahead.
  void excuse(int a, int b, double from, double to);
  /// `object`'s approaches from `from` to `to` may yet be excused (the move that sets a load
  /// down: what it lands on is known when it lands): they do not decide where halving pays.
  void provisional(int object, double from, double to);

  /// Watches the pair for coming nearer than `gap` (m) between samples (a clearance rule the
  /// run re-checks): where the certified bound over an interval is below it, the interval is
  /// halved at the kept poses of what moves until the bound clears it or a pose is nearer.
  void watch(int a, int b, double gap);
  /// A watched pair nearer than a gap between the last two samples: the earliest such pose, how
  /// near, and the parts as the run names them. Each gap watched on a pair has its own (two
  /// rules on one pair, 3 cm and 1.5 cm: a pose at 2 cm breaks the first only).
  struct Dip {
    double t = 0, distance = 0;
    std::string a, b;
  };
  /// The dip below `gap` (as watched) of the interval that ended at `t` (the sample being
  /// observed), if any.
  std::optional<Dip> dip(int a, int b, double gap, double t) const;

  /// The closest approach of the run: the smallest distance of any pair outside the moves
  /// excused, negative for the deepest penetration; none when nothing came within reach. A
  /// lower bound over the whole motion (certified) when every physics step was followed.
  std::optional<RunSummaryFile::Clearance> closest() const;

  /// Between samples, after every physics step (and once at the start): where `object` is now,
  /// one pose per part for a device, else one. The tracker keeps how far each of its points may
  /// have gone since the last sample and, for what `measure` will move (`keep_path`, decided
  /// from the sample on), every pose, to bound each pair's distance between the samples from
  /// below: a gripper passing a post between two samples 0.5 s apart is seen.
  void follow(double t, int object, const std::vector<Eigen::Isometry3d>& X_world, bool keep_path);
  /// How far the points of each part of `object` (one entry for an object) may have gone since
  /// the last sample, from the steps followed; nullptr when it is not followed (it stands).
  const std::vector<double>* travelled(int object) const {
    const Path* p = path(object);
    return p && !p->travelled.empty() ? &p->travelled.back() : nullptr;
  }
  /// At the sample at `t`, after every measure(): the paths start again from where everything is.
  void next_interval(double t);
  /// Where `object` is at any time of [from, to] (one pose per part for a device, else one).
  using PoseSource = std::function<void(double t, std::vector<Eigen::Isometry3d>& X_world)>;
  /// Fast mode's glide: between its followed sub-steps from `from` to `to`, `object`'s poses come
  /// from `source` (its plan), so a bound between two sub-steps is halved in time, as between
  /// the kept poses of physics steps, down to `step` (s, the physics step: as fine as they are).
  void glide(int object, double from, double to, double step, PoseSource source);
  /// Closer than this to the measured distance (m), or than kCertifyFraction of it, a lower
  /// bound is not refined further: 0.1 mm near, 2 mm at 2 m, where no closest approach is.
  static constexpr double kCertifyTolerance = 1e-4, kCertifyFraction = 1e-3;

 private:
  struct Seen {
    double distance = INFINITY;
    double t = 0;
    std::string a, b;  ///< `Object` or `Device.part`
  };
  struct Pair {
    /// Each sample closer than every earlier one still counted, in time order: excusing a
    /// stretch of time drops its records and leaves the closest before it.
    std::vector<Seen> records;
    std::vector<std::pair<double, double>> excused;  ///< (from, to) stretches ahead or under way
    double sampled_at = -1;  ///< when the pair was last measured at a sample, and how near it was then
    Proximity sampled;
    std::vector<double> watches;   ///< gaps the run re-checks (watch())
    std::map<double, Dip> dips;    ///< per gap: nearer than it between the samples ending at dip_at
    double dip_at = -1;
    double watch() const { return watches.empty() ? -INFINITY : *std::max_element(watches.begin(), watches.end()); }
    double closest() const { return records.empty() ? INFINITY : records.back().distance; }
    bool is_excused(double t) const;
    /// Excused over the whole of [from, to] (by one stretch).
    bool excused_over(double from, double to) const;
  };
  using Key = std::pair<int, int>;  ///< (lower object, higher object)
  static Key key(int a, int b) { return {std::min(a, b), std::max(a, b)}; }
  void keep(Pair& pair, Seen seen);

  /// An object's motion since the last sample: where it was then, and after each step how far
  /// each part's points may have gone since (a bound), with the poses when kept.
  struct Path {
    std::vector<Eigen::Isometry3d> now;                 ///< per part (one for an object)
    std::vector<double> t;                              ///< the sample's time, then (kept) each step's
    std::vector<std::vector<Eigen::Isometry3d>> poses;  ///< at each of t: the sample's first
    std::vector<std::vector<double>> travelled;         ///< kept: at each of t, per part; else one entry
    bool keep = false, decided = false;
    struct Span {
      double from = 0, to = 0, step = 0;
      PoseSource source;
    };
    std::vector<Span> spans;  ///< glides since the sample (fast mode)
    const Span* span(double from, double to) const {
      for (const Span& s : spans)
        if (from >= s.from - 1e-12 && to <= s.to + 1e-12) return &s;
      return nullptr;
    }
    const std::vector<Eigen::Isometry3d>& start() const { return poses.front(); }
    double total() const;  ///< the most any point went since the sample
    double between(size_t i, size_t j) const;  ///< the most any point went from t[i] to t[j]
  };
  const Path* path(int object) const;
  void place(int object, const std::vector<Eigen::Isometry3d>& X_world);
  /// The other object of a pair measured between samples: kept at the same steps as the moving
  /// one (placed with it at each halving), or standing where it is now having gone `travel`.
  struct Other {
    int object = -1;
    const Path* path = nullptr;
    double travel = 0;
    double between(size_t i, size_t j) const { return path ? path->between(i, j) : 0.0; }
    /// What each distance measured with it where it is now is less: how far it went.
    double shift() const { return path ? 0.0 : travel; }
  };
  /// Keeps the pair's lower bound over an interval whose ends are `at_i` (at t_i) and `at_j`
  /// (at t_j) apart and over which the two went `D` at most: min(d_i, d_j, (d_i + d_j − D) / 2),
  /// each distance less other.shift().
  void keep_bound(Pair& pair, int moving, const Other& other, const Proximity& at_i, double t_i, const Proximity& at_j, double t_j,
                  double D);
  /// The pair's lower bound between the kept poses i and j of `moving` (distances di and dj
  /// there): refined by halving where it could be news, each piece kept as a record.
  void refine(Pair& pair, int moving, const Other& other, const std::vector<char>& parts, const Path& p, size_t i, size_t j,
              const Proximity& at_i, const Proximity& at_j);

  /// refine() between two times of a glide, its poses from `span`'s source (and the other's
  /// from `theirs`, when it glides too: Y_a, Y_b its poses at the ends).
  void refine_span(Pair& pair, int moving, const Other& other, const Path::Span* theirs, const std::vector<char>& parts,
                   const Path::Span& span, double t_a, double t_b, const std::vector<Eigen::Isometry3d>& X_a,
                   const std::vector<Eigen::Isometry3d>& X_b, const std::vector<Eigen::Isometry3d>& Y_a,
                   const std::vector<Eigen::Isometry3d>& Y_b, const Proximity& at_a, const Proximity& at_b);

  /// The earliest kept pose in (i, j] nearer than `gap`: the interval halved, the earlier half
  /// searched first, a piece whose bound clears the gap skipped.
  std::optional<Dip> first_dip(double gap, int moving, const Other& other, const std::vector<char>& parts, const Path& p, size_t i,
                               size_t j, const Proximity& at_i, const Proximity& at_j);

  const Workcell& wc_;
  const GeometryModel& geometry_;
  CollisionWorld nearby_;
  std::map<Key, Pair> pairs_;
  std::unordered_map<int, Path> paths_;
  bool certified_ = true;  ///< every step followed (a tracker without paths measures samples only)
  bool followed_ = false;
  /// The smallest record kept so far (one excused since may have gone): where halving pays.
  double best_ = INFINITY;
  /// What was measured as moving at this sample and the last, with what it skipped.
  std::map<int, std::vector<int>> measured_now_, measured_before_;
  std::map<int, std::vector<std::pair<double, double>>> provisional_;  ///< per object (provisional())
  std::pair<int, int> keeping_{-1, -1};  ///< the pair whose records keep() is keeping
};

}  // namespace sscs
