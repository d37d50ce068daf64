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

}  // namespace sscs::cli
