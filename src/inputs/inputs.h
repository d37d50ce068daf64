#pragma once
/// The inputs stage: everything a compile reads, gathered once from the file system (through
/// Sources, which takes an editor's unsaved buffers in place of the disk: Sources::unsaved): the
/// type files of the vault's library folders loaded, its plugins loaded, and what the files that
/// input files name are (where a mesh reference resolves, whether it can be read). compile()
/// takes this set and never touches the file system (tests/layering/check_includes.py bans it).
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/diagnostics.h"
#include "core/source.h"
#include "load/spec.h"
#include "plugin/plugins.h"

namespace sscs {

struct ObjectType;

struct CompileOptions {
  std::vector<std::string> library_dirs;  ///< extra type folders (--library), after the vault's own
  std::vector<std::string> package_paths;  ///< --package-path: roots of `package://` references in URDF
  std::vector<std::string> plugin_dirs;   ///< --plugins: folders whose plugins are loaded
  bool allow_vault_plugins = false;       ///< --allow-vault-plugins: load the vault's `plugins:` folders too
  std::shared_ptr<PluginSet> plugins;     ///< where loaded plugins go (created when null)
  std::vector<std::pair<std::string, std::string>> overrides;  ///< --set NAME=VALUE
  /// The type library already loaded (a Workcell's `types` compiled from the same vault file with
  /// the same plugins): compile() then reads no type file and loads no plugin. A sweep compiles
  /// each variant this way.
  std::shared_ptr<const std::vector<ObjectType>> library;
  /// Compile the templates of every type of the library, not only those the vault's objects use
  /// (a library kept for other vaults, or variants, to reuse: a sweep's).
  bool whole_library = false;
};

/// What the files that input files name are, found when the inputs were gathered: where a
/// reference resolves (join_path and resolve_mesh_path look at the disk: symbolic links, a mesh
/// beside its type file or in its library folder) and why a file cannot be read ("" when it can).
/// compile() asks this, never the disk.
class FileFacts {
 public:
  /// Finds out about the file `rel` named in `base_file` (a vault's geomodel), relative to its folder.
  void add_reference(const std::string& base_file, const std::string& rel);
  /// Finds out about the mesh `rel` named in type file `type_file`.
  void add_mesh(const std::string& type_file, const std::string& rel);
  /// Where `rel` named in `base_file` resolves; where a mesh named in a type file resolves.
  std::string reference_path(const std::string& base_file, const std::string& rel) const;
  std::string mesh_path(const std::string& type_file, const std::string& rel) const;
  /// Why `path` (a resolved reference) cannot be read, "" when it can.
  std::string why_unreadable(const std::string& path) const;

 private:
  std::map<std::pair<std::string, std::string>, std::string> references_, meshes_;
  std::map<std::string, std::string> unreadable_;
};

/// A type library's inputs: its type files loaded (folders in order, each folder's files sorted),
/// then the types its plugins declare.
struct LibraryInputs {
  std::vector<std::shared_ptr<const TypeSpec>> specs;
  /// Errors and warnings of each type file, by type name: told where a vault uses the type (one
  /// broken type file does not break its folder).
  std::map<std::string, std::vector<Diagnostic>> problems;
  std::set<uint32_t> plugin_files;  ///< the Sources files of the plugins' types
  FileFacts files;                  ///< the meshes the type files name
};

/// Loads every type file of the standard library and of `dirs` (each with the mark of the
/// reference naming it, which reports a folder that does not exist), and the plugins' types.
/// `package_paths` resolve `package://` references of URDF devices. A plugin type whose name the
/// library has already throws PluginError naming the plugin.
LibraryInputs gather_library(const std::vector<std::pair<std::string, SourceMark>>& dirs, Sources& sources, Diagnostics& diag,
                             const std::vector<std::string>& package_paths = {}, const std::vector<PluginType>& plugin_types = {});

/// A vault's inputs, besides its spec: its plugins loaded, its library (unless the options hold one
/// already loaded) and what its objects' geomodel files are.
struct VaultInputs {
  std::shared_ptr<PluginSet> plugins;
  std::optional<LibraryInputs> library;  ///< absent when CompileOptions::library is given
  FileFacts files;                       ///< geomodels (the library's meshes are in `library`)
  std::vector<std::string> vault_plugin_dirs;  ///< the vault's `plugins:` folders, absolute
};

/// Gathers a vault's inputs: loads the plugins of --plugins folders, and of the vault's `plugins:`
/// folders when the command line allows them (else an input error saying how; nothing loads when
/// any folder is refused: nullopt), then its library. A plugin that cannot be used throws
/// PluginError.
std::optional<VaultInputs> gather_vault(const VaultSpec& spec, const CompileOptions& options, Sources& sources, Diagnostics& diag);

/// The type library folders of a vault, in the order compile reads them: the standard library
/// (unless the vault says otherwise), the vault's `library:` folders, then --library folders.
std::vector<std::pair<std::string, SourceMark>> library_dirs(const VaultSpec& spec, const CompileOptions& options);

/// The type files of a library folder (its types/ folder when it has one), sorted.
std::vector<std::string> library_type_files(const std::string& dir);

/// A type library kept between compiles (sscs lsp and sscs serve compile at every change): reused
/// while the vault names the same library folders and every file the library was read from (type
/// files, URDF, SRDF) has the same text, on disk or in an editor's buffer; so a change to the vault
/// compiles the vault, not the library. A vault that loads plugins is compiled whole every time.
class LibraryCache {
 public:
  /// Registers in `sources` (new, empty) the files the kept library was read from, at the indices
  /// its marks point at, so its types' problems quote their lines. Call before loading the vault.
  void seed(Sources& sources) const;
  /// The kept library when it still holds for `spec` (read with `sources`, seeded), else null.
  std::shared_ptr<const std::vector<ObjectType>> find(const VaultSpec& spec, const CompileOptions& options, const Sources& sources) const;
  /// Keeps `types`: the library of vault `spec`, compiled whole (CompileOptions::whole_library)
  /// with `sources` holding the files it was read from.
  void keep(const VaultSpec& spec, const CompileOptions& options, std::shared_ptr<const std::vector<ObjectType>> types,
            const Sources& sources);
  /// Whether a library may be kept for vaults like `spec` (none that loads plugins).
  static bool keepable(const VaultSpec& spec, const CompileOptions& options);

 private:
  struct File {
    std::string path, text;
    bool library = false;  ///< read for the library (compared when reused); else the vault's, renamed
  };
  std::vector<File> files_;
  std::vector<std::string> dirs_;
  std::vector<std::string> type_files_;
  std::shared_ptr<const std::vector<ObjectType>> types_;
};

}  // namespace sscs
