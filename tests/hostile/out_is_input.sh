#!/bin/bash
# check --out naming one of the check's inputs is refused (exit 2) and the input stays as it was.
set -u
sscs=$(realpath "$1") root=$(realpath "$2")
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cp "$root/tests/data/hostile/out_is_input.yaml" "$dir/vault.yaml"
cd "$dir"
"$sscs" check vault.yaml --format json --out ./vault.yaml >/dev/null 2>err
code=$?
[ $code = 2 ] || { echo "FAIL: exit $code, expected 2"; cat err; exit 1; }
grep -q "is an input of this check" err || { echo "FAIL: no reason given"; cat err; exit 1; }
cmp -s vault.yaml "$root/tests/data/hostile/out_is_input.yaml" || { echo "FAIL: the input was changed"; exit 1; }
echo "check --out over its own vault: refused, the vault untouched" # (and --html below)
# The same for --html (the report's page over the vault).
"$sscs" check vault.yaml --html vault.yaml >/dev/null 2>err
code=$?
[ $code = 2 ] || { echo "FAIL: --html: exit $code, expected 2"; cat err; exit 1; }
grep -q "\-\-html expects a .html file, found 'vault.yaml'" err || { echo "FAIL: --html: no reason given"; cat err; exit 1; }
cmp -s vault.yaml "$root/tests/data/hostile/out_is_input.yaml" || { echo "FAIL: --html: the input was changed"; exit 1; }
echo "check --html over its own vault: refused, the vault untouched"
# --html and --out naming one file: refused before anything is written.
"$sscs" check vault.yaml --format json --out r.html --html r.html >/dev/null 2>err
code=$?
[ $code = 2 ] || { echo "FAIL: --out = --html: exit $code, expected 2"; cat err; exit 1; }
grep -q "is also another output of this command" err || { echo "FAIL: --out = --html: no reason given"; cat err; exit 1; }
[ ! -e r.html ] || { echo "FAIL: --out = --html: r.html written"; exit 1; }
echo "check --out and --html naming one file: refused, nothing written"
