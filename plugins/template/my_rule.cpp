// A new functional constraint and a new object type for sscs, in one file. Copy this folder,
// rename the class and the type, change the check and the attributes, then:
//   cmake -S . -B build -DCMAKE_PREFIX_PATH=/where/sscs/is/installed && cmake --build build
//   sscs check my-vault.yaml --plugins build/plugins
// and use them in a vault:
//   objects:
//     - {name: C1, type: my_crate, location: [1, 0, 0], width: 1.2 m}
//   constraints:
//     - {name: racks low enough, plugin: {class: max_value, attributes: [Rack_1.height], args: {max: 3}}}
#include <sscs/plugin.hpp>  // the C ABI plus a C++ layer: exceptions never reach sscs

#include <string>

namespace {

// The check: every attribute at most args.max. Values come in the file units of their
// dimension (m, deg, kg, s); the margin is how far from violation, positive when satisfied.
sscs::plugin::Result max_value(const sscs::plugin::Inputs& in) {
  const double max = in.number("max");  // the args ({max: 3}); missing: the check's status is `error`
  double margin = max - in.value(0);
  size_t worst = 0;
  for (size_t i = 1; i < in.count; ++i)
    if (max - in.value(i) < margin) margin = max - in.value(i), worst = i;
  return sscs::plugin::Result::judge(margin >= 0, margin, in.unit(worst),
                                     in.ref(worst) + " = " + std::to_string(in.value(worst)) + ", at most " + std::to_string(max));
}

}  // namespace

// Registration: the class name a vault uses, a description (shown by `sscs types --plugins`),
// how many attributes it takes (at least, at most), and the check.
SSCS_PLUGIN(registry) {
  registry.constraint("max_value", "every attribute at most args.max", 1, SIZE_MAX, max_value);

  // An object type, declared as a type-library file would be: attributes {name, type, default,
  // min, max, enum values, description} (empty: none; an empty default makes it required), and
  // geometry whose numbers are expressions over the attributes, in the object's frame (z up,
  // origin on the floor).
  sscs::plugin::ObjectType crate;
  crate.name = "my_crate";
  crate.description = "a wooden crate on the floor";
  crate.color = "#B08850";
  crate.attributes = {
      {"width", "length", "1.0", "0.2", "3", "", "along x"},
      {"depth", "length", "0.8", "0.2", "3", "", "along y"},
      {"height", "length", "0.6", "0.1", "2", "", ""},
      {"gross_mass", "mass", "", "0", "", "", "required: every crate says what it weighs"},
  };
  crate.geometry = {sscs::plugin::Shape::box("width", "depth", "height").at("0", "0", "height/2")};
  crate.frames = {{"top", {"0", "0", "height"}}};
  registry.object_type(crate);
}
