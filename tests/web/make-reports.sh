#!/usr/bin/env bash
# Makes the HTML reports and glTF files the web tests look at, from the project's scenarios:
# every check, run and sweep report a user gets from scenarios/ (tests/web/reports.test.mjs).
# Usage: make-reports.sh SSCS SOURCE_DIR OUT_DIR
set -euo pipefail
sscs=$1
src=$2
out=$3
rm -rf "$out"
mkdir -p "$out"
cd "$src"
q=(--quiet)
# Checks: exit 1 means failing constraints (the demo fails 4 on purpose), not a broken report.
check() { local name=$1; shift; "$sscs" check "$@" --format json --out "$out/$name.json" --html "$out/$name.html" "${q[@]}" >/dev/null || [[ $? == 1 ]]; }
check demo scenarios/demo/demo.yaml
check drum-store scenarios/drum-store/store.yaml
check ci-main scenarios/ci-example/main/store.yaml
check ci-branch scenarios/ci-example/branch/store.yaml --baseline "$out/ci-main.json"
check two-vaults scenarios/demo/demo.yaml scenarios/ci-example/main/store.yaml
# Devices that fail to reach targets: each failed row has its closest pose (the "why can't it reach" picture).
check devices scenarios/devices/devices.yaml
# Runs: a run folder each, its HTML, and the animated glTF sscs export makes of it.
run() {
  local name=$1 scenario=$2
  "$sscs" simulate "$scenario" --out "$out/$name" --no-frames --html "$out/$name.html" "${q[@]}" >/dev/null || [[ $? == 1 ]]
  "$sscs" export "$out/$name" --out "$out/$name.glb" "${q[@]}"
}
run arm-loads-drum scenarios/drum-transfer/arm-loads-drum.yaml
run gantry-loads-drum scenarios/drum-transfer/gantry-loads-drum.yaml
run collision scenarios/drum-transfer/collision.yaml
run store-drum scenarios/drum-store/store-drum.yaml
# Campaigns (their Gantt chart, queue and utilization): a gantry setting three drums on pads, and one
# whose unreachable job fails alone (its device out, its next job never started).
run campaign-slots tests/data/campaigns/slots.yaml
run campaign-failure tests/data/campaigns/failure.yaml
# A run written only as a bundle: its report and glTF are those of the same run in a folder.
"$sscs" simulate scenarios/drum-transfer/arm-loads-drum.yaml --bundle "$out/arm-bundle.zip" --no-frames "${q[@]}" >/dev/null
"$sscs" report "$out/arm-bundle.zip" --html "$out/arm-bundle.html" "${q[@]}"
"$sscs" export "$out/arm-bundle.zip" --out "$out/arm-bundle.glb" "${q[@]}"
cmp "$out/arm-bundle.glb" "$out/arm-loads-drum.glb" || { echo "the bundle's glTF differs from the folder's" >&2; exit 1; }
# A sweep, and a report made afterwards from a check's JSON.
"$sscs" sweep scenarios/sweeps/aisle-rows.yaml --out "$out/aisle-rows" --html "$out/aisle-rows.html" "${q[@]}" >/dev/null || [[ $? == 1 ]]
# A sweep over alternative files (its parameter is words: an axis of categories) with simulations.
"$sscs" sweep scenarios/sweeps/arm-vs-gantry.yaml --out "$out/arm-vs-gantry" --html "$out/arm-vs-gantry.html" "${q[@]}" >/dev/null || [[ $? == 1 ]]
"$sscs" report "$out/demo.json" --html "$out/demo-from-json.html" "${q[@]}"
# A sweep variant's report: its vault with the variant's values (the report's "set"), five rows.
"$sscs" report "$out/aisle-rows/54-aisle=2m-rows=5/report.json" --html "$out/variant-from-json.html" "${q[@]}"
# Still models: the vaults as sscs export writes them.
"$sscs" export scenarios/demo/demo.yaml --out "$out/demo.glb" "${q[@]}"
"$sscs" export scenarios/drum-store/store.yaml --out "$out/drum-store.glb" "${q[@]}"
# Pages made of strings written to break them (reports.test.mjs, "hostile"): names with HTML
# comment and script openers, a right-to-left override, a 2,000-character name, a --set value
# with `<!`, a run folder named `run<!--x`, and a sweep whose results.json (an artifact anyone
# can edit) names a variant folder `javascript:window.x=99`.
check hostile tests/web/hostile/hostile.yaml --set 'gap=1 <!0'
"$sscs" simulate scenarios/drum-transfer/arm-loads-drum.yaml --out "$out/run<!--x" --no-frames --html "$out/hostile-run.html" "${q[@]}" >/dev/null
cp -r "$out/aisle-rows" "$out/hostile-sweep"
python3 - "$out/hostile-sweep/results.json" <<'PY'
import json, sys
path = sys.argv[1]
results = json.load(open(path))
results["variants"][0]["folder"] = "javascript:window.x=99"
results["variants"][1]["folder"] = "../../etc"
json.dump(results, open(path, "w"))
PY
"$sscs" report "$out/hostile-sweep" --html "$out/hostile-sweep.html" "${q[@]}"
ls "$out"/*.html "$out"/*.glb >/dev/null
