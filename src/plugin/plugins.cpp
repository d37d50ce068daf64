#include "plugin/plugins.h"

#include <dlfcn.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>
#include <yaml-cpp/emitter.h>
#include <yaml-cpp/emittermanip.h>

#include "core/diagnostics.h"
#include "core/names.h"
#include "load/load.h"

namespace sscs {

namespace {

/// Registration context: the plugin being loaded.
struct Loading {
  PluginSet* set;
  std::vector<ConstraintClass>* classes;
  std::vector<PluginType>* types;
  std::string path;
  std::vector<std::string> errors;
};

std::string str(const char* s) { return s ? s : ""; }

/// Emits `key: [a, b, c]` for the non-null of three expressions (absent ones are 0, or `fill`).
void triple(YAML::Emitter& out, const char* key, const char* const (&v)[3], const char* fill = "0") {
  if (!v[0] && !v[1] && !v[2]) return;
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const char* x : v) out << (x ? x : fill);
  out << YAML::EndSeq;
}

/// The type-library file a declared type amounts to. The type loader then reads it with the
/// same rules as any type file; problems come back as its diagnostics.
std::string type_yaml(const sscs_object_type& t, const std::string& plugin) {
  YAML::Emitter out;
  out << YAML::Comment(fmt::format("object type declared by plugin {}", plugin));
  out << YAML::BeginMap;
  out << YAML::Key << "sscs" << YAML::Value << 1;
  out << YAML::Key << "type" << YAML::Value << str(t.name);
  if (t.extends) out << YAML::Key << "extends" << YAML::Value << t.extends;
  if (t.description) out << YAML::Key << "description" << YAML::Value << t.description;
  if (t.color) out << YAML::Key << "color" << YAML::Value << YAML::DoubleQuoted << t.color;
  if (t.attribute_count) {
    out << YAML::Key << "attributes" << YAML::Value << YAML::BeginMap;
    for (size_t i = 0; i < t.attribute_count; ++i) {
      const sscs_attribute& a = t.attributes[i];
      out << YAML::Key << str(a.name) << YAML::Value << YAML::Flow << YAML::BeginMap;
      out << YAML::Key << "type" << YAML::Value << str(a.type);
      if (a.default_value) out << YAML::Key << "default" << YAML::Value << a.default_value;
      if (a.min) out << YAML::Key << "min" << YAML::Value << a.min;
      if (a.max) out << YAML::Key << "max" << YAML::Value << a.max;
      if (a.values) {
        out << YAML::Key << "values" << YAML::Value << YAML::BeginSeq;
        std::string all = a.values;
        for (size_t start = 0; start <= all.size();) {
          size_t comma = std::min(all.find(',', start), all.size());
          std::string v = all.substr(start, comma - start);
          v.erase(0, v.find_first_not_of(' '));
          v.erase(v.find_last_not_of(' ') + 1);
          out << v;
          start = comma + 1;
        }
        out << YAML::EndSeq;
      }
      if (a.description) out << YAML::Key << "description" << YAML::Value << a.description;
      out << YAML::EndMap;
    }
    out << YAML::EndMap;
  }
  if (t.frame_count) {
    out << YAML::Key << "frames" << YAML::Value << YAML::BeginMap;
    for (size_t i = 0; i < t.frame_count; ++i) {
      const sscs_frame& f = t.frames[i];
      out << YAML::Key << str(f.name) << YAML::Value << YAML::Flow << YAML::BeginMap;
      triple(out, "xyz", f.xyz);
      triple(out, "rpy", f.rpy);
      out << YAML::EndMap;
    }
    out << YAML::EndMap;
  }
  if (t.shape_count) {
    out << YAML::Key << "geometry" << YAML::Value << YAML::BeginSeq;
    for (size_t i = 0; i < t.shape_count; ++i) {
      const sscs_shape& g = t.geometry[i];
      out << YAML::Flow << YAML::BeginMap << YAML::Key << str(g.kind) << YAML::Value << YAML::BeginMap;
      triple(out, "size", g.size);
      if (g.radius) out << YAML::Key << "radius" << YAML::Value << g.radius;
      if (g.length) out << YAML::Key << "length" << YAML::Value << g.length;
      if (g.file) out << YAML::Key << "file" << YAML::Value << g.file;
      triple(out, "scale", g.scale, "1");
      triple(out, "xyz", g.xyz);
      triple(out, "rpy", g.rpy);
      out << YAML::EndMap << YAML::EndMap;
    }
    out << YAML::EndSeq;
  }
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

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
  std::vector<PluginType> added_types;
  Loading ctx{this, &added, &added_types, path, {}};
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
  host.add_object_type = [](void* context, const sscs_object_type* t) -> int {
    auto& l = *static_cast<Loading*>(context);
    std::string name = t && t->name ? t->name : "";
    if (!is_valid_name(name)) {
      l.errors.push_back(fmt::format("object type name '{}' is not a valid name", name));
      return 1;
    }
    auto same = [&](const PluginType& k) { return k.name == name; };
    auto other = std::find_if(l.set->types().begin(), l.set->types().end(), same);
    if (other != l.set->types().end()) {
      l.errors.push_back(fmt::format("object type '{}' is already defined by plugin {}", name, other->plugin));
      return 1;
    }
    if (std::any_of(l.types->begin(), l.types->end(), same)) {
      l.errors.push_back(fmt::format("object type '{}' is registered twice", name));
      return 1;
    }
    PluginType pt{name, l.path, fmt::format("{} (type {})", l.path, name), ""};
    try {
      pt.text = type_yaml(*t, l.path);
    } catch (const std::exception& e) {  // yaml-cpp refuses a key or value it cannot write
      l.errors.push_back(fmt::format("object type '{}' cannot be written as a type: {}", name, e.what()));
      return 1;
    }
    // Read it as the type loader reads type files, so a malformed declaration fails here, with
    // the plugin's name, instead of in some vault that uses it.
    Sources sources;
    Diagnostics diag;
    load_type(sources.add(pt.label, pt.text), l.path, sources, diag);
    if (diag.has_errors()) {
      std::string why = diag.format(sources);
      while (!why.empty() && why.back() == '\n') why.pop_back();
      l.errors.push_back(fmt::format("object type '{}' is not valid:\n{}", name, why));
      return 1;
    }
    l.types->push_back(std::move(pt));
    return 0;
  };
  host.set_object_type_mass = [](void* context, const char* type_name, const char* mass) -> int {
    auto& l = *static_cast<Loading*>(context);
    std::string name = type_name ? type_name : "";
    auto it = std::find_if(l.types->begin(), l.types->end(), [&](const PluginType& k) { return k.name == name; });
    if (it == l.types->end()) {
      l.errors.push_back(fmt::format("set_object_type_mass names '{}', which is no object type this plugin registered", name));
      return 1;
    }
    // The declaration gains `mass:`, read again as a type file is.
    YAML::Emitter out;
    out << YAML::BeginMap << YAML::Key << "mass" << YAML::Value << YAML::DoubleQuoted << (mass ? mass : "") << YAML::EndMap;
    std::string text = it->text + (it->text.empty() || it->text.back() == '\n' ? "" : "\n") + out.c_str() + "\n";
    Sources sources;
    Diagnostics diag;
    load_type(sources.add(it->label, text), l.path, sources, diag);
    if (diag.has_errors()) {
      std::string why = diag.format(sources);
      while (!why.empty() && why.back() == '\n') why.pop_back();
      l.errors.push_back(fmt::format("the mass of object type '{}' is not valid:\n{}", name, why));
      return 1;
    }
    it->text = std::move(text);
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
  types_.insert(types_.end(), added_types.begin(), added_types.end());
  files_.push_back(path);
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
