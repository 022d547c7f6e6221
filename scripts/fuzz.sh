#!/usr/bin/env bash
# Runs every fuzz target for a fixed time (issue 15; see docs/reliability.md):
#   bash scripts/fuzz.sh [SECONDS per target, default 180]
# Rust targets (fuzz/, cargo-fuzz on nightly): lcp_solvers, world — one
# process each (-jobs=1 workers), corpus in fuzz/corpus/TARGET, crashes in
# fuzz/artifacts/TARGET. The Python readers: scripts/fuzz_readers.py, findings
# in fuzz/artifacts/readers. Prints the corpus size and findings per target;
# exits non-zero if any target found something.
set -uo pipefail
secs="${1:-180}"
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz --locked
status=0
for target in lcp_solvers world; do
  mkdir -p "fuzz/corpus/$target" "fuzz/artifacts/$target"
  log="fuzz/artifacts/$target/run.log"
  cargo +nightly fuzz run --fuzz-dir fuzz "$target" "fuzz/corpus/$target" -- \
    -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -max_len=512 -print_final_stats=1 >"$log" 2>&1
  rc=$?
  crashes=$(find "fuzz/artifacts/$target" -name 'crash-*' -o -name 'timeout-*' -o -name 'oom-*' | wc -l)
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1)
  echo "$target: ${secs}s, ${runs:-?} runs, corpus $(ls "fuzz/corpus/$target" | wc -l) inputs, findings $crashes (exit $rc; log $log)"
  [ "$rc" -ne 0 ] || [ "$crashes" -ne 0 ] && status=1
done
PYTHONPATH="$root/python${PYTHONPATH:+:$PYTHONPATH}" python3 scripts/fuzz_readers.py --seconds "$secs" --out fuzz/artifacts/readers || status=1
exit "$status"
