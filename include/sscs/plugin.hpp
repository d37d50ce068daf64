// sscs plugins in ordinary C++: a thin, header-only layer over the C ABI of plugin.h. Exceptions
// thrown by a check or by registration are caught here and become errors; none reach sscs.
//
//   #include <sscs/plugin.hpp>
//   static sscs::plugin::Result my_rule(const sscs::plugin::Inputs& in) {
//     double h = in.value(0);
//     return sscs::plugin::Result::judge(h <= 3, 3 - h, "m", "height " + std::to_string(h) + " m <= 3 m");
//   }
//   SSCS_PLUGIN(registry) { registry.constraint("my_rule", "heights at most 3 m", 1, 1, my_rule); }
#pragma once

#include <sscs/plugin.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace sscs::plugin {

/// The participating attributes and the args (a JSON text) of one check.
struct Inputs {
  const sscs_value* values;
  size_t count;
  const char* args_json;
  double value(size_t i) const {
    if (i >= count) throw std::out_of_range("attribute " + std::to_string(i) + " of " + std::to_string(count));
    return values[i].value;
  }
  std::string ref(size_t i) const { return i < count ? values[i].ref : ""; }
  std::string unit(size_t i) const { return i < count ? values[i].unit : ""; }
  std::string args() const { return args_json ? args_json : "{}"; }
};

struct Result {
  bool pass = false;
  double margin = NAN;
  std::string unit, message;
  static Result judge(bool pass, double margin, std::string unit, std::string message) {
    return {pass, margin, std::move(unit), std::move(message)};
  }
};

using Check = std::function<Result(const Inputs&)>;

namespace detail {
inline void copy(char* dst, size_t n, const std::string& s) {
  std::strncpy(dst, s.c_str(), n - 1);
  dst[n - 1] = '\0';
}
inline std::vector<Check>& checks() {
  static std::vector<Check> all;
  return all;
}
inline int trampoline(void* user, const sscs_value* values, size_t count, const char* args, sscs_check_result* out) {
  try {
    Result r = checks()[reinterpret_cast<size_t>(user)](Inputs{values, count, args});
    out->pass = r.pass ? 1 : 0;
    out->margin = r.margin;
    copy(out->unit, sizeof out->unit, r.unit);
    copy(out->message, sizeof out->message, r.message);
    return 0;
  } catch (const std::exception& e) {
    copy(out->message, sizeof out->message, std::string("the check threw: ") + e.what());
  } catch (...) {
    copy(out->message, sizeof out->message, "the check threw something that is not a std::exception");
  }
  return 1;
}
}  // namespace detail

/// What a plugin's registration function is given.
class Registry {
 public:
  explicit Registry(const sscs_host* host) : host_(host) {}
  /// Registers a constraint class; throws when sscs rejects it.
  void constraint(const std::string& name, const std::string& description, size_t min_values, size_t max_values, Check check) {
    detail::checks().push_back(std::move(check));
    sscs_constraint_class cls{name.c_str(), description.c_str(), min_values, max_values, &detail::trampoline,
                              reinterpret_cast<void*>(detail::checks().size() - 1)};
    if (host_->add_constraint_class(host_->context, &cls) != 0)
      throw std::runtime_error("sscs rejected constraint class '" + name + "'");
  }

 private:
  const sscs_host* host_;
};

}  // namespace sscs::plugin

/// Defines the plugin's two entry points; the body registers its classes through `registry`.
#define SSCS_PLUGIN(registry)                                                              \
  static void sscs_plugin_body(sscs::plugin::Registry& registry);                          \
  extern "C" SSCS_PLUGIN_EXPORT uint32_t sscs_plugin_abi_version(void) {                   \
    return SSCS_PLUGIN_ABI_VERSION;                                                        \
  }                                                                                        \
  extern "C" SSCS_PLUGIN_EXPORT int sscs_plugin_register(const sscs_host* host) {          \
    try {                                                                                  \
      sscs::plugin::Registry r(host);                                                      \
      sscs_plugin_body(r);                                                                 \
      return 0;                                                                            \
    } catch (const std::exception& e) {                                                    \
      host->error(host->context, e.what());                                                \
    } catch (...) {                                                                        \
      host->error(host->context, "registration threw");                                    \
    }                                                                                      \
    return 1;                                                                              \
  }                                                                                        \
  static void sscs_plugin_body(sscs::plugin::Registry& registry)
