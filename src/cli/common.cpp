#include <filesystem>
#include <algorithm>
#include "cli/subcommands.h"

namespace sscs::cli {

/// Writes the diagnostics to stderr, warnings then errors; true when there were errors (the
/// command then stops, having written nothing).
bool report_diagnostics(const Diagnostics& diag, const Sources& sources, const Common& common) {
  if (!diag.has_errors() && diag.warnings().empty()) return false;
  std::cerr << diag.format(sources, common.color_for(stderr));
  return diag.has_errors();
}


/// "WIDTHxHEIGHT" within 16..8192; false (with the message printed) otherwise.
bool parse_size(const std::string& text, int& width, int& height) {
  char tail;
  if (std::sscanf(text.c_str(), "%dx%d%c", &width, &height, &tail) == 2 && width >= 16 && height >= 16 && width <= 8192 &&
      height <= 8192)
    return true;
  std::cerr << fmt::format("sscs: error: --size expects WIDTHxHEIGHT between 16 and 8192, found '{}'\n", text);
  return false;
}


/// "x,y,z" -> a vector; false when it is not three numbers.
bool parse_vec3(const std::string& text, Eigen::Vector3d& v) {
  double x, y, z;
  char tail;
  if (std::sscanf(text.c_str(), "%lf,%lf,%lf%c", &x, &y, &z, &tail) != 3) return false;
  v = {x, y, z};
  return v.allFinite();
}


volatile std::sig_atomic_t g_interrupted = 0;

namespace {
extern "C" void on_interrupt(int) { g_interrupted = 1; }
}  // namespace

InterruptGuard::InterruptGuard() {
  struct sigaction action = {};
  action.sa_handler = on_interrupt;
  sigaction(SIGINT, &action, &old_int_);
  sigaction(SIGTERM, &action, &old_term_);
}

InterruptGuard::~InterruptGuard() {
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
}

std::string html_target_refusal(const std::string& html, const std::vector<std::string>& outputs) {
  namespace fs = std::filesystem;
  if (html.empty()) return "";
  std::string ext = fs::path(html).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  // A page is written only to a .html file: never over a vault, a report, a run's log or a
  // folder (`--html vault.yaml` replaced the vault).
  if (ext != ".html" && ext != ".htm") return fmt::format("--html expects a .html file, found '{}'", html);
  std::error_code ec;
  if (fs::is_directory(html, ec)) return fmt::format("--html '{}' is a folder", html);
  const fs::path parent = fs::path(html).parent_path();
  if (!parent.empty() && !fs::is_directory(parent, ec)) return fmt::format("--html '{}': there is no folder '{}'", html, parent.string());
  const fs::path target = fs::weakly_canonical(html, ec);
  for (const std::string& out : outputs)
    if (!out.empty() && fs::weakly_canonical(out, ec) == target) return fmt::format("--html '{}' is also another output of this command", html);
  return "";
}

}  // namespace sscs::cli
