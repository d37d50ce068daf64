#pragma once
/// What a plugin's constraint class decides, as the compiled model keeps it: the plugin runtime
/// (plugin/) produces it, check reads it, and neither the model nor check sees dlopen.
#include <string>

namespace sscs {

/// What a check gave: an evaluation (pass/fail, margin) or an error message.
struct PluginOutcome {
  bool ok = false;  ///< false: the check failed to evaluate (status `error`)
  bool pass = false;
  double margin = 0;
  std::string unit, message;
};

}  // namespace sscs
