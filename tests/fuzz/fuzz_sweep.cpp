// Fuzzes a sweep file through load and variant expansion (`sscs sweep --dry-run`'s table).
#include "fuzz_support.h"
#include "load/sweep.h"
#include "sweep/variants.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace sscs;
  Sources sources;
  Diagnostics diag;
  // Every return says its diagnostics as sscs prints them (placing a mark re-reads the file).
  const struct Said {
    const Sources& s;
    const Diagnostics& d;
    ~Said() { (void)d.format(s); }
  } said{sources, diag};
  uint32_t file = sources.add((fuzz::scratch() / "sweep.yaml").string(), std::string(reinterpret_cast<const char*>(data), size));
  auto spec = load_sweep(file, sources, diag);
  if (!spec || diag.has_errors()) return 0;
  expand_variants(*spec, diag);
  return 0;
}
