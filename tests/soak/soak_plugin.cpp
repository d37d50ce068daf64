// The soak test's plugin (tests/soak/run.sh): a constraint class `soak` whose check misbehaves for
// some variants of a 500-variant sweep, chosen by the variant's index k (the drum's height is
// 1 m + k mm): k % 50 == 7 crashes (SIGSEGV), k % 125 == 23 never returns (a timeout: 4 of them, each costing the 3-s timeout on every pass), k % 97 == 5
// allocates memory until the variant's limit stops it; every other variant passes when k is even
// and fails when it is odd.
#include <sscs/plugin.hpp>

#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

SSCS_PLUGIN(registry) {
  registry.constraint("soak", "misbehaves for some variants", 1, 1, [](const sscs::plugin::Inputs& in) -> sscs::plugin::Result {
    const long k = std::lround((in.value(0) - 1.0) * 1000.0);
    if (k % 50 == 7) {
      volatile int* nowhere = nullptr;
      *nowhere = static_cast<int>(k);
    }
    if (k % 125 == 23)
      for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));
    if (k % 97 == 5) {
      std::vector<std::vector<char>> hog;
      for (;;) hog.emplace_back(size_t(64) << 20, char(1));  // 64 MB at a time, touched
    }
    return sscs::plugin::Result::judge(k % 2 == 0, k % 2 == 0 ? 1.0 : -1.0, "m", "soak k = " + std::to_string(k));
  });
}
