// A new functional constraint for sscs, in one file. Copy this folder, rename the class, change
// the check, then:
//   cmake -S . -B build -DCMAKE_PREFIX_PATH=/where/sscs/is/installed && cmake --build build
//   sscs check my-vault.yaml --plugins build/plugins
// and use it in a vault:
//   constraints:
//     - {name: racks low enough, plugin: {class: max_value, attributes: [Rack_1.height], args: {max: 3}}}
#include <sscs/plugin.hpp>  // the C ABI plus a C++ layer: exceptions never reach sscs

#include <regex>
#include <string>

namespace {

// The args arrive as JSON text ({"max": 3}); a regular expression is enough for one number.
double number_arg(const std::string& json, const std::string& key) {
  std::smatch m;
  if (!std::regex_search(json, m, std::regex("\"" + key + "\"\\s*:\\s*(-?[0-9.eE+-]+)")))
    throw std::runtime_error("args need a number '" + key + "'");  // becomes the constraint's `error`
  return std::stod(m[1]);
}

// The check: every attribute at most args.max. Values come in the file units of their
// dimension (m, deg, kg, s); the margin is how far from violation, positive when satisfied.
sscs::plugin::Result max_value(const sscs::plugin::Inputs& in) {
  const double max = number_arg(in.args(), "max");
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
}
