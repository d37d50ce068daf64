// sscs plugins in ordinary C++: a thin, header-only layer over the C ABI of plugin.h. Exceptions
// thrown by a check or by registration are caught here and become errors; none reach sscs.
//
//   #include <sscs/plugin.hpp>
//   static sscs::plugin::Result my_rule(const sscs::plugin::Inputs& in) {
//     double h = in.value(0);
//     return sscs::plugin::Result::judge(h <= 3, 3 - h, "m", "height " + std::to_string(h) + " m <= 3 m");
//   }
//   SSCS_PLUGIN(registry) { registry.constraint("my_rule", "heights at most 3 m", 1, 1, my_rule); }
//
// An object type, declared as a type-library file would be (sizes are expressions):
//   sscs::plugin::ObjectType t{"newdrum", "object", "a drum", "#3A6EA5"};
//   t.attributes = {{"diameter", "length", "0.6", "0.1", "2"}, {"height", "length", "0.9", "0.1"}};
//   t.geometry = {sscs::plugin::Shape::cylinder("diameter/2", "height").at("0", "0", "height/2")};
//   registry.object_type(t);
#pragma once

#include <sscs/plugin.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <functional>
#include <optional>
#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

namespace sscs::plugin {

/// The participating attributes and the args (a JSON text) of one check.
struct Inputs {
  const sscs_value* values;
  size_t count;
  const char* args_json;
  double value(size_t i) const {
    if (i >= count) throw std::out_of_range("attribute " + std::to_string(i) + " of " + std::to_string(count));
    return values[i].value;
  }
  std::string ref(size_t i) const { return i < count ? values[i].ref : ""; }
  std::string unit(size_t i) const { return i < count ? values[i].unit : ""; }
  std::string args() const { return args_json ? args_json : "{}"; }
  /// The number args.KEY (args are a flat mapping in the vault: {k_eff: 0.6}), or `fallback`;
  /// without a fallback a missing number throws (the constraint's status becomes `error`).
  double number(const std::string& key, std::optional<double> fallback = std::nullopt) const {
    std::smatch m;
    const std::string json = args();
    if (std::regex_search(json, m, std::regex("\"" + key + "\"\\s*:\\s*(-?[0-9.]+(?:[eE][-+]?[0-9]+)?)")))
      return std::stod(m[1]);
    if (fallback) return *fallback;
    throw std::runtime_error("args need a number '" + key + "'");
  }
};

struct Result {
  bool pass = false;
  double margin = NAN;
  std::string unit, message;
  static Result judge(bool pass, double margin, std::string unit, std::string message) {
    return {pass, margin, std::move(unit), std::move(message)};
  }
};

using Check = std::function<Result(const Inputs&)>;

namespace detail {
inline void copy(char* dst, size_t n, const std::string& s) {
  std::strncpy(dst, s.c_str(), n - 1);
  dst[n - 1] = '\0';
}
inline std::vector<Check>& checks() {
  static std::vector<Check> all;
  return all;
}
inline int trampoline(void* user, const sscs_value* values, size_t count, const char* args, sscs_check_result* out) {
  try {
    Result r = checks()[reinterpret_cast<size_t>(user)](Inputs{values, count, args});
    out->pass = r.pass ? 1 : 0;
    out->margin = r.margin;
    copy(out->unit, sizeof out->unit, r.unit);
    copy(out->message, sizeof out->message, r.message);
    return 0;
  } catch (const std::exception& e) {
    copy(out->message, sizeof out->message, std::string("the check threw: ") + e.what());
  } catch (...) {
    copy(out->message, sizeof out->message, "the check threw something that is not a std::exception");
  }
  return 1;
}
}  // namespace detail

/// An attribute of an object type; empty strings are absent (an empty default: required).
struct Attribute {
  std::string name, type, default_value, min, max, values, description;
  Attribute(std::string name, std::string type, std::string default_value = "", std::string min = "", std::string max = "",
            std::string values = "", std::string description = "")
      : name(std::move(name)), type(std::move(type)), default_value(std::move(default_value)), min(std::move(min)),
        max(std::move(max)), values(std::move(values)), description(std::move(description)) {}
};

/// A shape of an object type's geometry; every number is an expression over the attributes.
struct Shape {
  std::string kind;
  std::string size[3], radius, length, file, scale[3], xyz[3], rpy[3];
  static Shape box(std::string x, std::string y, std::string z) {
    Shape s;
    s.kind = "box";
    s.size[0] = std::move(x), s.size[1] = std::move(y), s.size[2] = std::move(z);
    return s;
  }
  static Shape cylinder(std::string radius, std::string length) {
    Shape s;
    s.kind = "cylinder";
    s.radius = std::move(radius), s.length = std::move(length);
    return s;
  }
  static Shape sphere(std::string radius) {
    Shape s;
    s.kind = "sphere";
    s.radius = std::move(radius);
    return s;
  }
  /// A mesh file relative to the plugin's folder.
  static Shape mesh(std::string file) {
    Shape s;
    s.kind = "mesh";
    s.file = std::move(file);
    return s;
  }
  Shape& at(std::string x, std::string y, std::string z) {
    xyz[0] = std::move(x), xyz[1] = std::move(y), xyz[2] = std::move(z);
    return *this;
  }
  /// Roll, pitch, yaw in degrees.
  Shape& rotated(std::string r, std::string p, std::string y) {
    rpy[0] = std::move(r), rpy[1] = std::move(p), rpy[2] = std::move(y);
    return *this;
  }
  Shape& scaled(std::string x, std::string y, std::string z) {
    scale[0] = std::move(x), scale[1] = std::move(y), scale[2] = std::move(z);
    return *this;
  }
};

/// A named frame: position (and roll, pitch, yaw in degrees) as expressions.
struct Frame {
  std::string name;
  std::array<std::string, 3> xyz, rpy;
  Frame(std::string name, std::array<std::string, 3> xyz, std::array<std::string, 3> rpy = {})
      : name(std::move(name)), xyz(std::move(xyz)), rpy(std::move(rpy)) {}
};

/// An object type, the report's object sub-class: name, super-class, attributes, geometry.
struct ObjectType {
  std::string name, extends, description, color;
  /// What an instance weighs (kg) for the physics: a number or an expression over the attributes
  /// ("22 + fill_mass"); empty: a `mass` attribute, else an estimate from the bounds.
  std::string mass;
  std::vector<Attribute> attributes;
  std::vector<Shape> geometry;
  std::vector<Frame> frames;
};

/// sscs refused a class or type and has been told why; registration stops.
struct Rejected : std::runtime_error {
  using std::runtime_error::runtime_error;
};

namespace detail {
inline const char* c_str(const std::string& s) { return s.empty() ? nullptr : s.c_str(); }
}  // namespace detail

/// What a plugin's registration function is given.
class Registry {
 public:
  explicit Registry(const sscs_host* host) : host_(host) {}
  /// Registers a constraint class; throws when sscs rejects it.
  void constraint(const std::string& name, const std::string& description, size_t min_values, size_t max_values, Check check) {
    detail::checks().push_back(std::move(check));
    sscs_constraint_class cls{name.c_str(), description.c_str(), min_values, max_values, &detail::trampoline,
                              reinterpret_cast<void*>(detail::checks().size() - 1)};
    if (host_->add_constraint_class(host_->context, &cls) != 0)
      throw Rejected("sscs rejected constraint class '" + name + "'");
  }

  /// Registers an object type; throws when sscs rejects it.
  void object_type(const ObjectType& t) {
    using detail::c_str;
    if (host_->size < offsetof(sscs_host, add_object_type) + sizeof host_->add_object_type)
      throw std::runtime_error("this sscs does not accept object types from plugins");
    std::vector<sscs_attribute> attrs;
    for (const Attribute& a : t.attributes)
      attrs.push_back({c_str(a.name), c_str(a.type), c_str(a.default_value), c_str(a.min), c_str(a.max), c_str(a.values),
                       c_str(a.description)});
    std::vector<sscs_shape> shapes;
    for (const Shape& g : t.geometry)
      shapes.push_back({c_str(g.kind),
                        {c_str(g.size[0]), c_str(g.size[1]), c_str(g.size[2])},
                        c_str(g.radius),
                        c_str(g.length),
                        c_str(g.file),
                        {c_str(g.scale[0]), c_str(g.scale[1]), c_str(g.scale[2])},
                        {c_str(g.xyz[0]), c_str(g.xyz[1]), c_str(g.xyz[2])},
                        {c_str(g.rpy[0]), c_str(g.rpy[1]), c_str(g.rpy[2])}});
    std::vector<sscs_frame> frames;
    for (const Frame& f : t.frames)
      frames.push_back({c_str(f.name), {c_str(f.xyz[0]), c_str(f.xyz[1]), c_str(f.xyz[2])},
                        {c_str(f.rpy[0]), c_str(f.rpy[1]), c_str(f.rpy[2])}});
    sscs_object_type ct{c_str(t.name), c_str(t.extends), c_str(t.description), c_str(t.color), attrs.data(), attrs.size(),
                        shapes.data(), shapes.size(), frames.data(), frames.size()};
    if (host_->add_object_type(host_->context, &ct) != 0) throw Rejected("sscs rejected object type '" + t.name + "'");
    if (!t.mass.empty()) {
      if (host_->size < offsetof(sscs_host, set_object_type_mass) + sizeof host_->set_object_type_mass)
        throw std::runtime_error("this sscs does not accept the masses of object types from plugins (it is older than this header)");
      if (host_->set_object_type_mass(host_->context, t.name.c_str(), t.mass.c_str()) != 0)
        throw Rejected("sscs rejected the mass of object type '" + t.name + "'");
    }
  }

 private:
  const sscs_host* host_;
};

}  // namespace sscs::plugin

/// Defines the plugin's two entry points; the body registers its classes through `registry`.
#define SSCS_PLUGIN(registry)                                                              \
  static void sscs_plugin_body(sscs::plugin::Registry& registry);                          \
  extern "C" SSCS_PLUGIN_EXPORT uint32_t sscs_plugin_abi_version(void) {                   \
    return SSCS_PLUGIN_ABI_VERSION;                                                        \
  }                                                                                        \
  extern "C" SSCS_PLUGIN_EXPORT int sscs_plugin_register(const sscs_host* host) {          \
    try {                                                                                  \
      sscs::plugin::Registry r(host);                                                      \
      sscs_plugin_body(r);                                                                 \
      return 0;                                                                            \
    } catch (const sscs::plugin::Rejected&) {                                              \
      /* sscs has the reason already */                                                    \
    } catch (const std::exception& e) {                                                    \
      host->error(host->context, e.what());                                                \
    } catch (...) {                                                                        \
      host->error(host->context, "registration threw");                                    \
    }                                                                                      \
    return 1;                                                                              \
  }                                                                                        \
  static void sscs_plugin_body(sscs::plugin::Registry& registry)
