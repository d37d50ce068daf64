#include "pipeline/live_check.h"

#include <filesystem>
#include <set>

#include <fmt/format.h>

#include "check/check.h"
#include "model/shape.h"
#include "pipeline/html_report.h"
#include "pipeline/prepare.h"

namespace sscs {

LiveCheck live_check(const std::string& path, const CompileOptions& options, LibraryCache& library) {
  namespace fs = std::filesystem;
  LiveCheck out;
  Sources sources;
  Diagnostics diag;
  PreparedVault vault = prepare_vault(path, options, sources, diag, {.visuals = true, .contacts = nullptr}, library);
  std::set<std::string> files;
  auto read = [&](const std::string& file) {
    std::error_code ec;
    if (file.empty() || file.front() == '<' || !fs::is_regular_file(file, ec)) return;  // (texts of no file: a plugin's types)
    files.insert(fs::absolute(file).lexically_normal().string());
  };
  read(path);
  for (uint32_t f = 1; f < sources.size(); ++f) read(sources.path(f));
  if (vault.wc)
    for (const ObjectGeometry& g : vault.geometry.objects)
      for (const auto* shapes : {&g.shapes, &g.visual_shapes})
        for (const Shape& s : *shapes)
          if (s.mesh) read(s.mesh->path);
  out.files.assign(files.begin(), files.end());
  if (diag.has_errors() || !vault.wc) {
    out.errors = diag.format(sources);
    const size_t n = diag.errors().size();
    out.summary = fmt::format("{} input error{}", n, n == 1 ? "" : "s");
    return out;
  }
  CheckOptions check_options;
  check_options.describe_passes = true;
  std::vector<VaultReport> reports;
  reports.push_back({&*vault.wc, path, check(*vault.wc, vault.geometry, check_options), std::nullopt, diag.warnings(), options.overrides});
  const CheckReport& r = reports.back().report;
  out.summary = fmt::format("{} passed, {} failed, {} warnings", r.passed, r.failed, r.warnings);
  out.page = check_html(reports, sources, {&vault.geometry});
  out.compiled = true;
  return out;
}

}  // namespace sscs
