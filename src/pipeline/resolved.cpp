#include "pipeline/resolved.h"

#include <filesystem>
#include <algorithm>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "core/data_dirs.h"
#include "core/digest.h"
#include "core/files.h"
#include "core/pose.h"
#include "core/units.h"
#include "core/yaml_edit.h"
#include "geometry/mesh_io.h"

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
  /// Writes `text` to `dest` under resolved/, once.
  void put(const std::string& dest, std::string text) {
    if (copied_.insert(dest).second) out_.resolved.emplace_back("resolved/" + dest, std::move(text));
  }

  /// The image files `mesh`'s textures were read from: known from the run's geometry, else read
  /// now (a visual mesh a run without frames never drew; if it cannot be read, the rerun will say
  /// so where the run would have).
  const std::vector<std::string>& images(const std::string& mesh) {
    auto it = images_.find(mesh);
    if (it != images_.end()) return it->second;
    Diagnostics unused;  // the mesh was read once before, or is only drawn (see above)
    auto read = meshes_.load(mesh, {}, unused);
    return images_[mesh] = read ? read->images : std::vector<std::string>{};
  }
  void know_images(const TriangleMesh& mesh) { images_.try_emplace(mesh.path, mesh.images); }

  /// The folder under library/urdf/ that holds the files below `root` (a vendor's package
  /// folder, or the folder holding a URDF and its meshes), unique per root.
  std::string folder_for(const fs::path& root) {
    auto it = folders_.find(root);
    if (it != folders_.end()) return it->second;
    std::string base = root.filename().empty() ? std::string("files") : root.filename().string(), name = base;
    for (int n = 2; std::count_if(folders_.begin(), folders_.end(), [&](const auto& f) { return f.second == "library/urdf/" + name; }); ++n)
      name = fmt::format("{}-{}", base, n);
    return folders_[root] = "library/urdf/" + name;
  }

  /// A file a type file names (`rel`, resolved like resolve_mesh_path does): copied beside the
  /// type's copy in library/types/, or in library/, wherever the original was found. Returns
  /// where, or nullopt when it cannot keep its relative place (listed as not copied).
  std::optional<std::string> copy_type_relative(const std::string& type_file, const std::string& rel, const std::string& used) {
    fs::path p(rel);
    std::string normal = p.lexically_normal().generic_string();
    if (p.is_absolute() || normal.starts_with("..")) {
      out_.not_copied.push_back(used);
      return std::nullopt;
    }
    bool beside = fs::path(used).lexically_normal() == (fs::path(type_file).parent_path() / p).lexically_normal();
    std::string dest = (beside ? "library/types/" : "library/") + normal;
    copy(used, dest);
    return dest;
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
  std::map<std::string, std::vector<std::string>> images_;
  MeshCache meshes_;
  std::map<fs::path, std::string> folders_;
};

/// The deepest folder holding every one of `files` (absolute paths).
fs::path common_folder(const std::vector<std::string>& files) {
  fs::path folder = fs::path(files.front()).parent_path();
  for (const std::string& f : files)
    while (inside(f, folder).empty() && folder != folder.parent_path()) folder = folder.parent_path();
  return folder;
}

/// `text` with each `from` between the delimiters `open` and `close` (`"from"`: an XML attribute's
/// value or a JSON string; `>from<`: an XML element's text) replaced by `to`.
std::string replace_delimited(std::string text, const std::string& from, const std::string& to,
                              std::initializer_list<std::pair<char, char>> delimiters) {
  for (auto [open, close] : delimiters) {
    const std::string a = open + from + close, b = open + to + close;
    for (size_t at = text.find(a); at != std::string::npos; at = text.find(a, at + b.size())) text.replace(at, a.size(), b);
  }
  return text;
}

std::string replace_attribute_values(const std::string& text, const std::string& from, const std::string& to) {
  return replace_delimited(text, from, to, {{'"', '"'}, {'\'', '\''}});
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
                             const Workcell& wc, const GeometryModel& geometry, const Sources& sources,
                             const std::vector<uint32_t>* files, const char* kind) {
  RunInputs out;
  Resolver resolver(sources, out);
  for (const ObjectGeometry& g : geometry.objects)
    for (const auto* shapes : {&g.shapes, &g.visual_shapes})
      for (const Shape& s : *shapes)
        if (s.mesh) resolver.know_images(*s.mesh);

  // The types the vault's objects use, with the types they extend.
  std::set<int> used;
  for (const Object& o : wc.objects)
    for (int t : wc.lineage(o.type)) used.insert(t);
  std::set<std::string> meshes;
  for (int t : used) {
    const ObjectType& type = wc.types[t];
    if (!type.plugin.empty()) {  // plugins are code: named, hashed, never copied
      out.not_copied.push_back(type.plugin);
      continue;
    }
    const std::string type_dest = "library/types/" + fs::path(type.path).filename().string();
    if (type.own_device && type.templates.device && !type.templates.device->urdf.empty()) {
      // A vendor's files (URDF, SRDF, meshes and their images), wherever they lie, keep their
      // layout below the folder that holds them all, in library/urdf/NAME/; the type copy names
      // the copies, and the URDF copy's package:// and absolute mesh references become relative.
      const DeviceTemplate& d = *type.templates.device;
      const std::string urdf = fs::absolute(resolve_mesh_path(type.path, d.urdf)).lexically_normal().string();
      std::vector<std::string> files = {urdf};
      std::string srdf;
      if (!d.srdf.empty()) files.push_back(srdf = fs::absolute(resolve_mesh_path(type.path, d.srdf)).lexically_normal().string());
      for (const std::string& mesh : type.own_meshes) {
        files.push_back(mesh);
        for (const std::string& image : resolver.images(mesh)) files.push_back(image);
      }
      const fs::path root = common_folder(files);
      const std::string folder = resolver.folder_for(root);
      auto dest = [&](const std::string& f) { return folder + "/" + inside(f, root); };
      std::string urdf_text = resolver.bytes(urdf);
      for (const auto& [uri, path] : d.urdf_mesh_refs)
        if (uri.starts_with("package://") || uri.starts_with("file://") || fs::path(uri).is_absolute())
          urdf_text = replace_attribute_values(urdf_text, uri, fs::path(dest(path)).lexically_relative(fs::path(dest(urdf)).parent_path()).generic_string());
      resolver.put(dest(urdf), std::move(urdf_text));
      // A COLLADA or glTF mesh naming its texture by absolute path (or file://) names the copy
      // instead, relatively; a relative name holds, for the layout is kept.
      std::set<std::string> rewritten;
      for (const std::string& mesh : type.own_meshes) {
        const std::string ext = fs::path(mesh).extension().string();
        if (rewritten.count(mesh) || resolver.images(mesh).empty() || (ext != ".dae" && ext != ".DAE" && ext != ".gltf")) continue;
        const std::string original = resolver.bytes(mesh);
        std::string text = original;
        for (const std::string& image : resolver.images(mesh)) {
          const std::string rel = fs::path(dest(image)).lexically_relative(fs::path(dest(mesh)).parent_path()).generic_string();
          for (const std::string& form : {"file://" + image, image})
            text = replace_delimited(text, form, rel, {{'>', '<'}, {'"', '"'}});
        }
        if (text == original) continue;
        resolver.put(dest(mesh), std::move(text));
        rewritten.insert(mesh);
      }
      for (size_t k = 1; k < files.size(); ++k)
        if (!rewritten.count(files[k])) resolver.copy(files[k], dest(files[k]));
      auto from_types = [&](const std::string& f) { return yaml::flow_scalar(fs::path(dest(f)).lexically_relative("library/types").generic_string()); };
      std::vector<yaml::TopLevelChange> changes = {{"urdf", from_types(urdf)}};
      if (!d.srdf.empty()) changes.push_back({"srdf", from_types(srdf)});
      resolver.put(type_dest, edited(sources, type.path, changes));
      continue;
    }
    resolver.copy(type.path, type_dest);
    for (const std::string& rel : type.own_meshes) {
      const std::string mesh = resolve_mesh_path(type.path, rel);
      const std::optional<std::string> mesh_dest = resolver.copy_type_relative(type.path, rel, mesh);
      if (!mesh_dest) continue;
      // The images its textures were read from keep their place beside the mesh's copy.
      for (const std::string& image : resolver.images(mesh)) {
        std::string beside = inside(image, fs::path(mesh).parent_path());
        if (beside.empty()) out.not_copied.push_back(image);
        else resolver.copy(image, (fs::path(*mesh_dest).parent_path() / beside).generic_string());
      }
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
                           kind));

  // Every input: the text files in the order they were read (URDFs and SRDFs too), then meshes.
  // Named as the user would: relative to the folder sscs runs in when inside it (a URDF's meshes
  // are resolved to absolute paths), else absolute.
  const fs::path here = fs::current_path();
  auto named = [&](const std::string& f) {
    const std::string rel = fs::path(f).is_absolute() ? inside(f, here) : "";
    return rel.empty() ? f : rel;
  };
  for (uint32_t f = 1; f < sources.size(); ++f)
    if (!files || std::find(files->begin(), files->end(), f) != files->end())
      out.files.push_back({named(sources.path(f)), sha256_hex(sources.text(f))});
  for (const ObjectGeometry& g : geometry.objects)
    for (const auto* shapes : {&g.shapes, &g.visual_shapes})  // what the checks used, and what frames drew
      for (const Shape& s : *shapes)
        if (s.mesh) {
          meshes.insert(s.mesh->path);
          meshes.insert(s.mesh->images.begin(), s.mesh->images.end());
        }
  std::set<std::string> plugins(wc.plugin_files.begin(), wc.plugin_files.end());
  for (const auto* set : {&meshes, &plugins})  // (URDFs, like SRDFs, were read into the sources)
    for (const std::string& f : *set) out.files.push_back({named(f), sha256_hex(resolver.bytes(f))});
  for (std::string& f : out.not_copied) f = named(f);
  std::sort(out.not_copied.begin(), out.not_copied.end());
  out.not_copied.erase(std::unique(out.not_copied.begin(), out.not_copied.end()), out.not_copied.end());
  return out;
}

namespace {

/// A number as final.yaml writes it: exact where it can be (the shortest text that reads back the
/// same double), else to 1e-9 (a pose the physics left, an angle turned into degrees).
std::string final_number(double x, bool rounded) {
  if (rounded) x = std::round(x * 1e9) / 1e9;
  if (x == 0) x = 0;  // no -0
  return fmt::format("{}", x);
}

/// A value of `dim` (SI) in the file's unit: a plain number means that unit.
std::string in_file_unit(double si, Dim dim) {
  const double factor = file_unit_to_si(dim);
  return final_number(si / factor, factor != 1);
}

}  // namespace

std::string final_vault_text(const Workcell& wc, const Sources& sources, const FinalState& end, const std::string& title,
                             bool beside_resolved) {
  const uint32_t file = file_of(sources, wc.path);
  Diagnostics diag;
  yaml::Document doc = yaml::parse(sources, file, diag);
  if (doc.empty() || !doc.root().is_map()) throw std::logic_error(fmt::format("'{}' no longer parses as it did", wc.path));
  const fs::path folder = fs::absolute(wc.path).parent_path();
  std::vector<yaml::TopLevelChange> changes;
  changes.push_back({"description", yaml::flow_scalar(fmt::format("{} as {} left it at {} s (final.yaml of sscs simulate)", wc.name,
                                                                  title, final_number(end.t, true)))});

  // Where its types and plugins are found from the run folder.
  if (beside_resolved) {
    changes.push_back({"library", "[resolved/library]"});
    changes.push_back({"standard_library", "false"});
  } else if (yaml::Node lib = doc.root().find("library"); lib.valid() && lib.is_sequence()) {
    std::vector<std::string> dirs;
    for (size_t i = 0; i < lib.size(); ++i)
      dirs.push_back(yaml::flow_scalar((folder / std::string(lib.item(i).text())).lexically_normal().generic_string()));
    changes.push_back({"library", fmt::format("[{}]", fmt::join(dirs, ", "))});
  }
  if (!wc.vault_plugin_dirs.empty()) {
    std::vector<std::string> dirs;
    for (const std::string& d : wc.vault_plugin_dirs) dirs.push_back(yaml::flow_scalar(d));
    changes.push_back({"plugins", fmt::format("[{}]", fmt::join(dirs, ", "))});
  }

  // The parameters at the values the run used (the constraints may name them).
  if (!wc.parameters.empty()) {
    // The objects are written out below: a parameter set here moves none of them.
    std::string text = "\n  # the run's values; the objects below are written where they stood, so a --set of these changes only the rules that name them";
    for (const Parameter& p : wc.parameters) {
      const double v = wc.values[p.slot];
      std::string value;
      if (p.type == AttrType::Integer) value = fmt::format("{{value: {}, type: integer}}", static_cast<long long>(v));
      else if (p.type == AttrType::Boolean) value = v != 0 ? "true" : "false";
      else if (p.dim == Dim::Fraction) value = fmt::format("\"{}%\"", final_number(v * 100, true));
      else if (*file_unit(p.dim)) value = fmt::format("\"{} {}\"", in_file_unit(v, p.dim), file_unit(p.dim));
      else value = final_number(v, false);
      text += fmt::format("\n  {}: {}", p.name, value);
    }
    changes.push_back({"parameters", text});
  }

  // Every object, one line each. What stands where the vault had it, on a parent that did too,
  // is written as the vault wrote it (at its frame); the rest where the run left it.
  std::vector<signed char> known_to_stay(wc.objects.size(), -1);  // per object: -1 not looked at yet
  std::function<bool(int)> stays = [&](int o) {
    if (known_to_stay[o] < 0) known_to_stay[o] = !end.moved[o] && (wc.objects[o].parent < 0 || stays(wc.objects[o].parent));
    return known_to_stay[o] == 1;
  };
  std::string objects;
  for (size_t o = 0; o < wc.objects.size(); ++o) {
    if (end.gone[o]) continue;
    const Object& obj = wc.objects[o];
    const ObjectType& type = wc.types[obj.type];
    const double* slots = &wc.values[obj.first_slot];
    std::vector<std::string> items = {fmt::format("type: {}", yaml::flow_scalar(type.name)), fmt::format("name: {}", obj.name)};
    // Its place: as compiled when it stands where the vault has it, else where the run left it.
    const bool stayed = stays(static_cast<int>(o));
    Eigen::Vector3d xyz, rpy;
    if (stayed) {
      if (!obj.at.empty()) items.push_back(fmt::format("at: {}.{}", wc.objects[obj.parent].name, obj.at));
      else if (obj.parent >= 0) items.push_back(fmt::format("parent: {}", wc.objects[obj.parent].name));
      xyz = {slots[kLocationSlot], slots[kLocationSlot + 1], slots[kLocationSlot + 2]};
      rpy = {slots[kOrientationSlot], slots[kOrientationSlot + 1], slots[kOrientationSlot + 2]};
    } else {
      // In the room it stands in: what moved no longer hangs on what it stood at (a drum that
      // arrived on the dock pallet and was stored in a rack is no child of the pallet, which
      // no_overlap would then never compare it with).
      int parent = obj.parent;
      while (parent >= 0 && !wc.types[wc.objects[parent].type].container) parent = wc.objects[parent].parent;
      Eigen::Isometry3d X = end.X_world[o];
      if (parent >= 0) {
        items.push_back(fmt::format("parent: {}", wc.objects[parent].name));
        X = end.X_world[parent].inverse() * X;
      }
      xyz = X.translation();
      rpy = rotation_to_rpy(X.linear());
    }
    items.push_back(fmt::format("location: [{}, {}, {}]", final_number(xyz.x(), !stayed), final_number(xyz.y(), !stayed),
                                final_number(xyz.z(), !stayed)));
    if ((rpy / kRadPerDeg).cwiseAbs().maxCoeff() >= 5e-10)  // (what rounds to no turn is none)
      items.push_back(fmt::format("orientation: [{}, {}, {}]", in_file_unit(rpy.x(), Dim::Angle), in_file_unit(rpy.y(), Dim::Angle),
                                  in_file_unit(rpy.z(), Dim::Angle)));
    if (!obj.geomodel.empty()) {
      const std::string rel = inside(obj.geomodel, folder);
      items.push_back(fmt::format("geomodel: {}", yaml::flow_scalar(beside_resolved && !rel.empty() ? "resolved/" + rel : obj.geomodel)));
    }
    if (!obj.color.empty()) items.push_back(fmt::format("color: {}", yaml::flow_scalar(obj.color)));
    for (size_t a = 0; a < type.attributes.size(); ++a) {
      const AttributeDef& def = type.attributes[a];
      const uint32_t slot = obj.first_slot + kFirstAttributeSlot + static_cast<uint32_t>(a);
      double v = wc.values[slot];
      bool changed = false;
      for (const auto& [index, value] : end.attributes[o])
        if (index == static_cast<int>(a)) v = value, changed = true;
      std::string text;
      if (def.type == AttrType::String || def.type == AttrType::Enum) text = yaml::flow_scalar(wc.texts[slot]);
      else if (def.type == AttrType::Boolean) text = v != 0 ? "true" : "false";
      else if (def.type == AttrType::Integer) text = fmt::format("{}", static_cast<long long>(v));
      else text = changed ? final_number(v / file_unit_to_si(def.dim), true) : in_file_unit(v, def.dim);
      items.push_back(fmt::format("{}: {}", def.name, text));
    }
    objects += fmt::format("\n  - {{{}}}", fmt::join(items, ", "));
  }
  changes.push_back({"objects", objects});
  std::string text = yaml::replace_top_level(sources.text(file), doc.root(), changes);
  return with_schema_modeline(
      fmt::format("# The vault as {} left it (sscs simulate writes it): every object where it came to rest, the loads\n"
                  "# that arrived added; check it, render it, or start the next campaign from it.\n{}",
                  title, text),
      "vault");
}

}  // namespace sscs
