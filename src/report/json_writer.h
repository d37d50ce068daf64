#pragma once
/// A streaming JSON writer whose output is byte for byte nlohmann::json's dump(2) (two-space
/// indent, `"key": value`, empty containers as [] and {}, numbers and escapes alike), so reports
/// are written as they are produced instead of being built as one tree first: a report of
/// 100,000 results costs little more memory than the results themselves.
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace sscs {

/// A figure of a report as JSON: stable(v) (12 significant digits), null when absent or not finite.
nlohmann::ordered_json number_or_null(const std::optional<double>& v);

class JsonWriter {
 public:
  explicit JsonWriter(std::ostream& out) : out_(out) { buffer_.reserve(kFlushAt + 4096); }
  ~JsonWriter() { flush(); }
  JsonWriter(const JsonWriter&) = delete;
  JsonWriter& operator=(const JsonWriter&) = delete;

  void begin_object() { open('{'); }
  void end_object() { close('}'); }
  void begin_array() { open('['); }
  void end_array() { close(']'); }
  /// The key of the next value in an object.
  void key(std::string_view k);
  void string(std::string_view s);
  /// A string already written as a JSON literal (append_json_string): a value repeated in every
  /// result, escaped once.
  void literal(std::string_view json);
  void number(double v);    ///< as nlohmann prints a double (750.0, 0.001, 1e-09); null when not finite
  /// number(stable(v)): how reports print their numbers (12 significant digits).
  void stable_number(double v);
  void integer(int64_t v);
  void unsigned_integer(uint64_t v);
  void boolean(bool v);
  void null();
  /// A small tree (a rare part of a report) in the same layout at the current depth.
  void json(const nlohmann::ordered_json& j);

  /// Shorthands for a key and its value.
  template <class T>
  void field(std::string_view k, const T& v) {
    key(k);
    put(v);
  }

 private:
  void open(char bracket);
  void close(char bracket);
  void before_value();
  void put(std::string_view s) { string(s); }
  void put(const std::string& s) { string(s); }
  void put(const char* s) { string(s); }
  void put(double v) { number(v); }
  void put(bool v) { boolean(v); }
  void put(int v) { integer(v); }
  void put(unsigned v) { unsigned_integer(v); }
  void put(long v) { integer(v); }
  void put(unsigned long v) { unsigned_integer(v); }
  void put(const nlohmann::ordered_json& j) { json(j); }
  void newline_indent();
  /// Output goes through a buffer written out in large pieces (an ostream per token is slow).
  void flush() {
    out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    buffer_.clear();
  }
  void maybe_flush() {
    if (buffer_.size() >= kFlushAt) flush();
  }
  static constexpr size_t kFlushAt = 1 << 16;

  std::ostream& out_;
  std::string buffer_;
  struct Level {
    char closer;
    size_t count = 0;
  };
  std::vector<Level> stack_;
  bool after_key_ = false;
};

/// `s` as a JSON string literal, escaped as nlohmann escapes it; invalid UTF-8 becomes U+FFFD.
void append_json_string(std::string& out, std::string_view s);
/// A double as nlohmann prints it.
void append_json_number(std::string& out, double v);
/// append_json_number(out, stable(v)).
void append_json_stable_number(std::string& out, double v);

}  // namespace sscs
