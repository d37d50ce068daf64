#!/usr/bin/env bash
# Configures (once) and builds sscs incrementally in build/. Used by run-demo.sh and test.sh.
# SSCS_BUILD_DIR overrides the folder; CI=true turns warnings into errors.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SSCS_BUILD_DIR:-$root/build}
werror=OFF
[[ ${CI:-} == true ]] && werror=ON
# Ninja: the objects of the tests and tools compile while the library's do (Make waits for each
# target's dependencies first, which left one of CI's two cores idle). A folder configured for
# another generator is configured again.
if [[ -f $build/CMakeCache.txt ]] && ! grep -q "CMAKE_GENERATOR:INTERNAL=Ninja" "$build/CMakeCache.txt"; then
  rm -rf "$build/CMakeCache.txt" "$build/CMakeFiles"
fi
# A unity build (the sources compiled eight to a batch) takes a clean clone's build from 5 to 3
# minutes: the headers' templates are compiled once per batch, not once per file. A folder that is
# already configured keeps its choice (`cmake build -DCMAKE_UNITY_BUILD=OFF` recompiles only the
# file you edit); docs/testing.md says what a batch asks of the sources.
if [[ ! -f $build/CMakeCache.txt ]] || ! grep -q "SSCS_WERROR:BOOL=$werror" "$build/CMakeCache.txt"; then
  cmake -G Ninja -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSSCS_WERROR=$werror \
    -DCMAKE_UNITY_BUILD=ON >/dev/null
fi
cmake --build "$build" -j"$(nproc)" >"$build/build.log" 2>&1 || { tail -n 60 "$build/build.log"; echo "build failed (full log: $build/build.log)" >&2; exit 1; }
