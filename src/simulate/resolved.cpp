#include "simulate/resolved.h"

#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "core/data_dirs.h"
#include "core/digest.h"
#include "core/yaml_edit.h"
#include "load/load.h"

namespace fs = std::filesystem;

namespace sscs {

namespace {

uint32_t file_of(const Sources& sources, const std::string& path) {
  if (uint32_t f = sources.find(path)) return f;
  throw std::logic_error(fmt::format("'{}' was not read through the sources registry", path));
}

/// `path` relative to `base` when it lies inside it, else "".
std::string inside(const fs::path& path, const fs::path& base) {
  fs::path rel = fs::absolute(path).lexically_normal().lexically_relative(fs::absolute(base).lexically_normal());
  if (rel.empty() || *rel.begin() == "..") return {};
  return rel.generic_string();
}

class Resolver {
 public:
  Resolver(const Sources& sources, RunInputs& out) : sources_(sources), out_(out) {}

  /// Copies `file` (read by sscs) to `dest` under resolved/, once.
  void copy(const std::string& file, const std::string& dest) {
    if (!copied_.insert(dest).second) return;
    out_.resolved.emplace_back("resolved/" + dest, bytes(file));
  }

  /// A file a type file names (`rel`, resolved like resolve_mesh_path does): copied beside the
  /// type's copy in library/types/, or in library/, wherever the original was found.
  void copy_type_relative(const std::string& type_file, const std::string& rel, const std::string& used) {
    fs::path p(rel);
    std::string normal = p.lexically_normal().generic_string();
    if (p.is_absolute() || normal.starts_with("..")) {
      out_.not_copied.push_back(used);
      return;
    }
    bool beside = fs::path(used).lexically_normal() == (fs::path(type_file).parent_path() / p).lexically_normal();
    copy(used, (beside ? "library/types/" : "library/") + normal);
  }

  std::string bytes(const std::string& file) {
    if (uint32_t f = sources_.find(file)) return sources_.text(f);
    auto b = read_file_bytes(file);
    if (!b) throw std::runtime_error(fmt::format("cannot read '{}' again to keep it with the run", file));
    return *b;
  }

 private:
  const Sources& sources_;
  RunInputs& out_;
  std::set<std::string> copied_;
};

std::vector<const GeometrySpec*> mesh_specs(const TypeSpec& t) {
  std::vector<const GeometrySpec*> out;
  for (const GeometrySpec& g : t.geometry) out.push_back(&g);
  if (t.device)
    for (const PartSpec& p : t.device->parts) {
      for (const GeometrySpec& g : p.geometry) out.push_back(&g);
      for (const GeometrySpec& g : p.visual) out.push_back(&g);  // frames of a rerun draw them
    }
  std::erase_if(out, [](const GeometrySpec* g) { return !std::holds_alternative<MeshSpec>(g->shape); });
  return out;
}

std::string set_text(const std::vector<std::pair<std::string, std::string>>& overrides) {
  std::vector<std::string> names;
  std::map<std::string, std::string> last;
  for (const auto& [name, value] : overrides) {
    if (!last.count(name)) names.push_back(name);
    last[name] = value;
  }
  std::vector<std::string> items;
  for (const std::string& n : names) items.push_back(fmt::format("{}: {}", n, yaml::flow_scalar(last[n])));
  return fmt::format("{{{}}}", fmt::join(items, ", "));
}

std::string edited(const Sources& sources, const std::string& path, const std::vector<yaml::TopLevelChange>& changes) {
  uint32_t file = file_of(sources, path);
  Diagnostics diag;
  yaml::Document doc = yaml::parse(sources, file, diag);
  if (doc.empty() || !doc.root().is_map())
    throw std::logic_error(fmt::format("'{}' no longer parses as it did", path));
  return yaml::replace_top_level(sources.text(file), doc.root(), changes);
}

}  // namespace

RunInputs collect_run_inputs(const ScenarioSpec& scenario, const std::vector<std::pair<std::string, std::string>>& overrides,
                             const Workcell& wc, const GeometryModel& geometry, const Sources& sources) {
  RunInputs out;
  Resolver resolver(sources, out);

  // The types the vault's objects use, with the types they extend.
  std::set<int> used;
  for (const Object& o : wc.objects)
    for (int t = o.type; t >= 0 && used.insert(t).second; t = wc.types[t].base) {}
  std::set<std::string> urdfs, meshes;
  for (int t : used) {
    const TypeSpec& spec = *wc.types[t].spec;
    if (!spec.plugin.empty()) {  // plugins are code: named, hashed, never copied
      out.not_copied.push_back(spec.plugin);
      continue;
    }
    resolver.copy(spec.path, "library/types/" + fs::path(spec.path).filename().string());
    if (spec.device && spec.device->srdf.present)
      resolver.copy_type_relative(spec.path, spec.device->srdf.text, resolve_mesh_path(spec.path, spec.device->srdf.text));
    if (spec.device && spec.device->urdf.present) {
      std::string urdf = resolve_mesh_path(spec.path, spec.device->urdf.text);
      urdfs.insert(urdf);
      resolver.copy_type_relative(spec.path, spec.device->urdf.text, urdf);
      // Its meshes (absolute paths by now) keep their place relative to the URDF file.
      std::string urdf_dest = fs::path(spec.device->urdf.text).lexically_normal().generic_string();
      bool beside = fs::exists(fs::path(spec.path).parent_path() / spec.device->urdf.text);
      for (const GeometrySpec* g : mesh_specs(spec)) {
        const std::string& mesh = std::get<MeshSpec>(g->shape).file.text;
        std::string rel = inside(mesh, fs::path(urdf).parent_path());
        if (rel.empty() || urdf_dest.starts_with("..")) out.not_copied.push_back(mesh);
        else resolver.copy(mesh, fmt::format("library/{}{}", beside ? "types/" : "",
                                             (fs::path(urdf_dest).parent_path() / rel).generic_string()));
      }
      continue;
    }
    for (const GeometrySpec* g : mesh_specs(spec)) {
      const std::string& rel = std::get<MeshSpec>(g->shape).file.text;
      resolver.copy_type_relative(spec.path, rel, resolve_mesh_path(spec.path, rel));
    }
  }
  for (const Object& o : wc.objects) {
    if (o.geomodel.empty()) continue;
    std::string rel = inside(o.geomodel, fs::path(wc.path).parent_path());
    if (rel.empty()) out.not_copied.push_back(o.geomodel);
    else resolver.copy(o.geomodel, rel);
  }

  // The vault with its library pinned to the copies, and the scenario pointing at it.
  std::vector<yaml::TopLevelChange> vault_changes = {{"library", "[library]"}, {"standard_library", "false"}};
  if (!wc.vault_plugin_dirs.empty()) {  // relative folders would not be found from resolved/
    std::vector<std::string> dirs;
    for (const std::string& d : wc.vault_plugin_dirs) dirs.push_back(yaml::flow_scalar(d));
    vault_changes.push_back({"plugins", fmt::format("[{}]", fmt::join(dirs, ", "))});
  }
  out.resolved.emplace_back("resolved/vault.yaml", with_schema_modeline(edited(sources, wc.path, vault_changes), "vault"));
  out.resolved.emplace_back(
      "resolved/scenario.yaml",
      with_schema_modeline(edited(sources, scenario.path,
                                  {{"vault", "vault.yaml"},
                                   {"set", overrides.empty() ? std::nullopt : std::optional(set_text(overrides))}}),
                           "scenario"));

  // Every input: the text files in the order they were read, then URDF and mesh files.
  for (uint32_t f = 1; f < sources.size(); ++f) out.files.push_back({sources.path(f), sha256_hex(sources.text(f))});
  for (const ObjectGeometry& g : geometry.objects)
    for (const Shape& s : g.shapes)
      if (s.mesh) meshes.insert(s.mesh->path);
  std::set<std::string> plugins(wc.plugin_files.begin(), wc.plugin_files.end());
  for (const auto* set : {&urdfs, &meshes, &plugins})
    for (const std::string& f : *set) out.files.push_back({f, sha256_hex(resolver.bytes(f))});
  std::sort(out.not_copied.begin(), out.not_copied.end());
  out.not_copied.erase(std::unique(out.not_copied.begin(), out.not_copied.end()), out.not_copied.end());
  return out;
}

}  // namespace sscs
