// URDF devices: `urdf: robots/ur5.urdf` in a device type. urdfdom parses the file; its links and
// joints become the same PartSpec/JointSpec a type file writes, so everything after loading
// treats URDF and native devices alike. Values are written out as text in SI (lengths in m,
// angles as "<x> rad"), marked at the type file's `urdf:` key.
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include <console_bridge/console.h>
#include <map>
#include <optional>
#include <set>
#include <tinyxml.h>

#include <fmt/format.h>
#include <urdf_parser/urdf_parser.h>

#include "core/inertia.h"
#include "core/names.h"
#include "core/files.h"
#include "load/load.h"
#include "load/urdf_xml.h"

namespace fs = std::filesystem;

namespace sscs {

namespace {

/// Collects urdfdom's messages (it logs through console_bridge) instead of printing them.
class CapturedLog : public console_bridge::OutputHandler {
 public:
  CapturedLog() {
    previous_ = console_bridge::getOutputHandler();
    console_bridge::useOutputHandler(this);
  }
  ~CapturedLog() override { console_bridge::useOutputHandler(previous_); }
  CapturedLog(const CapturedLog&) = delete;
  CapturedLog& operator=(const CapturedLog&) = delete;
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR && messages_.size() < 5) messages_.push_back(text);
  }
  std::string text() const {
    std::string out;
    for (const std::string& m : messages_) out += (out.empty() ? "" : "; ") + m;
    return out;
  }

 private:
  console_bridge::OutputHandler* previous_;
  std::vector<std::string> messages_;
};

/// The <safety_controller> soft limits a joint's element writes (each optional: urdfdom reads an
/// attribute that is absent as 0, which would pin the joint at 0).
struct SoftLimits {
  std::optional<double> lower, upper;
};

/// Per joint name, the soft limits written in the URDF (read from the document urdfdom reads too,
/// to tell a written 0 from an absent attribute).
std::map<std::string, SoftLimits> read_soft_limits(const TiXmlElement& robot) {
  std::map<std::string, SoftLimits> out;
  for (const TiXmlElement* j = robot.FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const TiXmlElement* safety = j->FirstChildElement("safety_controller");
    const char* name = j->Attribute("name");
    if (!safety || !name) continue;
    SoftLimits s;
    double v = 0;
    if (safety->QueryDoubleAttribute("soft_lower_limit", &v) == TIXML_SUCCESS) s.lower = v;
    if (safety->QueryDoubleAttribute("soft_upper_limit", &v) == TIXML_SUCCESS) s.upper = v;
    // One side given: the other is 0, as the URDF format defines it and MoveIt reads it (the
    // checker warns). Neither given: no soft limits.
    if (s.lower && !s.upper) s.upper = 0.0;
    if (s.upper && !s.lower) s.lower = 0.0;
    out[name] = s;
  }
  return out;
}

/// Where each link's <visual> and <collision> shapes are in the URDF, in file order (urdfdom
/// keeps that order): a mesh's filename attribute, another shape's element. So what is found
/// wrong with a shape later (a mesh that cannot be read) is reported at its line.
/// Where each link and joint is, by name: what is found wrong with one is reported at its line.
struct ElementMarks {
  std::map<std::string, std::map<std::string, std::vector<SourceMark>>> shapes;  // link -> visual/collision -> marks
  std::map<std::string, SourceMark> links, joints;
};

ElementMarks read_element_marks(const TiXmlElement& robot, uint32_t file) {
  ElementMarks marks;
  for (const TiXmlElement* j = robot.FirstChildElement("joint"); j; j = j->NextSiblingElement("joint"))
    if (const char* name = j->Attribute("name")) marks.joints.emplace(name, xml_mark(file, *j));
  auto& out = marks.shapes;
  for (const TiXmlElement* l = robot.FirstChildElement("link"); l; l = l->NextSiblingElement("link")) {
    const char* name = l->Attribute("name");
    if (!name) continue;
    marks.links.emplace(name, xml_mark(file, *l));
    for (const char* kind : {"visual", "collision"})
      for (const TiXmlElement* e = l->FirstChildElement(kind); e; e = e->NextSiblingElement(kind)) {
        const TiXmlElement* g = e->FirstChildElement("geometry");
        const TiXmlElement* shape = g ? g->FirstChildElement() : nullptr;
        SourceMark mark = xml_mark(file, shape ? *shape : *e);
        if (shape)
          for (const TiXmlAttribute* a = shape->FirstAttribute(); a; a = a->Next())
            if (std::string_view(a->Name()) == "filename") mark = xml_mark(file, *a);
        out[name][kind].push_back(mark);
      }
  }
  return marks;
}

class Converter {
 public:
  Converter(const Scalar& at, std::string urdf_path, const std::vector<std::string>& package_paths, DeviceSpec& device,
            ElementMarks marks)
      : at_(at), urdf_path_(std::move(urdf_path)), package_paths_(package_paths), problems_(device.import_problems),
        mesh_refs_(device.urdf_mesh_refs), marks_(std::move(marks)) {}

  Scalar number(double v, const char* unit = "") const {
    Scalar s;
    s.present = true;
    s.mark = at_.mark;
    s.text = *unit ? fmt::format("{:.17g} {}", v, unit) : fmt::format("{:.17g}", v);
    return s;
  }

  PoseSpec pose(const urdf::Pose& p) const {
    PoseSpec out;
    double r, pi, y;
    p.rotation.getRPY(r, pi, y);
    out.xyz = {number(p.position.x), number(p.position.y), number(p.position.z)};
    out.rpy = {number(r, "rad"), number(pi, "rad"), number(y, "rad")};
    return out;
  }

  /// Where the element being converted is: the joint's or link's line in the URDF (else the
  /// type file's `urdf:` line).
  SourceMark here() const {
    if (shape_) return *shape_;
    if (!joint_.empty())
      if (auto it = marks_.joints.find(joint_); it != marks_.joints.end()) return it->second;
    if (!link_.empty())
      if (auto it = marks_.links.find(link_); it != marks_.links.end()) return it->second;
    return at_.mark;
  }
  /// An error of the import, at the element being converted, naming the link while a link is.
  void error(const std::string& what) const { error_at(here(), what); }
  void error_at(const SourceMark& mark, const std::string& what) const {
    problems_.push_back({mark, fmt::format("{}{}", link_.empty() || !joint_.empty() ? "" : fmt::format("link '{}': ", link_), what)});
  }
  /// Something the import skips, reported (as a warning) where the type is used, at its element.
  void warn(const std::string& what) const { warn_at(here(), what); }
  void warn_at(const SourceMark& mark, const std::string& what) const {
    problems_.push_back({mark, fmt::format("link '{}': {}", link_, what), true});
  }
  void warn_not_drawn(const std::string& what) const { warn(what + ": that visual is not drawn"); }

  /// `package://pkg/path` through --package-path (and ROS_PACKAGE_PATH), `file://` absolute,
  /// anything else relative to the URDF file. What cannot be resolved is reported through
  /// `report` (an error, or a warning for a visual the link does not need).
  std::optional<std::string> mesh_path(const std::string& uri, void (Converter::*report)(const std::string&) const) const {
    std::error_code ec;
    if (uri.starts_with("package://")) {
      std::string rest = uri.substr(10);
      auto slash = rest.find('/');
      std::string package = rest.substr(0, slash);
      std::string inside = slash == std::string::npos ? "" : rest.substr(slash + 1);
      std::vector<std::string> roots = package_paths_;
      for (const std::string& dir : ros_package_path()) roots.push_back(dir);
      for (const std::string& root : roots)
        if (const std::string dir = find_ros_package(root, package); !dir.empty())
          if (const fs::path candidate = fs::path(dir) / inside; fs::is_regular_file(candidate, ec))
            return fs::absolute(candidate).lexically_normal().string();
      (this->*report)(fmt::format("mesh '{}' not found: no package '{}' holding '{}' under {}", uri, package, inside,
                                  roots.empty() ? std::string("any --package-path (none given)")
                                                : fmt::format("the package paths ({})", fmt::join(roots, ", "))));
      return std::nullopt;
    }
    // file:///abs/path, or file://localhost/abs/path (RFC 8089's explicit local host).
    const std::string local = uri.starts_with("file://localhost/") ? uri.substr(16) : uri.starts_with("file://") ? uri.substr(7) : uri;
    fs::path p(local);
    if (uri.starts_with("file://") && p.is_relative()) {  // file://meshes/a.stl names host 'meshes' (RFC 8089)
      (this->*report)(fmt::format("mesh '{}': a file:// URI names an absolute path (file:///...); write a path relative to "
                                  "the URDF without file://", uri));
      return std::nullopt;
    }
    if (p.is_relative()) p = join_path(fs::path(urdf_path_).parent_path().string(), p.string());
    if (std::string why = not_a_readable_reference(p.string()); !why.empty()) {
      (this->*report)(fmt::format("mesh '{}' {} ({})", uri, why, p.string()));
      return std::nullopt;
    }
    return join_path(fs::current_path().string(), p.string());
  }

  /// A <visual> or <collision> shape (`element` names which); nullopt when absent, unreadable
  /// (an error) or degenerate: a shape with no volume (Franka's zero-length cylinder on
  /// panda_mount) is skipped with a warning, for it is no solid to check or draw.
  /// A mesh a `needed` shape names that cannot be found is an error; one of a visual the link
  /// does not need (it has collision shapes) is a warning: that visual is not drawn.
  std::optional<GeometrySpec> geometry(const urdf::GeometrySharedPtr& g, const urdf::Pose& origin, const char* element,
                                       size_t index, bool needed = true) const {
    if (!g) return std::nullopt;
    SourceMark mark = here();
    if (auto l = marks_.shapes.find(link_); l != marks_.shapes.end())
      if (auto e = l->second.find(element); e != l->second.end() && index < e->second.size()) mark = e->second[index];
    struct Converting {  // messages while the shape is converted are at its element
      std::optional<SourceMark>& shape;
      ~Converting() { shape.reset(); }
    } converting{shape_ = mark};
    auto degenerate = [&](const char* shape, const std::string& what) {
      warn_at(mark, fmt::format("its <{}> {} has {}: skipped, for it has no volume", element, shape, what));
      return std::nullopt;
    };
    auto not_positive = [](double v) { return !(v > 0); };
    switch (g->type) {
      case urdf::Geometry::BOX: {
        const urdf::Vector3& d = static_cast<const urdf::Box*>(g.get())->dim;
        if (not_positive(d.x) || not_positive(d.y) || not_positive(d.z))
          return degenerate("box", fmt::format("size {} {} {}", d.x, d.y, d.z));
        break;
      }
      case urdf::Geometry::CYLINDER: {
        auto* c = static_cast<const urdf::Cylinder*>(g.get());
        if (not_positive(c->length)) return degenerate("cylinder", fmt::format("length {}", c->length));
        if (not_positive(c->radius)) return degenerate("cylinder", fmt::format("radius {}", c->radius));
        break;
      }
      case urdf::Geometry::SPHERE:
        if (double r = static_cast<const urdf::Sphere*>(g.get())->radius; not_positive(r))
          return degenerate("sphere", fmt::format("radius {}", r));
        break;
      case urdf::Geometry::MESH: {
        const urdf::Vector3& k = static_cast<const urdf::Mesh*>(g.get())->scale;
        if (k.x == 0 || k.y == 0 || k.z == 0) return degenerate("mesh", fmt::format("scale {} {} {}", k.x, k.y, k.z));
        break;
      }
    }
    GeometrySpec out;
    out.mark = mark;
    out.pose = pose(origin);
    switch (g->type) {
      case urdf::Geometry::BOX: {
        auto* b = static_cast<const urdf::Box*>(g.get());
        out.shape = BoxSpec{{number(b->dim.x), number(b->dim.y), number(b->dim.z)}};
        break;
      }
      case urdf::Geometry::CYLINDER: {
        auto* c = static_cast<const urdf::Cylinder*>(g.get());
        out.shape = CylinderSpec{number(c->radius), number(c->length)};
        break;
      }
      case urdf::Geometry::SPHERE:
        out.shape = SphereSpec{number(static_cast<const urdf::Sphere*>(g.get())->radius)};
        break;
      case urdf::Geometry::MESH: {
        auto* m = static_cast<const urdf::Mesh*>(g.get());
        auto path = mesh_path(m->filename, needed ? &Converter::error : &Converter::warn_not_drawn);
        if (!path) return std::nullopt;
        mesh_refs_.emplace_back(m->filename, *path);
        MeshSpec mesh;
        mesh.file = number(0);
        mesh.file.text = *path;
        mesh.file.mark = out.mark;  // a mesh that cannot be read is reported at its line of the URDF
        mesh.scale = {number(m->scale.x), number(m->scale.y), number(m->scale.z)};
        out.shape = std::move(mesh);
        break;
      }
    }
    return out;
  }

  /// Whether a material gives a colour (one named only for its texture reads as transparent black).
  static bool has_color(const urdf::Material& m) { return m.color.a > 0 || m.color.r > 0 || m.color.g > 0 || m.color.b > 0; }
  static std::string hex(const urdf::Color& c) {
    auto byte = [](float x) { return static_cast<int>(std::lround(std::clamp(x, 0.0f, 1.0f) * 255)); };
    return fmt::format("#{:02x}{:02x}{:02x}", byte(c.r), byte(c.g), byte(c.b));
  }

  PartSpec part(const urdf::Link& link) const {
    PartSpec p;
    p.name = link.name;
    link_.clear();
    auto at = marks_.links.find(link.name);
    p.mark = at != marks_.links.end() ? at->second : at_.mark;
    if (!is_valid_name(link.name))
      error_at(p.mark, fmt::format("link name '{}' is not a valid sscs name (a letter, then letters, digits, _ or -)", link.name));
    link_ = link.name;
    // Collision shapes are what the checker needs; a link with only visuals uses those. The
    // visuals, each with its material's colour, are what the link looks like.
    std::vector<GeometrySpec> visual;
    const bool visuals_needed = link.collision_array.empty();  // else checks never read them
    for (size_t k = 0; k < link.visual_array.size(); ++k)
      if (const auto& v = link.visual_array[k]; auto g = geometry(v->geometry, v->origin, "visual", k, visuals_needed)) {
        if (v->material && has_color(*v->material)) g->color = hex(v->material->color);
        visual.push_back(std::move(*g));
      }
    if (!link.collision_array.empty()) {
      for (size_t k = 0; k < link.collision_array.size(); ++k)
        if (const auto& c = link.collision_array[k]; auto g = geometry(c->geometry, c->origin, "collision", k))
          p.geometry.push_back(std::move(*g));
      p.visual = std::move(visual);
    } else {
      p.geometry = visual;  // checked as what it looks like
      p.visual = std::move(visual);
    }
    for (const auto& v : link.visual_array)
      if (v->material && has_color(*v->material) && p.color.text.empty()) {
        p.color = number(0);
        p.color.text = hex(v->material->color);
      }
    if (link.inertial) {
      const urdf::Inertial& i = *link.inertial;
      p.mass = number(i.mass);
      Eigen::Matrix3d I;
      I << i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz;
      // A massless link (mass and inertia all 0: a frame the vendor never meant to simulate) is
      // as if it wrote no <inertial>; any other body ODE cannot integrate is warned about.
      if (std::string why = unphysical_inertia(i.mass, I); why.empty()) {
        InertialSpec in;
        in.origin = pose(i.origin);
        in.inertia = {number(i.ixx), number(i.ixy), number(i.ixz), number(i.iyy), number(i.iyz), number(i.izz)};
        p.inertial = std::move(in);
      } else if (i.mass != 0 || !I.isZero()) {
        warn(fmt::format("its <inertial> is not a physical body ({}): simulated as a box around its shapes{}", why,
                         simulable_mass(i.mass) ? fmt::format(" of {} kg", i.mass) : " of 1 kg"));
      }
    }
    link_.clear();
    return p;
  }

  /// A joint; `soft` holds the <safety_controller> soft limits the file writes for it (urdfdom
  /// reads an absent one as 0), which narrow its <limit>, as MoveIt reads them.
  std::optional<JointSpec> joint(const urdf::Joint& j, const SoftLimits& soft) const {
    struct Converting {  // messages while the joint is converted are at its element
      std::string& joint;
      ~Converting() { joint.clear(); }
    } converting{joint_ = j.name};
    JointSpec out;
    out.name = j.name;
    out.mark = here();
    out.origin = pose(j.parent_to_joint_origin_transform);
    out.axis = {number(j.axis.x), number(j.axis.y), number(j.axis.z)};
    if (!is_valid_name(j.name))
      error(fmt::format("joint name '{}' is not a valid sscs name (a letter, then letters, digits, _ or -)", j.name));
    const char* unit = "";
    switch (j.type) {
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS:
        out.type = JointType::Revolute;
        unit = "rad";
        break;
      case urdf::Joint::PRISMATIC: out.type = JointType::Prismatic; break;
      case urdf::Joint::FIXED: out.type = JointType::Fixed; break;
      default:
        error(fmt::format("joint '{}' is {}: sscs devices have revolute, continuous, prismatic and fixed joints "
                          "(model a mobile base as prismatic x, y and revolute z joints)",
                          j.name, j.type == urdf::Joint::FLOATING ? "floating" : j.type == urdf::Joint::PLANAR ? "planar" : "of unknown type"));
        return std::nullopt;
    }
    if (j.limits && out.type != JointType::Fixed) {
      if (j.type != urdf::Joint::CONTINUOUS) {
        if (!(j.limits->lower <= j.limits->upper)) {  // the file's fault, not an instance's joint value
          error(fmt::format("joint '{}' has its lower limit {} above its upper limit {}", j.name, j.limits->lower, j.limits->upper));
          return std::nullopt;
        }
        double lower = j.limits->lower, upper = j.limits->upper;
        if (soft.lower) lower = std::max(lower, *soft.lower);
        if (soft.upper) upper = std::min(upper, *soft.upper);
        out.soft_limited = lower != j.limits->lower || upper != j.limits->upper;
        if (!(lower <= upper)) {
          error(fmt::format("joint '{}' has soft limits [{}, {}] that leave nothing of its limits [{}, {}] (joint_limits: hard "
                            "ignores the soft limits)", j.name, soft.lower.value_or(-INFINITY), soft.upper.value_or(INFINITY),
                            j.limits->lower, j.limits->upper));
          return std::nullopt;
        }
        out.min = number(lower, unit);
        out.max = number(upper, unit);
      }
      if (j.limits->velocity > 0) out.velocity = number(j.limits->velocity, unit);
      if (j.limits->effort > 0) out.effort = number(j.limits->effort);
    }
    return out;
  }

 private:
  const Scalar& at_;
  std::string urdf_path_;
  const std::vector<std::string>& package_paths_;
  std::vector<Diagnostic>& problems_;
  std::vector<std::pair<std::string, std::string>>& mesh_refs_;
  ElementMarks marks_;
  mutable std::string link_;   ///< the link being converted, for messages
  mutable std::string joint_;  ///< the joint being converted, for messages
  mutable std::optional<SourceMark> shape_;  ///< the shape being converted: where it is
};

}  // namespace

void load_urdf(DeviceSpec& device, const std::string& type_file, const std::vector<std::string>& package_paths,
               Sources& sources) {
  const Scalar& at = device.urdf;
  const std::string urdf_path = resolve_mesh_path(type_file, at.text);
  // Read like every input file (project root, size limit, not a FIFO), so errors point into it.
  Diagnostics diag;
  auto keep = [&] {
    for (const Diagnostic& d : diag.warnings()) device.import_problems.push_back({d.mark, d.message, true});
    for (const Diagnostic& d : diag.errors()) device.import_problems.push_back(d);
  };
  TiXmlDocument doc;
  uint32_t file = 0;
  const TiXmlElement* robot = read_robot_xml("URDF file", type_file, at, sources, diag, doc, file);
  if (!robot) return keep();
  const std::string& text = sources.text(file);
  if (const char* name = robot->Attribute("name")) device.urdf_robot = name;
  check_urdf_numbers(*robot, file, diag);
  if (!diag.has_errors()) check_urdf_tree(*robot, file, diag);
  keep();  // its errors, and its warnings (reported where the type is used)
  if (diag.has_errors()) return;
  urdf::ModelInterfaceSharedPtr model;
  std::string log;
  {
    CapturedLog capture;
    model = urdf::parseURDF(text);
    log = capture.text();
  }
  // urdfdom's links hold their children by shared_ptr, so a joint whose parent is its child
  // keeps the model alive for ever; drop those pointers when done.
  struct Release {
    urdf::ModelInterfaceSharedPtr& model;
    ~Release() {
      if (model)
        for (auto& [name, link] : model->links_) link->child_links.clear();
    }
  } release{model};
  if (!model || !model->getRoot()) {
    device.import_problems.push_back(
        {at.mark, fmt::format("cannot read URDF file '{}': {}", at.text, log.empty() ? "not a valid URDF robot" : log)});
    return;
  }
  Converter convert(at, urdf_path, package_paths, device, read_element_marks(*robot, file));
  const std::map<std::string, SoftLimits> soft_limits = read_soft_limits(*robot);
  // Links from the root down, each after its parent, in the order the file's joints list them.
  std::vector<urdf::LinkConstSharedPtr> order = {model->getRoot()};
  std::set<const urdf::Link*> seen = {model->getRoot().get()};
  for (size_t i = 0; i < order.size(); ++i)
    for (const auto& child : order[i]->child_links) {
      // A joint whose parent is its child (or a loop of joints) made this walk grow for ever.
      if (!seen.insert(child.get()).second) {
        device.import_problems.push_back(
            {at.mark, fmt::format("URDF file '{}': link '{}' is reached twice from the root (joint '{}' closes a loop, or a "
                                  "joint's parent is its child): a device is a tree",
                                  at.text, child->name, child->parent_joint ? child->parent_joint->name : "?")});
        return;
      }
      order.push_back(child);
    }
  for (const auto& link : order) {
    PartSpec p = convert.part(*link);
    if (auto j = link->parent_joint) {
      p.parent = j->parent_link_name;
      p.parent_mark = at.mark;
      SoftLimits none;
      auto soft = device.hard_limits ? soft_limits.end() : soft_limits.find(j->name);
      p.joint = convert.joint(*j, soft == soft_limits.end() ? none : soft->second);
      if (!p.joint) {  // reported; made fixed, so its children still load
        p.joint.emplace();
        p.joint->name = j->name;
        p.joint->mark = at.mark;
      }
    }
    device.parts.push_back(std::move(p));
  }
}

}  // namespace sscs
