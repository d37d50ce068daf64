#include "sweep/dealer.h"

namespace sscs {

Dealer::Dealer(size_t tasks, size_t workers) : taken_(tasks, 0), cursor_(workers == 0 ? 1 : workers), left_(tasks) {
  for (size_t w = 0; w < cursor_.size(); ++w) cursor_[w] = w * tasks / cursor_.size();
}

std::optional<size_t> Dealer::next(size_t worker) {
  if (left_ == 0) return std::nullopt;
  size_t& at = cursor_.at(worker);
  if (at >= taken_.size() || taken_[at]) {
    // The longest run of untaken tasks: start at its middle (its first half stays with whoever
    // works towards it).
    size_t best_start = 0, best_length = 0;
    for (size_t k = 0; k < taken_.size();) {
      if (taken_[k]) {
        ++k;
        continue;
      }
      size_t start = k;
      while (k < taken_.size() && !taken_[k]) ++k;
      if (k - start > best_length) best_start = start, best_length = k - start;
    }
    at = best_start + best_length / 2;
  }
  taken_[at] = 1;
  --left_;
  return at++;
}

}  // namespace sscs
