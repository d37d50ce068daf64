#pragma once
/// Source files read by sscs and positions inside them.
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace sscs {

/// A position in an input file: 1-based line and column (in bytes; reports show
/// Sources::character_column). file == 0 means "no file".
struct SourceMark {
  uint32_t file = 0;
  uint32_t line = 0;
  uint32_t column = 0;
  bool valid() const { return file != 0; }
};

/// Owns the text of every file read, so a diagnostic found at any stage can quote its line.
/// Not copyable (marks index into it); movable.
/// The characters (UTF-8 code points) in the first `bytes` bytes of `text`.
size_t characters(std::string_view text, size_t bytes);

class Sources {
 public:
  Sources();
  Sources(const Sources&) = delete;
  Sources& operator=(const Sources&) = delete;
  Sources(Sources&&) = default;
  Sources& operator=(Sources&&) = default;

  /// Registers a file's text and returns its index for SourceMark::file.
  uint32_t add(std::string path, std::string text);
  const std::string& path(uint32_t file) const { return files_.at(file).path; }
  const std::string& text(uint32_t file) const { return files_.at(file).text; }
  /// The index of the file registered as `path`, or 0 when none was.
  uint32_t find(std::string_view path) const;
  /// The text of the line a mark points into, without its line break.
  std::string_view line(const SourceMark& mark) const;
  /// The column a user reads for `mark`: the characters (Unicode code points) before it on its
  /// line, plus one, as editors and compilers count. `mark.column` counts bytes (as the YAML
  /// reader does): `name: "Drüm → 2", x: [` puts `[` at byte 22 and character 19.
  uint32_t character_column(const SourceMark& mark) const;
  size_t size() const { return files_.size(); }

  /// Texts that stand in for files on disk, by absolute path (an editor's unsaved buffers, given
  /// by `sscs lsp`): read_source() takes the text from here, not from the disk. The one seam
  /// between the inputs and the file system for the YAML files; nothing is written anywhere.
  using Unsaved = std::map<std::string, std::string, std::less<>>;
  void set_unsaved(std::shared_ptr<const Unsaved> texts) { unsaved_ = std::move(texts); }
  const std::shared_ptr<const Unsaved>& unsaved_texts() const { return unsaved_; }
  /// The unsaved text of `path` (absolute, lexically normal), or null: read the disk.
  const std::string* unsaved(std::string_view path) const;

 private:
  struct File {
    std::string path;
    std::string text;
    bool ascii = true;  ///< every byte below 0x80: a column in characters is the column in bytes
  };
  std::vector<File> files_;
  std::shared_ptr<const Unsaved> unsaved_;
};

}  // namespace sscs
