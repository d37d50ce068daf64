#!/usr/bin/env bash
# Runs one libFuzzer target for a bounded time from the project's seeds and the formats'
# dictionary; fails (printing the reproducer) when it finds a crash, a leak, a sanitizer report,
# an input slower than 20 s or one that needs more than 2.5 GB.
#   run.sh FUZZER_BINARY TARGET SECONDS WORK_DIR
# The corpus grows in WORK_DIR/corpus/TARGET between runs; reproducers land in WORK_DIR/crashes/.
# Reproduce one with: FUZZER_BINARY WORK_DIR/crashes/TARGET-crash-...
set -euo pipefail
binary=$1 target=$2 seconds=$3 work=$4
here=$(cd "$(dirname "$0")" && pwd)
python=/usr/bin/python3; [[ -x $python ]] || python=python3
mkdir -p "$work/corpus/$target" "$work/crashes" "$work/seeds"
rm -rf "$work/seeds/$target"
"$python" "$here/seeds.py" "$target" "$work/seeds/$target" --dict "$work/sscs.dict"
cd "$work"
# Leaks of system libraries are suppressed (as in tools/test.sh); a slow mesh stops at 5 s.
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$here/../sanitize/lsan.supp:print_suppressions=0}
export ASAN_OPTIONS=${ASAN_OPTIONS:-max_allocation_size_mb=4096}
export SSCS_MAX_MESH_READ_SECONDS=${SSCS_MAX_MESH_READ_SECONDS:-5}
log="$work/$target.log"
status=0
"$binary" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2560 -malloc_limit_mb=2560 \
  -dict="$work/sscs.dict" -artifact_prefix="$work/crashes/$target-" -print_final_stats=1 \
  "$work/corpus/$target" "$work/seeds/$target" >"$log" 2>&1 || status=$?
grep -E "^#[0-9]+ *DONE|stat::number_of_executed_units|cov:" "$log" | tail -n 2 || true
if ((status != 0)); then
  grep -E "ERROR|SUMMARY|==[0-9]+==|Test unit written|artifact_prefix|Base64" "$log" | head -n 30 || true
  echo "fuzz $target: found a failing input (log: $log)" >&2
  exit 1
fi
echo "fuzz $target: clean for ${seconds}s"
