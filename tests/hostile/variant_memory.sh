#!/bin/bash
# --variant-memory (issue 18): a variant that needs more memory than its limit is recorded as an
# error naming the limit; the other variants and the sweep go on.
set -u
sscs=$1 root=$2
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$sscs" sweep "$root/tests/data/hostile/memory_sweep.yaml" --out "$out/sw" --variant-memory 0.3 >/dev/null 2>"$out/err"
code=$?
[ $code = 1 ] || { echo "FAIL: exit $code, expected 1 (a variant in error)"; cat "$out/err"; exit 1; }
grep -q '^0,0-n=10,10,pass,' "$out/sw/results.csv" || { echo "FAIL: the small variant did not pass"; cat "$out/sw/results.csv"; exit 1; }
grep -q '^1,1-n=300000,300000,error,.*ran out of memory: a variant may take 0.3 GB (--variant-memory)' "$out/sw/results.csv" ||
  { echo "FAIL: the large variant is not an error naming the limit"; cat "$out/sw/results.csv"; exit 1; }
echo "variant memory: the large variant ran out of its 0.3 GB alone, the sweep went on"
