// Fuzzes a vault file through load, compile, geometry and check (`sscs check`), against the
// standard library.
#include "check/check.h"
#include "fuzz_support.h"
#include "geometry/geometry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace sscs;
  static const auto library = fuzz::standard_library();
  fuzz::confine_to_scratch();
  Sources sources;
  Diagnostics diag;
  // Every return says its diagnostics as sscs prints them (placing a mark re-reads the file).
  const struct Said {
    const Sources& s;
    const Diagnostics& d;
    ~Said() { (void)d.format(s); }
  } said{sources, diag};
  uint32_t file = sources.add((fuzz::scratch() / "vault.yaml").string(), std::string(reinterpret_cast<const char*>(data), size));
  auto spec = load_vault(file, sources, diag);
  if (!spec || diag.has_errors()) return 0;
  CompileOptions options;
  options.library = library;
  auto wc = compile_vault(*spec, options, sources, diag);
  if (!wc) return 0;
  GeometryModel geometry = build_geometry(*wc, diag);
  if (diag.has_errors()) return 0;
  check(*wc, geometry);
  return 0;
}
