#include "plugin/plugins.h"

#include <dlfcn.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>

#include "core/names.h"

namespace sscs {

namespace {

/// Registration context: the plugin being loaded.
struct Loading {
  PluginSet* set;
  std::vector<ConstraintClass>* classes;
  std::string path;
  std::vector<std::string> errors;
};

// The message a crash inside a check prints: prepared before the call, written by the signal
// handler with write(2) (async-signal-safe), then _exit(3).
char g_crash_message[1024];
size_t g_crash_length = 0;

extern "C" void on_crash(int) {
  ssize_t ignored = ::write(STDERR_FILENO, g_crash_message, g_crash_length);
  (void)ignored;
  ::_exit(3);
}

}  // namespace

PluginSet::PluginSet() = default;
PluginSet::~PluginSet() = default;  // handles stay open: their functions may be referenced until exit

void PluginSet::load_folder(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw PluginError(fmt::format("plugin folder '{}' does not exist", dir));
  if (!folders_.insert(fs::weakly_canonical(dir, ec).string()).second) return;  // loaded already
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file() && e.path().extension() == ".so") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  for (const std::string& f : files) load(f);
}

void PluginSet::load(const std::string& path) {
  void* h = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!h) throw PluginError(fmt::format("plugin {}: cannot load it: {}", path, ::dlerror()));
  handles_.push_back(h);
  auto version = reinterpret_cast<sscs_plugin_abi_version_fn>(::dlsym(h, "sscs_plugin_abi_version"));
  auto reg = reinterpret_cast<sscs_plugin_register_fn>(::dlsym(h, "sscs_plugin_register"));
  if (!version || !reg)
    throw PluginError(fmt::format("plugin {}: missing the entry symbol {} (build it with sscs/plugin.hpp's SSCS_PLUGIN, "
                                  "or export it as extern \"C\")",
                                  path, !version ? "sscs_plugin_abi_version" : "sscs_plugin_register"));
  if (uint32_t v = version(); v != SSCS_PLUGIN_ABI_VERSION)
    throw PluginError(fmt::format("plugin {}: built for plugin ABI version {}, this sscs has version {}; rebuild it "
                                  "against this sscs's sscs/plugin.h",
                                  path, v, SSCS_PLUGIN_ABI_VERSION));
  std::vector<ConstraintClass> added;
  Loading ctx{this, &added, path, {}};
  sscs_host host{};
  host.abi_version = SSCS_PLUGIN_ABI_VERSION;
  host.size = sizeof(sscs_host);
  host.context = &ctx;
  host.add_constraint_class = [](void* context, const sscs_constraint_class* c) -> int {
    auto& l = *static_cast<Loading*>(context);
    std::string name = c && c->name ? c->name : "";
    if (!is_valid_name(name)) {
      l.errors.push_back(fmt::format("constraint class name '{}' is not a valid name", name));
      return 1;
    }
    if (!c->check) {
      l.errors.push_back(fmt::format("constraint class '{}' has no check function", name));
      return 1;
    }
    auto same = [&](const ConstraintClass& k) { return k.name == name; };
    if (const ConstraintClass* other = l.set->find(name)) {
      l.errors.push_back(fmt::format("constraint class '{}' is already defined by plugin {}", name, other->plugin));
      return 1;
    }
    if (std::any_of(l.classes->begin(), l.classes->end(), same)) {
      l.errors.push_back(fmt::format("constraint class '{}' is registered twice", name));
      return 1;
    }
    l.classes->push_back({name, c->description ? c->description : "", l.path, c->min_values, c->max_values, c->check, c->user});
    return 0;
  };
  host.error = [](void* context, const char* message) {
    static_cast<Loading*>(context)->errors.push_back(message ? message : "(no message)");
  };
  int status = reg(&host);
  if (status != 0 || !ctx.errors.empty())
    throw PluginError(fmt::format("plugin {}: registration failed: {}", path,
                                  ctx.errors.empty() ? fmt::format("sscs_plugin_register returned {}", status)
                                                     : fmt::format("{}", fmt::join(ctx.errors, "; "))));
  classes_.insert(classes_.end(), added.begin(), added.end());
}

const ConstraintClass* PluginSet::find(const std::string& name) const {
  for (const ConstraintClass& c : classes_)
    if (c.name == name) return &c;
  return nullptr;
}

PluginOutcome PluginSet::check(const ConstraintClass& cls, const std::string& constraint, const std::vector<sscs_value>& values,
                               const std::string& args_json) const {
  std::string msg = fmt::format("sscs: error: plugin {} crashed in the check of constraint '{}' (class {})\n", cls.plugin,
                                constraint, cls.name);
  g_crash_length = std::min(msg.size(), sizeof g_crash_message);
  std::memcpy(g_crash_message, msg.data(), g_crash_length);
  struct sigaction crash = {}, old[4];
  crash.sa_handler = on_crash;
  const int signals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL};
  for (int i = 0; i < 4; ++i) sigaction(signals[i], &crash, &old[i]);
  sscs_check_result r{};
  int status = cls.check(cls.user, values.data(), values.size(), args_json.c_str(), &r);
  for (int i = 0; i < 4; ++i) sigaction(signals[i], &old[i], nullptr);
  r.unit[sizeof r.unit - 1] = '\0';
  r.message[sizeof r.message - 1] = '\0';
  PluginOutcome out;
  out.message = r.message;
  out.unit = r.unit;
  if (status != 0) {
    out.message = fmt::format("plugin {} could not evaluate it: {}", cls.plugin, out.message.empty() ? "(no message)" : out.message);
    return out;
  }
  if (!std::isfinite(r.margin)) {
    out.message = fmt::format("plugin {} returned a margin that is not a number ({})", cls.plugin, r.margin);
    return out;
  }
  out.ok = true;
  out.pass = r.pass != 0;
  out.margin = r.margin;
  return out;
}

}  // namespace sscs
