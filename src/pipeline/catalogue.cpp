#include "pipeline/catalogue.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/data_dirs.h"
#include "core/files.h"
#include "core/units.h"
#include "geometry/geometry.h"
#include "model/device.h"
#include "render/camera.h"
#include "render/image.h"
#include "render/renderer.h"

namespace fs = std::filesystem;

namespace sscs {

namespace {

constexpr int kThumbWidth = 320, kThumbHeight = 240;
/// Copies of a repeated frame listed with their positions; the rest are counted.
constexpr size_t kCopiesShown = 6;

/// The type file as a reader finds it: under the standard library, `library/types/x.yaml`; else
/// its path as the library folder was given.
std::string shown_path(const ObjectType& t) {
  const fs::path std_dir = fs::weakly_canonical(standard_library_dir());
  std::error_code ec;
  const fs::path file = fs::weakly_canonical(t.path, ec);
  const fs::path rel = file.lexically_relative(std_dir);
  if (!rel.empty() && *rel.begin() != "..") return (fs::path("library") / rel).generic_string();
  return fs::path(t.path).filename().generic_string();
}

/// The type file's header comments (before its first key after `description`): its notes and
/// sources, as written.
std::string header_notes(const ObjectType& t, const Sources& sources) {
  const uint32_t file = sources.find(t.path);
  if (file == 0) return {};
  std::istringstream in(sources.text(file));
  std::string line, out;
  bool started = false;
  while (std::getline(in, line)) {
    if (line.starts_with("#")) {
      std::string body = line.size() > 1 && line[1] == ' ' ? line.substr(2) : line.substr(1);
      out += (out.empty() || out.back() == '\n' ? "" : " ") + body;
      started = true;
    } else if (started && !line.starts_with("description:")) {
      break;  // the first key after the header
    }
  }
  return out;
}

std::string cell(std::string s) {
  for (size_t p; (p = s.find('|')) != std::string::npos;) s.replace(p, 1, "\\|");
  return s;
}

std::string number(double si, Dim dim) { return number_text(stable(si_to_file(si, dim))); }

/// A frame row: name, position (m) and orientation (deg) in the type's frame.
std::string frame_row(const std::string& name, const Eigen::Isometry3d& X, const std::string& note = "") {
  auto rpy = frame_rpy_deg(X);
  return fmt::format("| `{}`{} | {} | {} |\n", name, note, vec_text(X.translation()), rpy ? vec_text(*rpy) : "");
}

/// The thumbnail of an instance at its defaults, framed from the front left above.
std::string render_thumbnail(const Workcell& wc, Diagnostics& diag) {
  GeometryModel drawn = build_geometry(wc, diag, nullptr, {.visuals = true, .contacts = nullptr});
  RenderOptions ro;
  ro.width = kThumbWidth;
  ro.height = kThumbHeight;
  Renderer renderer(wc, drawn, ro);
  Camera camera = framing_camera(renderer.bounds(), 35, double(kThumbWidth) / kThumbHeight);
  return encode_png(renderer.render(camera));
}

void write_type(std::ostream& md, const ObjectType& t, const std::map<std::string, std::string>& base_of, const TypeInstance& in,
                const Sources& sources) {
  md << fmt::format("## {}\n\n", t.name);
  if (in.workcell) md << fmt::format("![{}](img/library/{}.png)\n\n", t.name, t.name);
  md << fmt::format("{}.\n\n", t.description);
  md << fmt::format("*{}*, extends `{}`; file `{}`.{}\n\n", t.device ? "device" : t.container ? "container (a space)" : "object",
                    base_of.at(t.name), shown_path(t), t.templates.device && t.templates.device->kinematic ? " Driven kinematically." : "");
  if (std::string notes = header_notes(t, sources); !notes.empty()) md << notes << "\n\n";
  md << "| attribute | type | unit | default | min | max | description |\n|---|---|---|---|---|---|---|\n";
  for (const AttributeDef& a : t.attributes) {
    const std::string def = a.joint ? number(a.home_si, a.dim) : a.default_value.present ? a.default_value.text : "required";
    const std::string lo = a.min_si ? number(*a.min_si, a.dim) : a.min_expr.present ? "`" + a.min_expr.text + "`" : "";
    const std::string hi = a.max_si ? number(*a.max_si, a.dim) : a.max_expr.present ? "`" + a.max_expr.text + "`" : "";
    std::string type = a.joint ? "joint" : attr_type_name(a.type);
    if (a.type == AttrType::Enum) type += fmt::format(" ({})", fmt::join(a.values, ", "));
    md << fmt::format("| `{}` | {} | {} | {} | {} | {} | {} |\n", a.name, cell(type), file_unit(a.dim), cell(def), cell(lo), cell(hi),
                      cell(a.description));
  }
  md << "\n";
  if (!t.templates.rules.empty()) {
    md << "Rules every instance keeps (an error at the object otherwise):\n\n";
    for (const RuleTemplate& r : t.templates.rules) md << fmt::format("- `{}`: else {}\n", r.condition.text, r.message);
    md << "\n";
  }
  if (!in.workcell) {
    md << fmt::format("No instance at its defaults ({}).\n\n", in.unbuilt);
    return;
  }
  md << "Frames at the defaults (in the type's frame; m, deg):\n\n| frame | xyz | rpy |\n|---|---|---|\n";
  // Named frames as the type writes them: a repeated one as its pattern, its first copies and a count.
  const Workcell& wc = *in.workcell;
  const double* attributes = &wc.values[wc.objects[0].first_slot + kFirstAttributeSlot];
  std::set<std::string> listed;
  for (const FrameTemplate& f : t.templates.frames) {
    std::vector<std::pair<std::string, Eigen::Isometry3d>> copies;
    f.each(attributes, [&](const std::string& name, const Eigen::Isometry3d& X) { copies.emplace_back(name, X); });
    if (!f.repeat) {
      for (const auto& [name, X] : copies) md << frame_row(name, X);
      listed.insert(f.name);
      continue;
    }
    std::vector<std::string> counts;
    for (const RepeatTemplate::Counter& c : f.repeat->counters) {
      std::vector<std::string> pitch;
      for (const ValueRef& v : c.pitch.v) pitch.push_back(v.present ? v.text : "0");
      counts.push_back(fmt::format("{} 1 to `{}` = {}{}", c.name, c.count.text, number_text(c.count.eval(attributes, NAN)),
                                   c.pitch.v[0].present || c.pitch.v[1].present || c.pitch.v[2].present
                                       ? fmt::format(", each `[{}]` further", fmt::join(pitch, ", "))
                                       : ""));
    }
    std::vector<std::string> xyz;
    for (const ValueRef& v : f.pose.xyz.v) xyz.push_back(v.present ? v.text : "0");
    md << fmt::format("| `{}` | {} copies ({}) at `[{}]` | |\n", f.name, copies.size(), fmt::join(counts, ", "), fmt::join(xyz, ", "));
    for (size_t k = 0; k < copies.size() && k < kCopiesShown; ++k) md << frame_row(copies[k].first, copies[k].second);
    if (copies.size() > kCopiesShown)
      md << frame_row(copies.back().first, copies.back().second, fmt::format(" (the last; {} more between)", copies.size() - kCopiesShown - 1));
    for (const auto& c : copies) listed.insert(c.first);
  }
  for (const auto& [name, X] : in.frames)
    if (!listed.count(name)) md << frame_row(name, X);  // `top` when the type names none, a device's tool
  md << "\n";
  if (!in.bounds.isEmpty()) md << fmt::format("Bounds at the defaults: {} to {} m.\n\n", vec_text(in.bounds.min()), vec_text(in.bounds.max()));
  if (!in.meshes.empty()) {
    std::vector<std::string> meshes;
    for (const TypeInstance::Mesh& m : in.meshes) meshes.push_back(fmt::format("`{}` ({})", m.file, m.closed ? "closed: a solid" : "open: a surface"));
    md << fmt::format("Meshes: {}.\n\n", fmt::join(meshes, ", "));
  }
  if (const DeviceTemplate* d = t.templates.device.get()) {
    // Speeds and accelerations as a run moves the joints: the type's, else the defaults (marked).
    md << "| part | parent | joint | type | range | speed | acceleration |\n|---|---|---|---|---|---|---|\n";
    for (const PartTemplate& p : d->parts) {
      std::string range, speed, accel;
      if (p.joint && p.joint->type != JointType::Fixed) {
        const int a = t.find_attribute(p.joint->name);
        if (a >= 0) {
          const AttributeDef& def = t.attributes[a];
          range = fmt::format("{} to {} {}", number(def.lower(attributes), def.dim), number(def.upper(attributes), def.dim), file_unit(def.dim));
        }
        auto m = std::find_if(in.joints.begin(), in.joints.end(), [&](const TypeInstance::JointMotion& x) { return x.name == p.joint->name; });
        if (m != in.joints.end()) {
          const bool turns = m->type == JointType::Revolute;
          const Dim dim = turns ? Dim::Angle : Dim::Length;
          speed = fmt::format("{} {}{}", number(m->speed, dim), turns ? "deg/s" : "m/s", m->speed_given ? "" : " (default)");
          accel = fmt::format("{} {}{}", number(m->acceleration, dim), turns ? "deg/s²" : "m/s²", m->acceleration_given ? "" : " (default)");
        }
      }
      md << fmt::format("| `{}` | {} | {} | {} | {} | {} | {} |\n", p.name, p.parent < 0 ? "" : "`" + d->parts[p.parent].name + "`",
                        p.joint ? "`" + p.joint->name + "`" : "", p.joint ? joint_type_name(p.joint->type) : "", range, speed, accel);
    }
    md << fmt::format("\nTool: `{}`.", d->tool_part < 0 ? "the end of the longest chain" : d->parts[d->tool_part].name);
    if (in.reach) md << fmt::format(" Tool reach over the joint ranges at the defaults: {} to {} m.", vec_text(in.reach->min()), vec_text(in.reach->max()));
    md << "\n\n";
  }
}

}  // namespace

std::string write_type_catalogue(const std::string& md_path, std::vector<ObjectType> types, const CompileOptions& instance_options,
                                 Sources& sources, Diagnostics& problems) {
  auto library = std::make_shared<const std::vector<ObjectType>>(types);
  std::map<std::string, TypeInstance> instances;
  Diagnostics found;
  for (const ObjectType& t : *library) instances[t.name] = instance_at_defaults(library, t, instance_options, sources, found);
  for (const Diagnostic& d : found.warnings()) problems.warning(d.mark, d.message);
  for (const Diagnostic& d : found.errors()) problems.error(d.mark, d.message);
  if (problems.has_errors()) return {};
  std::sort(types.begin(), types.end(), [](const ObjectType& a, const ObjectType& b) { return a.name < b.name; });
  std::map<std::string, std::string> base_of;
  for (const ObjectType& t : types) base_of[t.name] = t.extends.empty() ? "object" : t.extends;

  // Thumbnails first (rendering is what may fail), then the text that links them.
  const fs::path images = fs::path(md_path).parent_path() / "img" / "library";
  std::error_code ec;
  fs::create_directories(images, ec);
  if (ec) return fmt::format("cannot create {}: {}", images.string(), ec.message());
  for (const ObjectType& t : types) {
    const TypeInstance& in = instances[t.name];
    if (!in.workcell) continue;
    Diagnostics drawn;
    std::string png = render_thumbnail(*in.workcell, drawn);
    if (std::string err = write_file_atomic((images / (t.name + ".png")).string(), png); !err.empty()) return err;
  }
  std::ostringstream md;
  md << "# The type library\n\n"
        "The catalogue of the standard types (and of any `--library` folders it was made with), made by sscs itself:\n"
        "`sscs types --format md --out docs/library.md` writes this file and the thumbnails in `docs/img/library/`;\n"
        "`tools/test.sh` fails when the committed catalogue differs from a fresh one. Units: lengths m, angles deg,\n"
        "masses kg. Positions are at the type's defaults, in the type's own frame; an object's `location` puts that frame\n"
        "in its parent's, and `at: OBJECT.FRAME` stands an object at another's frame (docs/types.md). Expressions in\n"
        "defaults and limits are over the type's attributes.\n\n"
        "| type | kind | description |\n|---|---|---|\n";
  for (const ObjectType& t : types)
    md << fmt::format("| [`{}`](#{}) | {} | {} |\n", t.name, t.name, t.device ? "device" : t.container ? "container" : "object", cell(t.description));
  md << "\n";
  for (const ObjectType& t : types) write_type(md, t, base_of, instances[t.name], sources);
  return write_file_atomic(md_path, md.str());
}

}  // namespace sscs
