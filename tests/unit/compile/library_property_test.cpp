// The standard library over its whole attribute space: every type (found by listing the folder,
// so a new type is covered without editing this test) compiles and builds at its defaults, with
// each attribute at its min and at its max, and in random configurations within its limits; its
// shapes, bounds and frames are then finite, its repeated frames are all there, and every frame
// lies on or outside its solids (a reach to it is not refused as buried).
#include <filesystem>
#include <random>

#include <fmt/format.h>
#include <gmock/gmock.h>

#include "geometry/collision.h"
#include "geometry/geometry.h"
#include "model/device.h"
#include "vault_fixture.h"

namespace sscs::testing {
namespace {

class LibraryProperty : public VaultTest {
 public:
  /// The standard types, by name.
  std::vector<const ObjectType*> standard_types(const Workcell& wc) {
    std::vector<const ObjectType*> out;
    for (const auto& e : std::filesystem::directory_iterator(std::string(SSCS_LIBRARY_DIR) + "/types")) {
      const int t = wc.find_type(e.path().stem().string());
      EXPECT_GE(t, 0) << e.path();
      if (t >= 0) out.push_back(&wc.types[t]);
    }
    std::sort(out.begin(), out.end(), [](const ObjectType* a, const ObjectType* b) { return a->name < b->name; });
    return out;
  }

  /// An attribute's value as a vault writes it (file units).
  static std::string file_value(const AttributeDef& a, double si) {
    if (a.type == AttrType::Integer) return fmt::format("{}", static_cast<long long>(std::llround(si)));
    return fmt::format("{:.17g}", si_to_file(si, a.dim));
  }

  /// Compiles one instance of `type` with `values` (attribute: text) and builds it; checks what
  /// every instance must satisfy. `what` says which configuration it is. False when the type's
  /// own rules (`requires:`) refuse the configuration, and nothing else does.
  bool expect_sound(const ObjectType& type, const std::vector<std::pair<std::string, std::string>>& values, const std::string& what) {
    std::string object = "{type: " + type.name + ", name: X";
    for (const auto& [k, v] : values) object += ", " + k + ": " + v;
    object += "}";
    diag = Diagnostics{};
    auto wc = compile_text("objects:\n  - " + object + "\n");
    if (!wc && !type.templates.rules.empty() && !diag.errors().empty() &&
        std::all_of(diag.errors().begin(), diag.errors().end(), [&](const Diagnostic& d) {
          return d.message.find("; the rule '") != std::string::npos && d.message.find("' of type '") != std::string::npos;
        }))
      return false;
    EXPECT_TRUE(wc) << what << ": " << object << "\n" << diag.format(sources);
    if (!wc) return true;
    GeometryModel g = build_geometry(*wc, diag);
    EXPECT_FALSE(diag.has_errors()) << what << ": " << object << "\n" << diag.format(sources);
    if (diag.has_errors()) return true;
    EXPECT_TRUE(diag.warnings().empty()) << what << ": " << object << "\n" << diag.format(sources);
    const ObjectGeometry& o = g.objects[0];
    std::vector<Shape> shapes = o.shapes;
    if (o.device) {
      for (const Part& p : o.device->parts) shapes.insert(shapes.end(), p.shapes.begin(), p.shapes.end());
    }
    EXPECT_FALSE(shapes.empty()) << what << ": " << object;
    for (const Shape& s : shapes) {
      EXPECT_TRUE(s.X_object_shape.matrix().allFinite()) << what << ": " << object;
      if (s.kind == Shape::Kind::Box) {
        EXPECT_GT(s.box_size.minCoeff(), 0) << what << ": " << object;
      }
    }
    EXPECT_TRUE(!o.bbox_world.isEmpty() && o.bbox_world.min().allFinite() && o.bbox_world.max().allFinite()) << what << ": " << object;
    // Nothing stands below the floor its origin is on (a drum_rack took a first beam 0.1 m up,
    // under a beam 0.102 m deep: 2 mm into the floor). Devices move their parts: their joints'
    // limits are another test's.
    if (!o.device) {
      EXPECT_GE(o.bbox_world.min().z(), -1e-9) << what << ": " << object << " reaches " << -o.bbox_world.min().z() << " m below its floor";
    }
    // Every frame a vault can name is there and finite; none is buried in the type's own solids.
    CollisionWorld world(g);
    for (const std::string& name : wc->frame_names(0)) {
      const Eigen::Isometry3d X = o.frame_pose(name);
      EXPECT_TRUE(X.matrix().allFinite()) << what << ": " << object << " ." << name;
      if (name == "origin" || (o.device && o.device->find_part(name) >= 0)) continue;
      EXPECT_LE(world.depth_inside(0, X.translation()), 1e-9) << what << ": " << object << " ." << name;
    }
    // A repeated frame has a copy for each combination of its counts.
    const double* attributes = &wc->values[wc->objects[0].first_slot + kFirstAttributeSlot];
    for (const FrameTemplate& f : type.templates.frames) {
      if (!f.repeat) continue;
      double copies = 1;
      for (const RepeatTemplate::Counter& c : f.repeat->counters) copies *= c.count.eval(attributes, NAN);
      size_t found = 0;
      f.each(attributes, [&](const std::string& name, const Eigen::Isometry3d&) { found += o.frame(name) != nullptr; });
      EXPECT_EQ(static_cast<double>(found), copies) << what << ": " << object << " " << f.name;
    }
    return true;
  }

  /// Values for the attributes a type requires (no default): their min, else 1.
  static std::vector<std::pair<std::string, std::string>> required(const ObjectType& type) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const AttributeDef& a : type.attributes)
      if (!a.default_value.present && !a.joint) out.emplace_back(a.name, file_value(a, a.min_si.value_or(1) + 4));
    return out;
  }
};

TEST_F(LibraryProperty, EveryTypeIsSoundAtItsDefaultsAndWithEachAttributeAtItsLimits) {
  options.whole_library = true;  // (the templates of every type, not only those it uses: none)
  Workcell lib = must_compile("objects: []\n");
  options.whole_library = false;
  options.library = std::make_shared<const std::vector<ObjectType>>(lib.types);  // loaded once
  size_t configurations = 0;
  for (const ObjectType* type : standard_types(lib)) {
    EXPECT_TRUE(expect_sound(*type, required(*type), "defaults")) << type->name << ": its own rules refuse its defaults";
    ++configurations;
    for (const AttributeDef& a : type->attributes) {
      if (a.type == AttrType::Enum) {
        for (const std::string& v : a.values) {
          auto values = required(*type);
          values.emplace_back(a.name, v);
          expect_sound(*type, values, a.name + " = " + v);
        }
        continue;
      }
      // A joint's limits may be expressions: at the defaults they are numbers.
      for (std::optional<double> limit : {a.min_si, a.max_si}) {
        if (!limit) continue;
        auto values = required(*type);
        std::erase_if(values, [&](const auto& v) { return v.first == a.name; });
        values.emplace_back(a.name, file_value(a, *limit));
        expect_sound(*type, values, fmt::format("{} at a limit", a.name));
        ++configurations;
      }
    }
  }
  EXPECT_GT(configurations, 100u);
}

TEST_F(LibraryProperty, EveryTypeIsSoundInRandomConfigurationsWithinItsLimits) {
  // Every numeric attribute at once, uniform within its limits (an open end: up to three times the
  // default or the min); joints stay at their defaults (the kinematics tests move them). A draw
  // the type's own rules refuse (a wall's openings past its end) is drawn again: 24 sound
  // configurations of every type, each checked in full.
  options.whole_library = true;  // (the templates of every type, not only those it uses: none)
  Workcell lib = must_compile("objects: []\n");
  options.whole_library = false;
  options.library = std::make_shared<const std::vector<ObjectType>>(lib.types);  // loaded once
  std::mt19937 rng(20261126);
  for (const ObjectType* type : standard_types(lib)) {
    int sound = 0;
    for (int draw = 0; draw < 4000 && sound < 24; ++draw) {
      std::vector<std::pair<std::string, std::string>> values;
      for (const AttributeDef& a : type->attributes) {
        if (a.joint || a.type == AttrType::Enum || a.type == AttrType::Boolean || a.type == AttrType::String) continue;
        // A derived attribute (its default an expression over the others: gross_mass) keeps it.
        if (std::any_of(type->attributes.begin(), type->attributes.end(),
                        [&](const AttributeDef& b) { return a.default_value.text.find(b.name) != std::string::npos; }))
          continue;
        const double base = a.default_value.present ? std::abs(parse_number(a.default_value.text).value_or(1)) : 1;
        const double lo = a.min_si.value_or(0);
        const double hi = a.max_si.value_or(std::max(lo, 0.0) + 3 * std::max(base * file_unit_to_si(a.dim), 1.0));
        double v = std::uniform_real_distribution<double>(lo, hi)(rng);
        if (a.type == AttrType::Integer) v = std::clamp(std::round(v), std::ceil(lo), std::floor(hi));
        values.emplace_back(a.name, file_value(a, v));
      }
      sound += expect_sound(*type, values, fmt::format("random draw {}", draw));
    }
    EXPECT_EQ(sound, 24) << type->name << ": its rules refuse nearly every configuration within its limits";
  }
}

}  // namespace
}  // namespace sscs::testing
