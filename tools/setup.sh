#!/usr/bin/env bash
# Installs the Debian (bookworm) packages sscs builds and tests with. Idempotent: it asks apt only
# for the packages that are missing, and runs `apt-get update` only when something is missing.
# This is the one place the package list lives; run-demo.sh and test.sh call it.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git python3 python3-jsonschema python3-yaml python3-matplotlib jq
  libyaml-cpp-dev libeigen3-dev libode-dev libfcl-dev libassimp-dev libzip-dev libssl-dev libfmt-dev
  libgtest-dev libgmock-dev libosmesa6-dev libgl-dev libpng-dev libjpeg-dev libfreetype-dev fonts-dejavu-core libcli11-dev nlohmann-json3-dev libmuparser-dev
  libbenchmark-dev liburdfdom-dev libtinyxml-dev  # tinyxml: SRDF files (urdfdom uses it too)
  libcpp-httplib-dev  # sscs serve's HTTP server
  liborocos-kdl-dev  # the IK benchmark's peer solver only; sscs does not link it
  clang libclang-rt-14-dev  # the sanitizer and libFuzzer build of tools/test.sh (stage 2)
  libjs-three  # three.js r111, built into the HTML reports
  nodejs chromium-headless-shell  # test-only: the glTF validator, the reports in a real browser (tests/web)
  neovim  # test-only: an editor's own LSP client talking to sscs lsp (tests/lsp)
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

# npm comes with NodeSource's nodejs where that is installed; Debian packages it apart.
command -v npm >/dev/null 2>&1 || missing+=(npm)

if ((${#missing[@]} == 0)); then
  exit 0
fi

if [[ $(id -u) -ne 0 ]]; then
  echo "setup.sh: missing packages: ${missing[*]}" >&2
  echo "setup.sh: run as root (or install them with sudo apt-get install)" >&2
  exit 1
fi

echo "setup.sh: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
