#include "geometry/geometry.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <unordered_map>

#include <fmt/format.h>

#include "compile/compile.h"
#include "compile/values.h"
#include "core/expr.h"
#include "geometry/mesh_io.h"

namespace fs = std::filesystem;

namespace sscs {

Eigen::Matrix3d rpy_to_rotation(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
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

/// Evaluates type-file values (numbers, unit literals or expressions over the object's
/// attributes) for objects. Each written value is read once and kept by its address: a subtype
/// lists its base's attributes first and in the same order, so attribute indices carry over.
/// The type loader already reported problems with the text.
class ShapeEvaluator {
 public:
  explicit ShapeEvaluator(const Workcell& wc) : wc_(wc) {}

  double value(const Scalar& s, Dim dim, int object, double fallback) {
    if (!s.present) return fallback;
    const Compiled& c = compiled(s, dim, wc_.objects[object].type);
    if (!c.expr) return c.value;
    const Object& o = wc_.objects[object];
    inputs_.resize(c.attributes.size());
    for (size_t k = 0; k < c.attributes.size(); ++k)
      inputs_[k] = c.attributes[k] < 0 ? NAN : wc_.values[o.first_slot + kFirstAttributeSlot + c.attributes[k]];
    return c.expr->evaluate(inputs_.data());
  }

  Eigen::Vector3d vec(const std::array<Scalar, 3>& v, Dim dim, int object, double fallback) {
    return {value(v[0], dim, object, fallback), value(v[1], dim, object, fallback), value(v[2], dim, object, fallback)};
  }

  Eigen::Isometry3d pose(const PoseSpec& p, int object) {
    Eigen::Vector3d xyz = vec(p.xyz, Dim::Length, object, 0);
    Eigen::Vector3d rpy = vec(p.rpy, Dim::Angle, object, 0);
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() = rpy_to_rotation(rpy.x(), rpy.y(), rpy.z());
    X.translation() = xyz;
    return X;
  }

 private:
  struct Compiled {
    double value = NAN;
    std::unique_ptr<Expression> expr;
    std::vector<int> attributes;  ///< attribute index per expr->names()
  };

  const Compiled& compiled(const Scalar& s, Dim dim, int type) {
    auto [it, fresh] = cache_.try_emplace(&s);
    if (!fresh) return it->second;
    Compiled& c = it->second;
    Diagnostics scratch;
    ParsedValue v = parse_value(s, dim, "", scratch);
    if (v.kind == ParsedValue::Kind::Number) {
      c.value = v.si;
      return c;
    }
    if (auto e = Expression::parse(s.text, nullptr)) {
      c.expr = std::make_unique<Expression>(std::move(*e));
      for (const std::string& n : c.expr->names()) c.attributes.push_back(wc_.types[type].find_attribute(n));
    }
    return c;
  }

  const Workcell& wc_;
  std::unordered_map<const Scalar*, Compiled> cache_;  // lookups only
  std::vector<double> inputs_;
};

}  // namespace

GeometryModel build_geometry(const Workcell& wc, Diagnostics& diag) {
  GeometryModel model;
  model.objects.resize(wc.objects.size());
  ShapeEvaluator eval(wc);
  MeshCache meshes;
  // Local poses first; world poses follow the parent chain (parents may come later in the file).
  std::vector<Eigen::Isometry3d> local(wc.objects.size());
  for (size_t i = 0; i < wc.objects.size(); ++i) {
    const Object& o = wc.objects[i];
    const double* v = &wc.values[o.first_slot];
    local[i].setIdentity();
    local[i].linear() = rpy_to_rotation(v[kOrientationSlot], v[kOrientationSlot + 1], v[kOrientationSlot + 2]);
    local[i].translation() = Eigen::Vector3d(v[kLocationSlot], v[kLocationSlot + 1], v[kLocationSlot + 2]);
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
    // A type without its own geometry inherits its base type's.
    int t = o.type;
    while (!wc.types[t].spec->has_geometry && wc.types[t].base >= 0) t = wc.types[t].base;
    const TypeSpec& spec = *wc.types[t].spec;
    ObjectGeometry& g = model.objects[i];
    int obj = static_cast<int>(i);
    auto check_positive = [&](double v, const Scalar& s, const char* what) {
      if (!(std::isfinite(v) && v > 0))
        diag.error(s.mark.valid() ? s.mark : o.mark,
                   fmt::format("{} of '{}' is {}, expected a positive length", what, o.name, v));
      return v;
    };
    if (!o.geomodel.empty()) {
      Shape s;
      s.kind = Shape::Kind::Mesh;
      s.mesh = meshes.load(o.geomodel, o.mark, diag);
      if (s.mesh) g.shapes.push_back(std::move(s));
    } else {
      for (const GeometrySpec& gs : spec.geometry) {
        Shape s;
        s.X_object_shape = eval.pose(gs.pose, obj);
        std::visit(
            [&](const auto& shape) {
              using T = std::decay_t<decltype(shape)>;
              if constexpr (std::is_same_v<T, BoxSpec>) {
                s.kind = Shape::Kind::Box;
                s.box_size = eval.vec(shape.size, Dim::Length, obj, 0);
                for (int k = 0; k < 3; ++k) check_positive(s.box_size[k], shape.size[k], "box size");
              } else if constexpr (std::is_same_v<T, CylinderSpec>) {
                s.kind = Shape::Kind::Cylinder;
                s.radius = check_positive(eval.value(shape.radius, Dim::Length, obj, 0), shape.radius, "cylinder radius");
                s.length = check_positive(eval.value(shape.length, Dim::Length, obj, 0), shape.length, "cylinder length");
              } else if constexpr (std::is_same_v<T, SphereSpec>) {
                s.kind = Shape::Kind::Sphere;
                s.radius = check_positive(eval.value(shape.radius, Dim::Length, obj, 0), shape.radius, "sphere radius");
              } else {
                s.kind = Shape::Kind::Mesh;
                s.scale = eval.vec(shape.scale, Dim::None, obj, 1);
                s.mesh = meshes.load(resolve_mesh_path(spec.path, shape.file.text), shape.file.mark, diag);
              }
            },
            gs.shape);
        if (s.kind != Shape::Kind::Mesh || s.mesh) g.shapes.push_back(std::move(s));
      }
    }
    for (const Shape& s : g.shapes) g.bbox_world.extend(shape_bounds(s, g.X_world_object * s.X_object_shape));
    // Frames: the base types' first, a subtype's frame of the same name replacing its base's.
    std::vector<int> chain;
    for (int k = o.type; k >= 0; k = wc.types[k].base) chain.insert(chain.begin(), k);
    for (int k : chain)
      for (const FrameSpec& f : wc.types[k].spec->frames) {
        Eigen::Isometry3d X = g.X_world_object * eval.pose(f.pose, obj);
        auto same = std::find_if(g.frames_world.begin(), g.frames_world.end(), [&](const auto& e) { return e.first == f.name; });
        if (same != g.frames_world.end()) same->second = X;
        else g.frames_world.emplace_back(f.name, X);
      }
  }
  return model;
}

const Eigen::Isometry3d* ObjectGeometry::frame(std::string_view name) const {
  for (const auto& [n, X] : frames_world)
    if (n == name) return &X;
  return nullptr;
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
