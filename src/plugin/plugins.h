#pragma once
/// Plugins: shared objects in plugin folders, loaded with dlopen through the C ABI of
/// include/sscs/plugin.h. Loading a plugin runs its code: see docs/plugins.md for when sscs
/// does that (a vault alone never makes it).
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <sscs/plugin.h>

#include "core/plugin_outcome.h"

namespace sscs {

/// A plugin that cannot be used (missing entry symbol, wrong ABI version, dlopen error, a
/// duplicate class): the CLI's exit 3. The message names the plugin's path.
struct PluginError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ConstraintClass {
  std::string name, description, plugin;  ///< plugin: the shared object's path
  size_t min_values = 0, max_values = 0;
  sscs_check_fn check = nullptr;
  void* user = nullptr;
};

/// An object type a plugin declared, as the text of the type-library file it amounts to (the
/// type loader reads it like any other: one set of rules for library and plugin types).
struct PluginType {
  std::string name, plugin;  ///< plugin: the shared object's path
  std::string label;         ///< how errors name it: "PATH (type NAME)"
  std::string text;
};

class PluginSet {
 public:
  PluginSet();
  ~PluginSet();
  PluginSet(const PluginSet&) = delete;
  PluginSet& operator=(const PluginSet&) = delete;

  /// Loads every `*.so` in `dir` (sorted by name). Throws PluginError.
  void load_folder(const std::string& dir);
  /// Loads one shared object. Throws PluginError.
  void load(const std::string& path);

  const ConstraintClass* find(const std::string& name) const;
  const std::vector<ConstraintClass>& classes() const { return classes_; }
  const std::vector<PluginType>& types() const { return types_; }
  /// The shared objects loaded, in load order.
  const std::vector<std::string>& files() const { return files_; }

  /// Runs a class's check for constraint `constraint`. A check that reports an error, throws
  /// (caught by plugin.hpp), or returns a NaN margin gives ok = false. A check that crashes
  /// (SIGSEGV, SIGBUS, SIGFPE, SIGILL) ends sscs with a message naming the plugin and the
  /// constraint, and exit status 3.
  PluginOutcome check(const ConstraintClass& cls, const std::string& constraint, const std::vector<sscs_value>& values,
                      const std::string& args_json) const;

 private:
  std::vector<void*> handles_;
  std::set<std::string> folders_;
  std::vector<ConstraintClass> classes_;
  std::vector<PluginType> types_;
  std::vector<std::string> files_;
};

}  // namespace sscs
