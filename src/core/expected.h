#pragma once
/// A value, or why there is none: what the library's readers return instead of an error
/// out-parameter (`std::string* error`). The caller reports `error()` through its own sink.
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace sscs {

/// `return Unexpected{"why"};` from a function returning any Expected<T>.
struct Unexpected {
  std::string why;
};

template <class T>
class Expected {
 public:
  Expected(T value) : value_(std::move(value)) {}  // NOLINT: a value converts, as std::expected's
  Expected(Unexpected failure) : error_(std::move(failure.why)) {
    if (error_.empty()) throw std::logic_error("an Expected failure must say why");
  }

  bool has_value() const { return value_.has_value(); }
  explicit operator bool() const { return has_value(); }
  const T& operator*() const& { return *value_; }
  T& operator*() & { return *value_; }
  T&& operator*() && { return std::move(*value_); }
  const T* operator->() const { return &*value_; }
  T* operator->() { return &*value_; }
  /// Why there is no value ("" when there is one).
  const std::string& error() const { return error_; }

 private:
  std::optional<T> value_;
  std::string error_;
};

}  // namespace sscs
