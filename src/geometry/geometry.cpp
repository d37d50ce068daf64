#include "geometry/geometry.h"

#include "core/units.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <optional>
#include <unordered_map>

#include <fmt/format.h>

#include "core/files.h"
#include "core/inertia.h"
#include "geometry/mesh_io.h"
#include "model/device.h"

namespace fs = std::filesystem;

namespace sscs {

std::vector<char> containers(const Workcell& wc) {
  std::vector<char> out(wc.objects.size(), 0);
  for (size_t i = 0; i < wc.objects.size(); ++i) out[i] = wc.types[wc.objects[i].type].container;
  return out;
}

double floor_z(const Workcell& wc, const GeometryModel& geometry) {
  const std::vector<char> container = containers(wc);
  std::optional<double> floor;
  for (size_t i = 0; i < container.size(); ++i)
    if (container[i] && !geometry.objects[i].bbox_world.isEmpty())
      floor = std::min(floor.value_or(INFINITY), geometry.objects[i].bbox_world.min().z());
  return floor.value_or(0);
}

double floor_under(const Workcell& wc, const GeometryModel& geometry, int object) {
  for (int k = wc.objects[object].parent; k >= 0; k = wc.objects[k].parent)
    if (wc.types[wc.objects[k].type].container && !geometry.objects[k].bbox_world.isEmpty())
      return geometry.objects[k].bbox_world.min().z();
  return floor_z(wc, geometry);
}

bool opens_into(const Workcell& wc, const GeometryModel& geometry, int c, int h) {
  const Eigen::AlignedBox3d &room = geometry.objects[c].bbox_world, &pit = geometry.objects[h].bbox_world;
  if (h == c || room.isEmpty() || pit.isEmpty() || geometry.objects[c].shapes.empty() || geometry.objects[h].shapes.empty()) return false;
  for (int k = wc.objects[c].parent; k >= 0; k = wc.objects[k].parent)
    if (k == h) return false;  // the room around c
  const double z = room.min().z();
  const Eigen::AlignedBox2d a(room.min().head<2>(), room.max().head<2>()), b(pit.min().head<2>(), pit.max().head<2>());
  const Eigen::AlignedBox2d both = a.intersection(b);
  return pit.min().z() < z - 1e-9 && pit.max().z() >= z - 1e-9 && !both.isEmpty() && (both.sizes().array() > 0).all();
}

std::vector<FloorBlock> floor_blocks(const Workcell& wc, const GeometryModel& geometry) {
  const double plane = floor_z(wc, geometry);
  const std::vector<char> container = containers(wc);
  // A container's box in its own frame: its shapes' bounds.
  auto local_box = [&](size_t c) {
    Eigen::AlignedBox3d box;
    for (const Shape& s : geometry.objects[c].shapes) box.extend(shape_bounds(s, s.X_object_shape));
    return box;
  };
  auto around = [&](size_t c) {  // the nearest container c stands in, or -1
    for (int k = wc.objects[c].parent; k >= 0; k = wc.objects[k].parent)
      if (container[k]) return k;
    return -1;
  };
  std::vector<FloorBlock> out;
  for (size_t c = 0; c < wc.objects.size(); ++c) {
    const Eigen::AlignedBox3d& world_box = geometry.objects[c].bbox_world;
    if (!container[c] || world_box.isEmpty() || geometry.objects[c].shapes.empty()) continue;
    const double z = world_box.min().z();
    if (z <= plane + 1e-9) continue;
    const Eigen::AlignedBox3d box = local_box(c);
    const Eigen::Isometry3d& X_world_c = geometry.objects[c].X_world_object;
    const int outer = around(c);
    const bool ground = outer < 0 || z <= geometry.objects[outer].bbox_world.min().z() + 1e-9;
    const double depth = ground ? z - plane : kFloorSlabThickness;
    // The footprint as rectangles in c's frame, each opening cut out: a container that is not
    // c or around it, whose bottom lies lower and whose top reaches c's floor.
    std::vector<Eigen::AlignedBox2d> pieces = {Eigen::AlignedBox2d(box.min().head<2>(), box.max().head<2>())};
    for (size_t h = 0; h < wc.objects.size(); ++h) {
      if (!container[h] || !opens_into(wc, geometry, static_cast<int>(c), static_cast<int>(h))) continue;
      Eigen::AlignedBox2d hole;
      const Eigen::AlignedBox3d pit_local = local_box(h);
      const Eigen::Isometry3d X_c_h = X_world_c.inverse() * geometry.objects[h].X_world_object;
      for (int corner = 0; corner < 8; ++corner) hole.extend((X_c_h * pit_local.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner))).head<2>());
      std::vector<Eigen::AlignedBox2d> kept;
      for (const Eigen::AlignedBox2d& r : pieces) {
        const Eigen::AlignedBox2d cut = r.intersection(hole);
        if (cut.isEmpty() || (cut.sizes().array() <= 0).any()) {
          kept.push_back(r);
          continue;
        }
        // Up to four rectangles around the hole: the strips left and right of it, then below and above it.
        auto add = [&](double x0, double y0, double x1, double y1) {
          if (x1 > x0 && y1 > y0) kept.emplace_back(Eigen::Vector2d(x0, y0), Eigen::Vector2d(x1, y1));
        };
        add(r.min().x(), r.min().y(), cut.min().x(), r.max().y());
        add(cut.max().x(), r.min().y(), r.max().x(), r.max().y());
        add(cut.min().x(), r.min().y(), cut.max().x(), cut.min().y());
        add(cut.min().x(), cut.max().y(), cut.max().x(), r.max().y());
      }
      pieces = std::move(kept);
    }
    for (const Eigen::AlignedBox2d& r : pieces) {
      FloorBlock b;
      b.container = static_cast<int>(c);
      b.size = Eigen::Vector3d(r.sizes().x(), r.sizes().y(), depth);
      b.X_world_centre = X_world_c * Eigen::Translation3d(r.center().x(), r.center().y(), box.min().z() - depth / 2);
      out.push_back(b);
    }
  }
  return out;
}

Eigen::AlignedBox3d shape_bounds(const Shape& s, const Eigen::Isometry3d& X) {
  Eigen::AlignedBox3d box;
  const Eigen::Matrix3d& R = X.linear();
  const Eigen::Vector3d& p = X.translation();
  switch (s.kind) {
    case Shape::Kind::Box: {
      // Extent of a rotated box: |R| * half extents.
      Eigen::Vector3d half = R.cwiseAbs() * (s.box_size / 2);
      box.extend(p - half);
      box.extend(p + half);
      break;
    }
    case Shape::Kind::Sphere:
      box.extend(p - Eigen::Vector3d::Constant(s.radius));
      box.extend(p + Eigen::Vector3d::Constant(s.radius));
      break;
    case Shape::Kind::Cylinder: {
      // Exact bounds of a cylinder: its axis ends, widened by the disc's extent per world axis.
      Eigen::Vector3d axis = R.col(2);
      Eigen::Vector3d disc = (Eigen::Vector3d::Ones() - axis.cwiseProduct(axis)).cwiseMax(0).cwiseSqrt() * s.radius;
      for (double end : {-s.length / 2, s.length / 2}) {
        box.extend(p + axis * end - disc);
        box.extend(p + axis * end + disc);
      }
      break;
    }
    case Shape::Kind::Mesh:
      for (const Eigen::Vector3d& v : s.mesh->vertices) box.extend(X * v.cwiseProduct(s.scale));
      break;
  }
  return box;
}

namespace {

/// Builds objects' shapes and device models from their types' templates; one per build.
class Builder {
 public:
  Builder(const Workcell& wc, Diagnostics& diag, MeshCache& meshes) : wc_(wc), diag_(diag), meshes_(meshes) {}

  /// Object `obj`'s attribute values (SI), which its templates read.
  const double* attributes(int obj) const { return &wc_.values[wc_.objects[obj].first_slot + kFirstAttributeSlot]; }

  /// The shapes of templates, evaluated for object `obj`.
  std::vector<Shape> shapes(const std::vector<ShapeTemplate>& templates, int obj, bool split_colours = false) {
    std::vector<Shape> out;
    const Object& o = wc_.objects[obj];
    const double* a = attributes(obj);
    auto check_positive = [&](double v, const ValueRef& r, const char* what) {
      if (!(std::isfinite(v) && v > 0))
        diag_.error(r.mark.valid() ? r.mark : o.mark, fmt::format("{} of '{}' is {}, expected a positive length", what, o.name, v));
      return v;
    };
    // One shape of template t, for copy `at` of a repeated one.
    auto add = [&](const ShapeTemplate& t, const double* at) {
      Shape s;
      s.X_object_shape = t.pose.eval(a, at);
      if (at) s.X_object_shape.translation() += t.repeat->offset(a, at);
      switch (t.kind) {
        case ShapeTemplate::Kind::Box:
          s.kind = Shape::Kind::Box;
          s.box_size = t.size.eval(a, 0, at);
          for (int k = 0; k < 3; ++k) check_positive(s.box_size[k], t.size.v[k], "box size");
          break;
        case ShapeTemplate::Kind::Cylinder:
          s.kind = Shape::Kind::Cylinder;
          s.radius = check_positive(t.radius.eval(a, 0, at), t.radius, "cylinder radius");
          s.length = check_positive(t.length.eval(a, 0, at), t.length, "cylinder length");
          break;
        case ShapeTemplate::Kind::Sphere:
          s.kind = Shape::Kind::Sphere;
          s.radius = check_positive(t.radius.eval(a, 0, at), t.radius, "sphere radius");
          break;
        case ShapeTemplate::Kind::Mesh:
          s.kind = Shape::Kind::Mesh;
          s.scale = t.scale.eval(a, 1, at);
          s.mesh = meshes_.load(t.mesh_file, t.mesh_mark, diag_);
          break;
      }
      s.color = t.color;
      if (s.kind == Shape::Kind::Mesh && !s.mesh) return;
      // What is drawn: a mesh whose file colours its materials (a vendor's DAE) becomes a shape
      // per colour, in that colour (the file's colours win over a URDF material's).
      if (split_colours && s.kind == Shape::Kind::Mesh && !s.mesh->triangle_rgb.empty()) {
        for (const auto& [rgb, piece] : coloured_pieces(s.mesh)) {
          Shape p = s;
          p.mesh = piece;
          if (rgb) p.color = fmt::format("#{:06x}", rgb & 0xffffffu);
          out.push_back(std::move(p));
        }
        return;
      }
      out.push_back(std::move(s));
    };
    for (const ShapeTemplate& t : templates) {
      if (!t.repeat) add(t, nullptr);
      else t.repeat->each(a, [&](const double* at) { add(t, at); });
    }
    return out;
  }

  /// A mesh's triangles grouped by the colour its file gives them (0: none), each group a mesh
  /// of its own; once per mesh file.
  const std::vector<std::pair<uint32_t, std::shared_ptr<const TriangleMesh>>>& coloured_pieces(const std::shared_ptr<const TriangleMesh>& mesh) {
    auto [it, fresh] = pieces_.try_emplace(mesh.get());
    if (!fresh) return it->second;
    // Each piece keeps only its own vertices (a textured mesh may have many colours).
    std::map<uint32_t, std::pair<std::shared_ptr<TriangleMesh>, std::map<int, int>>> by_colour;
    for (size_t t = 0; t < mesh->triangles.size(); ++t) {
      auto& [piece, index] = by_colour[mesh->triangle_rgb[t]];
      if (!piece) {
        piece = std::make_shared<TriangleMesh>();
        piece->path = mesh->path;
        piece->images = mesh->images;
      }
      Eigen::Vector3i triangle;
      for (int k = 0; k < 3; ++k) {
        auto [at, fresh] = index.try_emplace(mesh->triangles[t][k], static_cast<int>(piece->vertices.size()));
        if (fresh) piece->vertices.push_back(mesh->vertices[static_cast<size_t>(mesh->triangles[t][k])]);
        triangle[k] = at->second;
      }
      piece->triangles.push_back(triangle);
    }
    for (auto& [rgb, piece] : by_colour) it->second.emplace_back(rgb, std::move(piece.first));
    return it->second;
  }

  std::shared_ptr<TriangleMesh const> mesh(const std::string& path, SourceMark where) { return meshes_.load(path, where, diag_); }
  bool visuals = false;  ///< build the parts' visual shapes too

  /// The kinematic model of device object `obj` from its type's device template.
  std::shared_ptr<Device> device(int obj, const DeviceTemplate& dt) {
    const ObjectType& type = wc_.types[wc_.objects[obj].type];
    const double* a = attributes(obj);
    auto d = std::make_shared<Device>();
    d->kinematic = dt.kinematic;
    std::vector<int> at(dt.parts.size(), -1);  // the template's part -> the model's
    for (int k : dt.build_order) {
      const PartTemplate& pt = dt.parts[k];
      at[k] = static_cast<int>(d->parts.size());
      Part part;
      part.name = pt.name;
      part.parent = pt.parent < 0 ? -1 : at[pt.parent];
      part.shapes = shapes(pt.shapes, obj);
      if (visuals) part.visual_shapes = shapes(pt.visual_shapes, obj, /*split_colours=*/true);
      part.mass = pt.mass.eval(a, 0);
      // A type file's part mass (a URDF's is checked by its import): above 0, else no body; in
      // the range ODE integrates, else it was simulated as 1 kg without a word.
      if (pt.mass.present && !dt.from_urdf) {
        if (!(part.mass > 0) || !std::isfinite(part.mass))
          diag_.error(pt.mass.mark, fmt::format("the mass of part '{}' is {} kg; a mass is a finite number above 0", pt.name,
                                                number_text(part.mass)));
        else if (!simulable_mass(part.mass))
          diag_.warning(pt.mass.mark, fmt::format("the mass of part '{}', {} kg, is beyond the 1e-6 to 1e7 kg the physics "
                                                  "integrates: a run simulates it as 1 kg", pt.name, number_text(part.mass)));
      }
      part.color = pt.color;
      if (pt.inertial) {
        const Eigen::Isometry3d X = pt.inertial->origin.eval(a);
        part.com = X.translation();
        auto v = [&](int k) { return pt.inertial->inertia[k].eval(a, 0); };  // ixx ixy ixz iyy iyz izz
        Eigen::Matrix3d m;
        m << v(0), v(1), v(2), v(1), v(3), v(4), v(2), v(4), v(5);
        part.inertia = X.linear() * m * X.linear().transpose();
      }
      if (pt.joint) {
        const JointTemplate& jt = *pt.joint;
        Joint& j = part.joint;
        j.name = jt.name;
        j.type = jt.type;
        j.origin = jt.origin.eval(a);
        if (jt.type != JointType::Fixed) {
          j.axis = jt.axis.eval(a, 0).normalized();
          // Its limits are its attribute's, as the object's type has them (a subtype may narrow them).
          j.attribute = type.find_attribute(jt.name);
          const AttributeDef& attr = type.attributes[j.attribute];
          j.lower = attr.lower(a);
          j.upper = attr.upper(a);
          j.velocity = jt.velocity.eval(a, 0);
          j.acceleration = jt.acceleration.eval(a, 0);
          j.effort = jt.effort.eval(a, 0);
        }
      }
      d->parts.push_back(std::move(part));
    }
    for (int p : dt.joint_parts) {
      d->parts[at[p]].joint.q = d->dof();
      d->joint_parts.push_back(at[p]);
    }
    for (auto [pa, pb] : dt.allowed) d->allowed.emplace_back(std::min(at[pa], at[pb]), std::max(at[pa], at[pb]));
    std::sort(d->allowed.begin(), d->allowed.end());
    d->allowed.erase(std::unique(d->allowed.begin(), d->allowed.end()), d->allowed.end());
    if (dt.tool_part >= 0) {
      d->tool_part = at[dt.tool_part];
      d->X_part_tool = dt.tool_pose.eval(a);
    } else {
      d->tool_part = deepest_part(*d);
    }
    return d;
  }

 private:
  std::map<const TriangleMesh*, std::vector<std::pair<uint32_t, std::shared_ptr<const TriangleMesh>>>> pieces_;
  /// Without a `tool`, the tool is the end of the longest chain (the first such part).
  static int deepest_part(const Device& d) {
    std::vector<int> depth(d.parts.size(), 0);
    int best = 0;
    for (size_t i = 0; i < d.parts.size(); ++i) {
      if (d.parts[i].parent >= 0) depth[i] = depth[d.parts[i].parent] + 1;
      if (depth[i] > depth[best]) best = static_cast<int>(i);
    }
    return best;
  }

  const Workcell& wc_;
  Diagnostics& diag_;
  MeshCache& meshes_;
};

}  // namespace

GeometryModel build_geometry(const Workcell& wc, Diagnostics& diag, MeshCache* meshes, const GeometryOptions& options) {
  GeometryModel model;
  model.objects.resize(wc.objects.size());
  model.contacts = options.contacts;
  MeshCache own;
  Builder build(wc, diag, meshes ? *meshes : own);
  build.visuals = options.visuals;
  // Local poses first; world poses follow the parent chain (parents may come later in the file).
  std::vector<Eigen::Isometry3d> local(wc.objects.size());
  for (size_t i = 0; i < wc.objects.size(); ++i) {
    const Object& o = wc.objects[i];
    local[i] = wc.local_pose(static_cast<int>(i));
    if (!o.at.empty() && o.parent >= 0)
      if (auto X = wc.named_frame(o.parent, o.at)) model.objects[i].X_parent_at = *X;
  }
  std::vector<char> done(wc.objects.size(), 0);
  for (size_t i = 0; i < wc.objects.size(); ++i) {
    std::vector<int> chain;
    for (int k = static_cast<int>(i); k >= 0 && !done[k]; k = wc.objects[k].parent) chain.push_back(k);
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      int k = *it, p = wc.objects[k].parent;
      model.objects[k].X_world_object = p >= 0 ? model.objects[p].X_world_object * local[k] : local[k];
      done[k] = 1;
    }
  }
  for (size_t i = 0; i < wc.objects.size(); ++i) {
    const Object& o = wc.objects[i];
    // The type's templates (a type without its own geometry, frames or parts has its base's).
    const TypeTemplates& tt = wc.types[o.type].templates;
    ObjectGeometry& g = model.objects[i];
    int obj = static_cast<int>(i);
    if (!o.geomodel.empty()) {
      Shape s;
      s.kind = Shape::Kind::Mesh;
      s.mesh = build.mesh(o.geomodel, o.mark);
      if (s.mesh) g.shapes.push_back(std::move(s));
    } else {
      g.shapes = build.shapes(tt.geometry, obj);
      // A type with geometry whose repeats all come out empty here (a wall that is all opening):
      // nothing to check, and bounds of nothing read as NaN.
      if (g.shapes.empty() && !tt.geometry.empty() && !tt.device)
        diag.error(o.mark, fmt::format("'{}' (type '{}') has no geometry at these attributes: every shape of its type is repeated "
                                       "0 times", o.name, wc.types[o.type].name));
    }
    std::vector<std::pair<std::string, Eigen::Isometry3d>> device_frames;
    if (tt.device) {
      auto device = build.device(obj, *tt.device);
      // The device type's own shapes hang on the root part; the parts' at the instance's joint values.
      device->parts[0].shapes.insert(device->parts[0].shapes.end(), g.shapes.begin(), g.shapes.end());
      g.shapes.clear();
      g.device = device;
      const Device& d = *device;
      g.X_object_part = d.part_poses(d.joint_values(&wc.values[o.first_slot + kFirstAttributeSlot]));
      const std::vector<Eigen::Isometry3d>& X = g.X_object_part;
      bool any_visual = false;
      for (const Part& part : d.parts) any_visual = any_visual || !part.visual_shapes.empty();
      for (size_t p = 0; p < d.parts.size(); ++p) {
        auto place = [&](const std::vector<Shape>& from, std::vector<Shape>& to) {
          for (const Shape& ps : from) {
            Shape s = ps;
            s.X_object_shape = X[p] * ps.X_object_shape;
            s.part = static_cast<int>(p);
            to.push_back(std::move(s));
          }
        };
        place(d.parts[p].shapes, g.shapes);
        // Drawn: the part's visual shapes, or its collision shapes where it has none.
        if (any_visual) place(d.parts[p].visual_shapes.empty() ? d.parts[p].shapes : d.parts[p].visual_shapes, g.visual_shapes);
        device_frames.emplace_back(d.parts[p].name, g.X_world_object * X[p]);
      }
      device_frames.emplace_back("tool", g.X_world_object * X[d.tool_part] * d.X_part_tool);
    }
    for (const Shape& s : g.shapes) g.bbox_world.extend(shape_bounds(s, g.X_world_object * s.X_object_shape));
    if (tt.mass.present) {
      g.declared_mass = tt.mass.eval(build.attributes(obj), NAN);
      if (!(g.declared_mass > 0) || !std::isfinite(g.declared_mass))
        diag.error(o.mark, fmt::format("the mass of '{}' ({}, as type '{}' declares it) is {} kg; a mass is a finite number above 0",
                                       o.name, tt.mass.text, tt.mass_type, number_text(g.declared_mass)));
    }
    // Each location is within the limit; their sum along a chain of parents must be too.
    Eigen::Vector3d far = g.X_world_object.translation().cwiseAbs();
    if (!g.bbox_world.isEmpty()) far = g.bbox_world.max().cwiseAbs().cwiseMax(g.bbox_world.min().cwiseAbs());
    if (!far.allFinite() || far.maxCoeff() > kMaxLengthSi)
      diag.error(o.mark, fmt::format("'{}' reaches {} m from the origin (its parents' locations added), beyond the "
                                     "{:g} m (1000 km) sscs places things within", o.name, number_text(far.maxCoeff()), kMaxLengthSi));
    // Frames: the base types' first, a subtype's frame of the same name replacing its base's.
    for (const FrameTemplate& f : tt.frames)
      f.each(build.attributes(obj), [&](std::string name, const Eigen::Isometry3d& X) { g.frames_world.emplace_back(std::move(name), g.X_world_object * X); });
    // A device's parts and tool are frames too, unless the type names a frame so itself.
    for (auto& f : device_frames)
      if (!g.frame(f.first)) g.frames_world.push_back(std::move(f));
  }
  // A pit turned against the room it opens into, by other than a multiple of 90 degrees, opens
  // the box around it in that room's floor (floor_blocks): say so where the pit is placed.
  const std::vector<char> container = containers(wc);
  std::vector<size_t> spaces;  // (pairs of containers, not of every object: 10,000 objects took 0.1 s)
  for (size_t o = 0; o < wc.objects.size(); ++o)
    if (container[o]) spaces.push_back(o);
  for (size_t c : spaces)
    for (size_t h : spaces) {
      if (!opens_into(wc, model, static_cast<int>(c), static_cast<int>(h))) continue;
      const Eigen::Matrix3d R = model.objects[c].X_world_object.linear().transpose() * model.objects[h].X_world_object.linear();
      const double turn = std::atan2(R(1, 0), R(0, 0)) * 180 / std::numbers::pi;
      const double off = std::abs(turn - 90 * std::round(turn / 90));
      if (off > 1e-6)
        diag.warning(wc.objects[h].mark, fmt::format("'{}' is turned {:g} deg against '{}', whose floor it opens into: the floor is "
                                                     "cut by the box around it, in the frame of '{}', so beside its slanted sides "
                                                     "there is no floor for the physics and reach (turn it by a multiple of 90 deg "
                                                     "against '{}')", wc.objects[h].name, stable(turn), wc.objects[c].name,
                                                     wc.objects[c].name, wc.objects[c].name));
    }
  return model;
}

ScenePose ScenePose::of(const GeometryModel& geometry) {
  ScenePose p;
  for (const ObjectGeometry& g : geometry.objects) {
    p.X_world_object.push_back(g.X_world_object);
    p.X_object_part.push_back(g.X_object_part);
  }
  return p;
}

Eigen::Isometry3d absent_pose(int object) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Eigen::Vector3d(0, 0, -1e4 - 20.0 * object);
  return X;
}

void repose(ObjectGeometry& g, const Eigen::Isometry3d& X_world_object, const std::vector<Eigen::Isometry3d>* X_object_part) {
  const Eigen::Isometry3d move = X_world_object * g.X_world_object.inverse();
  const Device* d = g.device && X_object_part ? g.device.get() : nullptr;
  if (d) {
    // Each part's move, once (a device posed at every sample of a run).
    std::vector<Eigen::Isometry3d> part_move(X_object_part->size());
    for (size_t p = 0; p < part_move.size(); ++p) part_move[p] = (*X_object_part)[p] * g.X_object_part[p].inverse();
    for (Shape& s : g.shapes) s.X_object_shape = part_move[s.part] * s.X_object_shape;
    g.X_object_part = *X_object_part;
  }
  // A device's part and tool frames follow its parts (a part named like the tool first); the
  // type's own frames follow the object.
  for (auto& [name, X] : g.frames_world) {
    int part = -1;
    for (size_t p = 0; d && part < 0 && p < d->parts.size(); ++p)
      if (d->parts[p].name == name) part = static_cast<int>(p);
    if (part >= 0) X = X_world_object * g.X_object_part[part];
    else if (d && name == "tool") X = X_world_object * g.X_object_part[d->tool_part] * d->X_part_tool;
    else X = move * X;
  }
  g.X_world_object = X_world_object;
  g.bbox_world.setEmpty();
  for (const Shape& s : g.shapes) g.bbox_world.extend(shape_bounds(s, g.X_world_object * s.X_object_shape));
}

const Eigen::Isometry3d* ObjectGeometry::frame(std::string_view name) const {
  for (const auto& [n, X] : frames_world)
    if (n == name) return &X;
  return nullptr;
}

Eigen::Isometry3d ObjectGeometry::frame_pose(std::string_view name) const {
  if (name == "origin") return X_world_object;
  if (const Eigen::Isometry3d* X = frame(name)) return *X;
  Eigen::Isometry3d X = X_world_object;
  if (name == "top" && !bbox_world.isEmpty()) {
    Eigen::Vector3d c = bbox_world.center();
    X.translation() = Eigen::Vector3d(c.x(), c.y(), bbox_world.max().z());
  }
  return X;
}

double bbox_value(const GeometryModel& geometry, int object, uint32_t corner_axis) {
  const Eigen::AlignedBox3d& b = geometry.objects[object].bbox_world;
  if (b.isEmpty()) return NAN;
  int axis = static_cast<int>(corner_axis % 3);
  switch (corner_axis / 3) {
    case 0: return b.min()[axis];
    case 1: return b.max()[axis];
    default: return b.sizes()[axis];
  }
}

}  // namespace sscs
