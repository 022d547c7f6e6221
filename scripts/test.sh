#!/usr/bin/env bash
# The whole test suite in one command, on a fresh machine with Rust and Python:
# installs the Python package (release build) with its test extras, then runs
# the Rust tests and the Python tests. Exits non-zero if anything fails.
set -euo pipefail
cd "$(dirname "$0")/.."

PYTHON="${PYTHON:-python3}"

if ! command -v cargo >/dev/null 2>&1; then
    echo "scripts/test.sh: error: cargo not found on PATH; install Rust >= 1.80 (https://rustup.rs) first" >&2
    exit 2
fi

echo "==> building and installing lcpsim with its test extras"
"$PYTHON" -m pip install --quiet --upgrade "pip>=23" "maturin>=1.16,<2"
"$PYTHON" -m pip install --quiet -e ".[test]"

# Both suites always run, so one failing does not hide the other's results.
echo "==> Rust tests (cargo test --workspace --exclude lcpsim-py)"
rust_rc=0
cargo test --workspace --exclude lcpsim-py || rust_rc=$?

echo "==> Python tests (pytest)"
py_rc=0
"$PYTHON" -m pytest tests "$@" || py_rc=$?

if [ "$rust_rc" -ne 0 ] || [ "$py_rc" -ne 0 ]; then
    echo "scripts/test.sh: FAILED (cargo test exit $rust_rc, pytest exit $py_rc)" >&2
    # pytest's own code when cargo passed (so .ci/run can tell 5 = no tests), else 1.
    [ "$rust_rc" -eq 0 ] && exit "$py_rc"
    exit 1
fi
echo "scripts/test.sh: all tests passed"
