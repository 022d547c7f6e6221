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

echo "==> Rust tests (cargo test --workspace --exclude lcpsim-py)"
cargo test --workspace --exclude lcpsim-py

echo "==> Python tests (pytest)"
"$PYTHON" -m pytest tests "$@"
