// Fuzzes expressions and quantities: the expression parser and evaluator, the margin split, unit
// literals, and an `expr` constraint and an attribute expression in a vault checked end to end.
#include <cmath>

#include "check/check.h"
#include "core/expr.h"
#include "core/units.h"
#include "fuzz_support.h"
#include "geometry/geometry.h"

namespace {

// The text as a YAML double-quoted scalar: every byte that YAML would read otherwise escaped.
std::string quoted(std::string_view text) {
  std::string out = "\"";
  for (unsigned char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20 || c >= 0x7f) {
      char buf[8];
      snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    } else {
      out += static_cast<char>(c);
    }
  }
  return out + "\"";
}

void check_vault(const std::string& text) {
  using namespace sscs;
  static const auto library = fuzz::standard_library();
  Sources sources;
  Diagnostics diag;
  uint32_t file = sources.add((fuzz::scratch() / "vault.yaml").string(), text);
  auto spec = load_vault(file, sources, diag);
  if (!spec || diag.has_errors()) return;
  CompileOptions options;
  options.library = library;
  auto wc = compile_vault(*spec, options, sources, diag);
  if (wc) check(*wc, build_geometry(*wc, diag));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace sscs;
  std::string_view text(reinterpret_cast<const char*>(data), size);
  Expression::Error error;
  if (auto e = Expression::parse(text, &error)) {
    for (double v : {0.0, 1.5, -1e300, std::nan("")}) {
      std::vector<double> values(e->names().size(), v);
      (void)e->evaluate(values.data());
    }
  }
  (void)split_for_margin(text);
  std::string unknown;
  (void)parse_quantity(text, &unknown);
  (void)parse_number(text);
  const std::string q = quoted(text);
  check_vault("sscs: 1\nvault: E\nparameters: {p: 2 m}\nobjects:\n"
              "  - {type: room, name: R, length: 10 m, width: 8 m, height: 4 m}\n"
              "  - {type: drum, name: D, parent: R, location: [1 m, 1 m, 0 m]}\n"
              "constraints:\n  - {kind: expr, expr: " + q + "}\n");
  check_vault("sscs: 1\nvault: E\nparameters: {p: 2 m}\nobjects:\n"
              "  - {type: room, name: R, length: 10 m, width: 8 m, height: " + q + "}\n");
  return 0;
}
