#include "inputs/inputs.h"

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>

#include "core/data_dirs.h"
#include "core/digest.h"
#include "core/files.h"
#include "load/load.h"

namespace sscs {

namespace fs = std::filesystem;

namespace {

std::string dir_of(const std::string& path) {
  fs::path p = fs::path(path).parent_path();
  return p.empty() ? "." : p.string();
}

void add_meshes(const TypeSpec& spec, FileFacts& facts) {
  for (const MeshSpec* m : named_meshes(spec)) facts.add_mesh(spec.path, m->file.text);
}

}  // namespace

void FileFacts::add_reference(const std::string& base_file, const std::string& rel) {
  const std::string path = join_path(dir_of(base_file), rel);
  references_[{base_file, rel}] = path;
  unreadable_.emplace(path, not_a_readable_reference(path));
}

void FileFacts::add_mesh(const std::string& type_file, const std::string& rel) {
  const std::string path = resolve_mesh_path(type_file, rel);
  meshes_[{type_file, rel}] = path;
  unreadable_.emplace(path, not_a_readable_reference(path));
}

std::string FileFacts::reference_path(const std::string& base_file, const std::string& rel) const {
  auto it = references_.find({base_file, rel});
  return it != references_.end() ? it->second : (fs::path(dir_of(base_file)) / rel).lexically_normal().string();
}

std::string FileFacts::mesh_path(const std::string& type_file, const std::string& rel) const {
  auto it = meshes_.find({type_file, rel});
  return it != meshes_.end() ? it->second : (fs::path(dir_of(type_file)) / rel).lexically_normal().string();
}

std::string FileFacts::why_unreadable(const std::string& path) const {
  auto it = unreadable_.find(path);
  return it == unreadable_.end() ? "was not gathered with the inputs (a bug)" : it->second;
}

LibraryInputs gather_library(const std::vector<std::pair<std::string, SourceMark>>& dirs, Sources& sources, Diagnostics& diag,
                             const std::vector<std::string>& package_paths, const std::vector<PluginType>& plugin_types) {
  LibraryInputs out;
  std::map<std::string, size_t> index;  // name -> specs index
  std::vector<fs::path> loaded;  // a folder named twice (a vault's library and --library) loads once
  for (const auto& [dir, where] : dirs) {
    std::error_code ec;
    if (fs::path real = fs::weakly_canonical(dir, ec); !ec) {
      if (std::find(loaded.begin(), loaded.end(), real) != loaded.end()) continue;
      loaded.push_back(real);
    }
    if (!fs::is_directory(dir, ec)) {
      const bool exists = fs::exists(dir, ec);
      diag.error(where, fmt::format("type library folder '{}' {}", dir,
                                    exists ? "is not a folder (a library is a folder holding types/)" : "does not exist"));
      continue;
    }
    // A folder a vault names (where is valid), and each type file in it, stay inside the project.
    if (std::string why = where.valid() ? outside_roots(dir) : ""; !why.empty()) {
      diag.error(where, fmt::format("type library folder '{}' {}", dir, why));
      continue;
    }
    for (const std::string& file : library_type_files(dir)) {
      if (std::string why = where.valid() ? outside_roots(file) : ""; !why.empty()) {
        diag.error(where, fmt::format("type file '{}' {}", file, why));
        continue;
      }
      // The file's own errors are the type's problems, told where a vault uses it.
      Diagnostics own;
      auto spec = load_type(file, sources, own, {}, package_paths);
      std::string stem = fs::path(file).stem().string();
      if (!spec || spec->name.empty()) {
        if (!own.has_errors()) continue;
        spec.emplace();  // unreadable: known by its file's name
        spec->name = stem;
        spec->path = file;
        spec->mark = own.errors()[0].mark;
      }
      if (own.has_errors() || !own.warnings().empty()) {
        std::vector<Diagnostic>& p = out.problems[spec->name];
        for (const Diagnostic& d : own.warnings()) p.push_back({d.mark, d.message, true});
        p.insert(p.end(), own.errors().begin(), own.errors().end());
      }
      if (stem != spec->name)
        diag.error(spec->mark, fmt::format("type file '{}' defines type '{}'; name the file after its type ({}.yaml)",
                                           fs::path(file).filename().string(), spec->name, spec->name));
      if (spec->name == "object") {
        diag.error(spec->mark, "'object' is the built-in super-class and cannot be redefined");
        continue;
      }
      auto [it, inserted] = index.emplace(spec->name, out.specs.size());
      if (!inserted) {
        diag.error(spec->mark, fmt::format("type '{}' is defined twice (also in {})", spec->name, out.specs[it->second]->path));
        continue;
      }
      add_meshes(*spec, out.files);
      out.specs.push_back(std::make_shared<const TypeSpec>(std::move(*spec)));
    }
  }

  // Plugin types, read from the type files they amount to (checked when the plugin loaded).
  for (const PluginType& pt : plugin_types) {
    uint32_t file = sources.add(pt.label, pt.text);
    out.plugin_files.insert(file);
    auto spec = load_type(file, pt.plugin, sources, diag, package_paths);
    if (!spec) continue;
    spec->plugin = pt.plugin;
    if (auto it = index.find(spec->name); it != index.end())
      throw PluginError(fmt::format("plugin {}: object type '{}' is already defined by {}", pt.plugin, spec->name,
                                    out.specs[it->second]->plugin.empty() ? "the type library (" + out.specs[it->second]->path + ")"
                                                                          : "plugin " + out.specs[it->second]->plugin));
    if (spec->name == "object") throw PluginError(fmt::format("plugin {}: 'object' is the built-in super-class", pt.plugin));
    index.emplace(spec->name, out.specs.size());
    add_meshes(*spec, out.files);
    out.specs.push_back(std::make_shared<const TypeSpec>(std::move(*spec)));
  }
  return out;
}

std::optional<VaultInputs> gather_vault(const VaultSpec& spec, const CompileOptions& options, Sources& sources, Diagnostics& diag) {
  VaultInputs in;
  // Plugins: --plugins folders load; a vault's own `plugins:` folders load only when the command
  // line allows them (the same folder in --plugins, or --allow-vault-plugins): a vault file from
  // a pull request must not be able to run code on its own (docs/plugins.md).
  in.plugins = options.plugins ? options.plugins : std::make_shared<PluginSet>();
  auto resolve = [&](const std::string& rel) { return join_path(dir_of(spec.path), rel); };
  if (!options.library) {  // else the library was compiled with these plugins already loaded
    auto same_folder = [](const std::string& a, const std::string& b) {
      std::error_code e1, e2;
      return fs::weakly_canonical(a, e1) == fs::weakly_canonical(b, e2);
    };
    std::vector<std::string> folders;
    for (const std::string& dir : options.plugin_dirs) {
      std::error_code ec;
      if (!fs::is_directory(dir, ec)) diag.error({}, fmt::format("--plugins folder '{}' does not exist", dir));
      else folders.push_back(dir);
    }
    for (const Scalar& dir : spec.plugins) {
      std::string path = resolve(dir.text);
      std::error_code ec;
      bool named = std::any_of(options.plugin_dirs.begin(), options.plugin_dirs.end(), [&](const std::string& d) { return same_folder(d, path); });
      if (!fs::is_directory(path, ec)) diag.error(dir.mark, fmt::format("plugin folder '{}' does not exist", dir.text));
      else if (!named && !options.allow_vault_plugins)
        diag.error(dir.mark, fmt::format("the vault asks to load the plugins in '{}'; a vault alone never loads code. To "
                                         "allow it, pass --plugins {} (or --allow-vault-plugins)", dir.text, path));
      else if (std::string why = named ? "" : outside_roots(path); !why.empty())
        diag.error(dir.mark, fmt::format("plugin folder '{}' {}", dir.text, why));
      else if (!named) folders.push_back(path);
    }
    if (diag.has_errors()) return std::nullopt;  // nothing loads when any folder is refused
    for (const std::string& dir : folders) in.plugins->load_folder(dir);
  }
  for (const Scalar& dir : spec.plugins) in.vault_plugin_dirs.push_back(fs::absolute(resolve(dir.text)).lexically_normal().string());

  // The type library: standard, the vault's folders, --library folders, then plugin types.
  if (!options.library) in.library = gather_library(library_dirs(spec, options), sources, diag, options.package_paths, in.plugins->types());
  for (const ObjectSpec& o : spec.objects)
    if (o.geomodel.present && !o.geomodel.null) in.files.add_reference(spec.path, o.geomodel.text);
  return in;
}

std::vector<std::pair<std::string, SourceMark>> library_dirs(const VaultSpec& spec, const CompileOptions& options) {
  std::vector<std::pair<std::string, SourceMark>> dirs;
  if (spec.standard_library) dirs.push_back({standard_library_dir(), {}});
  for (const Scalar& dir : spec.library) dirs.push_back({join_path(dir_of(spec.path), dir.text), dir.mark});
  for (const std::string& dir : options.library_dirs) dirs.push_back({dir, {}});
  return dirs;
}

std::vector<std::string> library_type_files(const std::string& dir) {
  std::vector<std::string> files;
  std::error_code ec;
  fs::path root = fs::is_directory(fs::path(dir) / "types", ec) ? fs::path(dir) / "types" : fs::path(dir);
  for (const auto& entry : fs::directory_iterator(root, ec)) {
    auto ext = entry.path().extension();
    if (entry.is_regular_file() && (ext == ".yaml" || ext == ".yml")) files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());  // deterministic order
  return files;
}

namespace {

std::vector<std::string> dir_names(const VaultSpec& spec, const CompileOptions& options) {
  std::vector<std::string> out;
  for (const auto& [dir, _] : library_dirs(spec, options)) out.push_back(dir);
  return out;
}

std::vector<std::string> type_files_of(const std::vector<std::string>& dirs) {
  std::vector<std::string> out;
  for (const std::string& dir : dirs)
    for (std::string& f : library_type_files(dir)) out.push_back(std::move(f));
  return out;
}

}  // namespace

bool LibraryCache::keepable(const VaultSpec& spec, const CompileOptions& options) {
  return spec.plugins.empty() && options.plugin_dirs.empty() && !options.library && (!options.plugins || options.plugins->files().empty());
}

void LibraryCache::seed(Sources& sources) const {
  for (const File& f : files_) sources.add(f.library ? f.path : "(earlier) " + f.path, f.text);
}

std::shared_ptr<const std::vector<ObjectType>> LibraryCache::find(const VaultSpec& spec, const CompileOptions& options,
                                                                  const Sources& sources) const {
  if (!types_ || !keepable(spec, options) || dir_names(spec, options) != dirs_) return nullptr;
  if (type_files_of(dirs_) != type_files_) return nullptr;  // a type file added or removed
  for (const File& f : files_) {
    if (!f.library) continue;
    if (const std::string* text = sources.unsaved(f.path)) {
      if (*text != f.text) return nullptr;
    } else if (std::optional<std::string> now = read_file_bytes(f.path); !now || *now != f.text) {
      return nullptr;
    }
  }
  return types_;
}

void LibraryCache::keep(const VaultSpec& spec, const CompileOptions& options, std::shared_ptr<const std::vector<ObjectType>> types,
                        const Sources& sources) {
  files_.clear();
  types_ = nullptr;
  if (!keepable(spec, options)) return;
  dirs_ = dir_names(spec, options);
  type_files_ = type_files_of(dirs_);
  for (uint32_t f = 1; f < sources.size(); ++f)
    files_.push_back({sources.path(f), sources.text(f), sources.path(f) != spec.path});
  types_ = std::move(types);
}

}  // namespace sscs
