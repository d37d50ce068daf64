// Fuzzes a type file through the library loader (inheritance, devices, URDF and meshes it names),
// then places each type it defines in a vault and builds its geometry.
#include "check/check.h"
#include "fuzz_support.h"
#include "geometry/geometry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace sscs;
  std::filesystem::create_directories(fuzz::scratch() / "lib" / "types");
  fuzz::write_scratch("lib/types/fuzzed.yaml", data, size);
  Sources sources;
  Diagnostics diag;
  // Every return says its diagnostics as sscs prints them (placing a mark re-reads the file).
  const struct Said {
    const Sources& s;
    const Diagnostics& d;
    ~Said() { (void)d.format(s); }
  } said{sources, diag};
  std::vector<ObjectType> types = load_library({{(fuzz::scratch() / "lib").string(), SourceMark{}}}, sources, diag);
  if (diag.has_errors()) return 0;
  auto library = std::make_shared<const std::vector<ObjectType>>(std::move(types));
  for (const ObjectType& type : *library) {
    if (type.path.find("fuzzed.yaml") == std::string::npos) continue;
    uint32_t file = sources.add((fuzz::scratch() / "vault.yaml").string(),
                                "sscs: 1\nvault: F\nobjects:\n  - {type: \"" + type.name + "\", name: X}\n");
    auto spec = load_vault(file, sources, diag);
    if (!spec) continue;
    CompileOptions options;
    options.library = library;
    auto wc = compile_vault(*spec, options, sources, diag);
    if (wc) check(*wc, build_geometry(*wc, diag));
  }
  return 0;
}
