// Fuzzes a scenario file through load, compile of its vault, planning and cameras (everything
// `sscs simulate` does before physics), and the same bytes as a campaign file through its loader. Its vault is scenarios/drum-transfer/cell.yaml, copied
// beside it as `cell.yaml`, so seeds from that folder reach the planner.
#include "load/campaign.h"
#include "pipeline/prepare.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace sscs;
  static const bool vault_in_place = [] {
    std::filesystem::copy_file(std::filesystem::path(SSCS_SOURCE_DIR) / "scenarios/drum-transfer/cell.yaml",
                               fuzz::scratch() / "cell.yaml", std::filesystem::copy_options::overwrite_existing);
    return true;
  }();
  (void)vault_in_place;
  std::string path = fuzz::write_scratch("scenario.yaml", data, size);
  CompileOptions options;
  options.library = fuzz::standard_library();
  PreparedScenario prepared;
  prepared.prepare(path, options);
  (void)prepared.diag.format(prepared.sources);  // as sscs prints them
  Sources sources;
  Diagnostics diag;
  // Every return says its diagnostics as sscs prints them (placing a mark re-reads the file).
  const struct Said {
    const Sources& s;
    const Diagnostics& d;
    ~Said() { (void)d.format(s); }
  } said{sources, diag};
  load_campaign(path, sources, diag);
  return 0;
}
