#!/usr/bin/env bash
# Runs every fuzz target for a fixed time (see docs/reliability.md):
#   bash scripts/fuzz.sh [SECONDS per target, default 180] [TARGET ...]
# TARGETs (default: all, one after another): lcp_solvers, world, shapes — Rust
# (fuzz/, cargo-fuzz on nightly), one process each (-jobs=1 workers), corpus in
# fuzz/corpus/TARGET, crashes in fuzz/artifacts/TARGET; readers — the Python
# readers (scripts/fuzz_readers.py), findings in fuzz/artifacts/readers;
# fclib — the FCLib reader alone, findings in fuzz/artifacts/fclib.
# Prints the inputs run, corpus size and findings per target; exits non-zero
# if any target found something.
set -uo pipefail
secs="${1:-180}"
shift || true
targets=("$@")
[ "${#targets[@]}" -gt 0 ] || targets=(lcp_solvers world shapes readers fclib)
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
status=0
readers() {  # OUT [READERS]
  PYTHONPATH="$root/python${PYTHONPATH:+:$PYTHONPATH}" python3 scripts/fuzz_readers.py \
    --seconds "$secs" --out "$1" ${2:+--readers "$2"} || status=1
}
for target in "${targets[@]}"; do
  case "$target" in
    lcp_solvers | world | shapes)
      command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz --locked
      mkdir -p "fuzz/corpus/$target" "fuzz/artifacts/$target"
      log="fuzz/artifacts/$target/run.log"
      cargo +nightly fuzz run --fuzz-dir fuzz "$target" "fuzz/corpus/$target" -- \
        -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -max_len=512 -print_final_stats=1 >"$log" 2>&1
      rc=$?
      crashes=$(find "fuzz/artifacts/$target" -name 'crash-*' -o -name 'timeout-*' -o -name 'oom-*' | wc -l)
      runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1)
      echo "$target: ${secs}s, ${runs:-?} runs, corpus $(ls "fuzz/corpus/$target" | wc -l) inputs, findings $crashes (exit $rc; log $log)"
      { [ "$rc" -ne 0 ] || [ "$crashes" -ne 0 ]; } && status=1
      ;;
    readers) readers fuzz/artifacts/readers ;;
    fclib) readers fuzz/artifacts/fclib read_fclib ;;
    *) echo "fuzz.sh: unknown target $target (lcp_solvers, world, readers, fclib)" >&2; exit 2 ;;
  esac
done
exit "$status"
