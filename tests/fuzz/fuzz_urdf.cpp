// Fuzzes URDF import: the input is `bot.urdf` of a device type `bot`, loaded as a library and
// placed in a vault whose geometry is built.
#include "check/check.h"
#include "fuzz_support.h"
#include "geometry/geometry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace sscs;
  static const bool type_in_place = [] {
    std::filesystem::create_directories(fuzz::scratch() / "urdf" / "types");
    std::ofstream(fuzz::scratch() / "urdf" / "types" / "bot.yaml") << "sscs: 1\ntype: bot\nkind: device\nurdf: ../bot.urdf\n";
    return true;
  }();
  (void)type_in_place;
  fuzz::write_scratch("urdf/bot.urdf", data, size);
  Sources sources;
  Diagnostics diag;
  auto types = load_library({{(fuzz::scratch() / "urdf").string(), SourceMark{}}}, sources, diag);
  if (diag.has_errors()) return 0;
  auto library = std::make_shared<const std::vector<ObjectType>>(std::move(types));
  uint32_t file = sources.add((fuzz::scratch() / "vault.yaml").string(),
                              "sscs: 1\nvault: U\nobjects:\n  - {type: bot, name: B}\n");
  auto spec = load_vault(file, sources, diag);
  if (!spec) return 0;
  CompileOptions options;
  options.library = library;
  auto wc = compile_vault(*spec, options, sources, diag);
  if (wc) check(*wc, build_geometry(*wc, diag));
  return 0;
}
