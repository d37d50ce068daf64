// Deliberately broken plugins for the e2e tests, one shared object each (BROKEN_KIND selects):
// wrong_abi, no_register, throws, nan, crash.
#include <sscs/plugin.hpp>

#include <cmath>
#include <stdexcept>

#if defined(BROKEN_wrong_abi)
extern "C" SSCS_PLUGIN_EXPORT uint32_t sscs_plugin_abi_version(void) { return 99; }
extern "C" SSCS_PLUGIN_EXPORT int sscs_plugin_register(const sscs_host*) { return 0; }
#elif defined(BROKEN_no_register)
extern "C" SSCS_PLUGIN_EXPORT uint32_t sscs_plugin_abi_version(void) { return SSCS_PLUGIN_ABI_VERSION; }
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
