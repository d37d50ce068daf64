#pragma once
/// The one diagnostic sink of sscs: every stage reports input errors here; it collects, never throws.
#include <string>
#include <vector>

#include "core/source.h"

namespace sscs {

/// Text from input as it may be shown on a terminal, in a log or in XML: control bytes (escape
/// sequences, NUL, DEL; newlines unless kept), bidirectional control characters (a right-to-left
/// override) and bytes that are not UTF-8 become '?'. Column positions stay (one byte, one '?').
std::string printable(std::string_view text, bool keep_newlines = false);
/// Text of at most about `max` bytes: a long expression quoted in an error shows its start and
/// end around "… (N bytes not shown) …".
std::string within_window(std::string_view text, size_t max = 2000);

struct Diagnostic {
  SourceMark mark;
  std::string message;
  bool warning = false;  ///< something skipped or assumed that the user should know; not an error
};

/// Collects input errors with their source marks. After `limit` errors further ones are counted
/// but not kept, so a file with thousands of mistakes still reports promptly.
class Diagnostics {
 public:
  static constexpr size_t kDefaultLimit = 50;
  explicit Diagnostics(size_t limit = kDefaultLimit) : limit_(limit) {}

  void error(SourceMark mark, std::string message);
  /// Something the input does that sscs skips or works around (a degenerate shape in a vendor's
  /// URDF): shown on stderr, never fails the command (unless strict: then it is an error). Kept
  /// up to the same limit, once each.
  void warning(SourceMark mark, std::string message);
  const std::vector<Diagnostic>& warnings() const {
    examined_warnings_ = warnings_.size();
    return warnings_;
  }
  bool has_errors() const { return count_ > 0; }
  size_t count() const { return count_; }
  bool full() const { return count_ >= limit_; }
  const std::vector<Diagnostic>& errors() const {
    examined_errors_ = errors_.size();
    return errors_;
  }

  /// Strict (Drake's diagnostic policy with warnings turned into errors): warning() records an
  /// error, its message followed by `note` (what made it one), so nothing sscs skipped or
  /// assumed passes (`sscs check --strict`).
  void set_strict(bool strict, std::string note = {}) {
    strict_ = strict;
    strict_note_ = std::move(note);
  }
  bool strict() const { return strict_; }
  /// Whether a diagnostic was recorded that nothing has looked at since: errors(), warnings(),
  /// format() and format_errors() look. The tests' fixtures fail on one left unchecked.
  bool unexamined() const { return errors_.size() > examined_errors_ || warnings_.size() > examined_warnings_; }

  /// `file:line:col: warning: message` for each warning, then `file:line:col: error: message` for
  /// each error, each with the source line and a caret under the column; then a line saying how
  /// many errors were not shown when the limit was reached.
  std::string format(const Sources& sources, bool color = false) const;
  /// format() without the warnings.
  std::string format_errors(const Sources& sources, bool color = false) const;

 private:
  size_t limit_;
  bool strict_ = false;
  std::string strict_note_;
  size_t count_ = 0;
  mutable size_t examined_errors_ = 0, examined_warnings_ = 0;
  std::vector<Diagnostic> errors_;
  std::vector<Diagnostic> warnings_;
};

/// An error that must stop the current stage at once (a file that cannot be read as YAML).
/// Thrown only inside a stage and caught at its edge, which reports it through Diagnostics.
struct InputError {
  SourceMark mark;
  std::string message;
};

}  // namespace sscs
