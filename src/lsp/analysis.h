#pragma once
/// What `sscs lsp` knows of a file an editor has open: the file compiled (and a vault checked)
/// from the editor's buffers, saved or not, and its problems placed as LSP places them.
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "check/check.h"
#include "compile/compile.h"
#include "core/source.h"
#include "geometry/geometry.h"

namespace sscs::lsp {

/// What a file is, by its top-level key (`vault:`, `scenario:`/`campaign:`, `type:`).
enum class FileKind { Vault, Scenario, Type, Other };
FileKind file_kind(std::string_view text);

/// One compile of a file. Immutable once made; shared by the requests that read it.
struct Analysis {
  std::string path;  ///< absolute, lexically normal
  FileKind kind = FileKind::Other;
  Sources sources;
  Diagnostics diag;
  std::optional<Workcell> wc;  ///< a vault's (a scenario's vault's), when it compiled
  GeometryModel geometry;
  std::optional<CheckReport> report;  ///< a vault's check
  /// The file's own text as it was analysed (its index in `sources`, 0 when it was not read).
  uint32_t file = 0;
};

/// Compiles the file `path` (absolute) of kind `kind`, with `unsaved` standing in for the files
/// the editor has open, and checks it when it is a vault.
/// `library` keeps the vault's type library between its compiles (a keystroke compiles the vault,
/// not the library). `cancel`: when it turns true, the check stops (CheckCancelled): a newer
/// edit supersedes it.
std::shared_ptr<const Analysis> analyze(const std::string& path, FileKind kind, std::shared_ptr<const Sources::Unsaved> unsaved,
                                        const CompileOptions& options, LibraryCache& library,
                                        const std::atomic<bool>* cancel = nullptr);

/// A range of a file as LSP counts: 0-based lines, and characters in UTF-16 code units (or bytes
/// when the client speaks UTF-8).
struct Range {
  int line = 0, character = 0, end_line = 0, end_character = 0;
};

/// One problem of an analysis at its place: an input error or warning, or a failed constraint.
struct Problem {
  Range range;
  int severity = 1;  ///< LSP's DiagnosticSeverity: 1 error, 2 warning
  std::string message;
};

/// The problems of an analysis, by the absolute path of the file they are in: input errors and
/// warnings where they are, failed constraints at the constraint's line with the values and the
/// margin (passing ones not). A failure of a type file's constraint is also shown at the object
/// it failed for, when the object is in the analysed file.
std::map<std::string, std::vector<Problem>> problems(const Analysis& analysis, bool utf8);

/// The UTF-16 column (or the byte column, when `utf8`) of byte column `byte` of `line`.
int client_column(std::string_view line, size_t byte, bool utf8);
/// The byte column of the client's column `column` of `line`.
size_t byte_column(std::string_view line, int column, bool utf8);
/// The range of the token a mark points at: a quoted scalar to its closing quote, else up to
/// the next space, comma, bracket, brace or `: `; a whole line when the mark has no column.
Range token_range(const Sources& sources, SourceMark mark, bool utf8);

}  // namespace sscs::lsp
