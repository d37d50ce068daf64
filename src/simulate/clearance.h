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
#include <memory>
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
  /// The pair's closest approach so far (a record, certified between samples) and when.
  std::optional<std::pair<double, double>> closest_of(int a, int b) const {
    auto it = pairs_.find(key(a, b));
    if (it == pairs_.end() || it->second.records.empty()) return std::nullopt;
    return std::make_pair(it->second.records.back().distance, it->second.records.back().t);
  }

  /// A contact no physics step saw: between two steps (a thin blade through a thin plate in one
  /// step) the moving object was measured into the other, `depth` deep at `t`, at a pose of its
  /// plan (fast mode) or of the straight motion between two kept step poses (physics mode: the
  /// integrator's own, each body at its step's velocity). The run makes it a collision.
  struct Swept {
    int a = -1, part_a = -1, b = -1, part_b = -1;
    double t = 0, depth = 0;
  };
  /// The contacts found between steps since the last call, in the order found.
  std::vector<Swept> take_swept() { return std::exchange(swept_, {}); }
  /// Deeper than this between two steps is a contact (a touch is none: kTouchTolerance).
  static constexpr double kSweptDepth = kTouchTolerance;
  /// Between two kept step poses the search advances by the distance over the fastest point's
  /// speed, at least this far (m): a contact shallower than it may pass unseen.
  static constexpr double kSweepResolution = 1e-4;

  /// Halves what is left to halve (deferred pieces, below): call once, when the run has ended,
  /// before closest().
  void finish();
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
  /// Fast mode's hand-over set `object` back to where it was at `t_back` (PhysicsWorld::hand_over's
  /// q_from) after the step to `t` was followed: it is at `X_world` at t, and its plan after
  /// t_back is no motion it made (its poses there went into what it met: review 23, a blade's
  /// episode 4.66 mm deep where the run went 2.14 mm).
  void set_back(int object, double t_back, double t, const std::vector<Eigen::Isometry3d>& X_world);
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
  /// `hull`, when given: where `object` can be at any time of [a, b] within the glide when it
  /// only translates then (its joints that move are slides): its poses at the corners of the
  /// box its joint values stay in; false when it turns. A bound between two sub-steps then
  /// needs only how far it goes towards the other (a drum lowered beside another is as far
  /// from it all the way down), not how far it goes.
  using HullSource = std::function<bool(double a, double b, std::vector<std::vector<Eigen::Isometry3d>>& corners)>;
  void glide(int object, double from, double to, double step, PoseSource source, HullSource hull = {});
  /// The span `object`'s path last got, when it ends at `from`, made to end at `to` instead
  /// (the same plan goes on: a run's next step); false when there is none such.
  bool extend(int object, double from, double to);
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
  /// Keeps a distance of the pair at `t` (a's part part_a to b's part_b, named as the run names
  /// them) when it is a new closest not excused.
  void keep(Pair& pair, double distance, double t, int a, int part_a, int b, int part_b);
  /// A distance measured at time `t` (a sample, or a pose halving found) where the pair counts:
  /// the run's closest approach is no farther (nearest_).
  void saw(const Pair& pair, double distance, double t);
  /// A record at `t` of the pair keeping_ is keeping may yet be excused (provisional()).
  bool provisional_at(double t) const;

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
      HullSource hull;
    };
    std::vector<Span> spans;  ///< glides since the sample (fast mode)
    /// The glide that [from, to] lies in. The times compared come apart by more than 1e-12:
    /// the physics' clock adds its steps (54.418 after 54,418 of them is not 54418 × 0.001), and
    /// a glide's sub-step then went unfound and its bound, 0.087 m coarse, was the run's figure.
    const Span* span(double from, double to) const {
      for (const Span& s : spans)
        if (from >= s.from - 1e-7 && to <= s.to + 1e-7) return &s;
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
  /// each distance less other.shift(); or `floor`, a better bound found otherwise (slab_over).
  void keep_bound(Pair& pair, int moving, const Other& other, const Proximity& at_i, double t_i, const Proximity& at_j, double t_j,
                  double D, double floor = -INFINITY);
  /// How near a lower bound must come to a distance measured to need no halving.
  static double certify_tolerance(double d) { return std::max(kCertifyTolerance, kCertifyFraction * d); }
  /// A bound that cannot be the run's closest approach, or only by less than the tolerance: not
  /// below every record, or within the tolerance of a distance measured where it counts (the
  /// run's closest approach is no farther than that). Kept unhalved, such a bound leaves the
  /// run's figure within the tolerance of the truth, as a halved one is, and the store's crane
  /// run, passing its drums at the same 0.139 m rack after rack, halves one pass, not each.
  bool moot(double lower) const { return lower >= best_ || lower >= nearest_ - certify_tolerance(nearest_); }

  /// One pair's motion between two samples, as its pieces are halved: the moving object's path
  /// (kept poses, glides), the other's (kept with it, or where it stood: its `now` then), the
  /// parts measured. Shared by the pieces deferred; the paths are frozen copies once the next
  /// interval begins (next_interval() starts a new one where a piece still holds the old).
  struct Motion {
    int moving = -1, other = -1;
    double travel = 0;  ///< how far the other went (its shift when it is not kept with `mine`)
    bool with = false;  ///< the other kept at the same steps: placed with the moving one
    std::shared_ptr<const Path> mine, theirs;
    /// The other, when it has no path this interval (it stood still): where it stood. A piece
    /// halved after it moved on measured it where it was by then (a forklift's body read 0.63 m
    /// into a drum 1.1 m away, that it carried later).
    std::optional<Eigen::Isometry3d> other_at;
    std::vector<char> parts;
    Other as_other() const { return Other{other, with ? theirs.get() : nullptr, travel}; }
  };
  /// A piece of a motion whose bound is below every record so far: it could be the run's
  /// closest approach, or not, which a later record may tell. Halving it is the cost, so it
  /// waits (best first, lowest bound first) until the run ends or too many wait: a drum
  /// hovering over its pallet, nearer by 0.1 mm a step, is news at each sample until the run's
  /// real closest approach comes later and makes every piece before it moot.
  struct Piece {
    double lower = 0;
    long order = 0;  ///< ties broken by age: deterministic
    std::shared_ptr<const Motion> motion;
    size_t i = 0, j = 0;  ///< kept poses i..j of motion->mine; or, for a glide's piece:
    const Path::Span* span = nullptr;
    const Path::Span* their_span = nullptr;
    double t_a = 0, t_b = 0;
    std::vector<Eigen::Isometry3d> X_a, X_b, Y_a, Y_b;
    Proximity at_a, at_b;
  };
  /// The pair's lower bound between the kept poses i and j of the motion's moving object
  /// (distances at_i and at_j there): kept, or deferred for halving where it could be news.
  void refine(const std::shared_ptr<const Motion>& motion, size_t i, size_t j, const Proximity& at_i, const Proximity& at_j);
  /// refine() between two times of a glide, its poses from `span`'s source (and the other's
  /// from `theirs`, when it glides too: Y_a, Y_b its poses at the ends).
  void refine_span(const std::shared_ptr<const Motion>& motion, const Path::Span& span, const Path::Span* theirs, double t_a,
                   double t_b, const std::vector<Eigen::Isometry3d>& X_a, const std::vector<Eigen::Isometry3d>& X_b,
                   const std::vector<Eigen::Isometry3d>& Y_a, const std::vector<Eigen::Isometry3d>& Y_b, const Proximity& at_a,
                   const Proximity& at_b);
  /// The bound slab_bound() gives the moving object's glide from t_a to t_b (poses X_a, X_b at
  /// its ends) against the other standing, from either end; -inf when not known (it turns).
  double slab_over(const Motion& m, const Path::Span& span, double t_a, double t_b, const std::vector<Eigen::Isometry3d>& X_a,
                   const std::vector<Eigen::Isometry3d>& X_b);
  void defer(Piece piece);
  /// The heap's order: the lowest bound on top, the oldest first among equals.
  static bool later(const Piece& a, const Piece& b);
  /// Halves the deferred pieces, lowest bound first, until what they hold is at most
  /// `keep_bytes` (a piece moot() by then is kept as its bound, unhalved); everything placed to
  /// halve is put back where the run has it.
  void settle(size_t keep_bytes);
  /// What the pieces waiting hold: their own poses, and once each path they share.
  static size_t bytes(const Piece& piece);
  void hold(const Path* path, int by);
  std::unordered_map<const Path*, std::pair<long, size_t>> held_;  ///< per path: pieces holding it, its bytes
  size_t held_bytes_ = 0;
  /// The piece halved at its middle, each half refined again.
  void halve(const Piece& piece, std::set<int>& placed);
  /// What halve() placed at a Motion's other_at, and where it is to go back to.
  std::map<int, Eigen::Isometry3d> put_back_;
  /// What the pieces waiting during a run may hold (their poses); beyond it, the lowest are
  /// halved until half is left. Halving during the run is where waiting was worth it: the store's
  /// 40-drum campaign holds about 85 MiB by its end, its crane's bridge passing the front wall
  /// 0.2 m away all along (each pass a new closest so far until two drums stand 0.139 m apart
  /// late in the run); at 48 MiB it halved 1.7 million of those pieces mid-run (23 s of 27).
  static constexpr size_t kMaxDeferredBytes = size_t{256} << 20;

  /// Whether a piece from t_a to t_b whose ends are d_a and d_b apart and whose bound is `lower`
  /// could hide a contact no step saw: not into each other at either end (the steps' contacts
  /// tell those), apart by more than kSweepResolution at one at least (a load resting or sliding
  /// on what it touches is no pass through it: halving each of its steps made a stalled arm's
  /// run ten times slower), not excused, the bound below a contact's depth. Such a piece is
  /// halved (and swept) whether or not it is news.
  bool unsure(const Pair& pair, double lower, double d_a, double d_b, double t_a, double t_b) const {
    return lower < -kSweptDepth && std::min(d_a, d_b) >= -kSweptDepth && std::max(d_a, d_b) > kSweepResolution &&
           !pair.excused_over(t_a, t_b);
  }
  /// Where the two are at fraction s of a piece: the moving object's poses, and the other's when
  /// it moves with it.
  using SweepPoses = std::function<void(double s, std::vector<Eigen::Isometry3d>& X, std::vector<Eigen::Isometry3d>& Y)>;
  /// Conservative advancement from t_a (the pair `at_a` apart) to t_b, where no point of the two
  /// goes farther than D: the deepest pose into the other found, if any, is a Swept contact and
  /// the pair's distance then.
  void sweep(const Motion& m, double t_a, double t_b, double D, const Proximity& at_a, const SweepPoses& poses);
  /// Physics mode: conservative advancement along the straight motion from kept step pose i to
  /// i + 1 (each part's frame moved at constant velocity and turning rate), for a contact no step
  /// saw; `D` bounds how far any point of the two goes in that step. A pose found into the other
  /// is noted (note_swept) and kept as the pair's distance.
  void sweep_step(const Motion& m, size_t i, const Proximity& at_i, double D);
  std::vector<Swept> swept_;

  /// The earliest kept pose in (i, j] nearer than `gap`: the interval halved, the earlier half
  /// searched first, a piece whose bound clears the gap skipped.
  std::optional<Dip> first_dip(double gap, int moving, const Other& other, const std::vector<char>& parts, const Path& p, size_t i,
                               size_t j, const Proximity& at_i, const Proximity& at_j);

  const Workcell& wc_;
  const GeometryModel& geometry_;
  CollisionWorld nearby_;
  struct KeyHash {
    size_t operator()(const Key& k) const {
      return std::hash<uint64_t>{}((static_cast<uint64_t>(static_cast<uint32_t>(k.first)) << 32 | static_cast<uint32_t>(k.second)) *
                                   0x9e3779b97f4a7c15ull);
    }
  };
  /// Looked up per pair a sample measures (hashed: an ordered map was 4 % of a campaign's time);
  /// closest() breaks ties by the key, as the ordered map's first did.
  std::unordered_map<Key, Pair, KeyHash> pairs_;
  std::unordered_map<int, std::shared_ptr<Path>> paths_;
  std::vector<Piece> deferred_;  ///< a heap: the lowest bound on top
  std::vector<std::vector<Eigen::Isometry3d>> corners_;  ///< slab_over()'s scratch
  long deferrals_ = 0;
  bool certified_ = true;  ///< every step followed (a tracker without paths measures samples only)
  bool followed_ = false;
  /// The smallest record kept so far (one excused since may have gone): where halving pays.
  double best_ = INFINITY;
  /// The nearest distance measured where a pair counts (saw()): an upper bound of the run's
  /// closest approach.
  double nearest_ = INFINITY;
  double interval_start_ = 0;  ///< the sample the interval under way began at
  /// Distances saw() measured that may yet be excused: they count at finish() if they are not.
  struct Measured {
    Key key;
    double distance = 0, t = 0;
  };
  std::vector<Measured> pending_seen_;
  /// What was measured as moving at this sample and the last, with what it skipped.
  std::map<int, std::vector<int>> measured_now_, measured_before_;
  std::map<int, std::vector<std::pair<double, double>>> provisional_;  ///< per object (provisional())
  std::pair<int, int> keeping_{-1, -1};  ///< the pair whose records keep() is keeping
};

}  // namespace sscs
