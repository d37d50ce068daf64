#pragma once
/// The order a sweep's workers take its variants in.
#include <cstddef>
#include <optional>
#include <vector>

namespace sscs {

/// Hands out tasks 0..n-1 to a number of workers so that each works through a stretch of
/// consecutive tasks: neighbouring variants differ in one parameter, so a worker's remembered
/// collision answers (ContactMemo) serve the next one. A worker whose stretch is done takes the
/// second half of the longest stretch nobody has taken yet, so all finish together.
class Dealer {
 public:
  Dealer(size_t tasks, size_t workers);
  /// The next task for `worker`; nullopt when every task is taken.
  std::optional<size_t> next(size_t worker);
  size_t left() const { return left_; }

 private:
  std::vector<char> taken_;
  std::vector<size_t> cursor_;  ///< per worker: the task after its last
  size_t left_;
};

}  // namespace sscs
