#!/usr/bin/env bash
# ctest's web.reports: makes every HTML report and glTF file of scenarios/ (make-reports.sh),
# validates the glTF files with the Khronos validator, and drives the reports in chromium.
# Usage: run.sh SSCS SOURCE_DIR OUT_DIR
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
if [[ ! -d $here/node_modules/puppeteer-core || ! -d $here/node_modules/gltf-validator ]]; then
  echo "tests/web/node_modules is missing: tools/test.sh installs it (cd tests/web && npm ci)" >&2
  exit 1
fi
"$here/make-reports.sh" "$1" "$2" "$3"
node "$here/validate-gltf.mjs" "$3"/*.glb
SSCS_WEB_OUT=$3 node --test --test-concurrency=1 --test-reporter=spec "$here/reports.test.mjs"
