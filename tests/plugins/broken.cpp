// Deliberately broken plugins for the e2e tests, one shared object each (BROKEN_KIND selects):
// wrong_abi, no_register, throws, nan, crash (constraint classes); dup_type, bad_type,
// unresolved_type (object types).
#include <sscs/plugin.hpp>

#include <cmath>
#include <stdexcept>

#if defined(BROKEN_wrong_abi)
extern "C" SSCS_PLUGIN_EXPORT uint32_t sscs_plugin_abi_version(void) { return 99; }
extern "C" SSCS_PLUGIN_EXPORT int sscs_plugin_register(const sscs_host*) { return 0; }
#elif defined(BROKEN_no_register)
extern "C" SSCS_PLUGIN_EXPORT uint32_t sscs_plugin_abi_version(void) { return SSCS_PLUGIN_ABI_VERSION; }
#elif defined(BROKEN_dup_type) || defined(BROKEN_bad_type) || defined(BROKEN_unresolved_type)
SSCS_PLUGIN(registry) {
  sscs::plugin::ObjectType t;
#if defined(BROKEN_dup_type)
  t.name = "drum";  // the standard library's
  t.attributes = {{"diameter", "length", "0.6"}};
#elif defined(BROKEN_bad_type)
  t.name = "bad_type";
  t.attributes = {{"diameter", "lenght", "0.6"}};
#else
  t.name = "unresolved_type";
  t.attributes = {{"diameter", "length", "0.6"}};
  t.geometry = {sscs::plugin::Shape::cylinder("diametre/2", "1")};
#endif
  registry.object_type(t);
}
#else
SSCS_PLUGIN(registry) {
  registry.constraint("broken", "a check that goes wrong", 1, SIZE_MAX, [](const sscs::plugin::Inputs& in) -> sscs::plugin::Result {
#if defined(BROKEN_throws)
    throw std::runtime_error("no table for " + in.ref(0));
#elif defined(BROKEN_nan)
    return sscs::plugin::Result::judge(true, NAN, "m", "fine, I think: " + in.ref(0));
#elif defined(BROKEN_crash)
    volatile int* nowhere = nullptr;
    *nowhere = static_cast<int>(in.value(0));
    return sscs::plugin::Result::judge(true, 0, "", "unreachable");
#endif
  });
}
#endif
