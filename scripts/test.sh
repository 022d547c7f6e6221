#!/usr/bin/env bash
# The whole test suite in one command, on a fresh machine with Rust and Python:
# installs the Python package (release build) with its test extras, then runs
# the Rust tests and the Python tests. Exits non-zero if anything fails.
#
#   bash scripts/test.sh [PYTEST ARGS...]           the whole suite (README's and CI's command)
#   bash scripts/test.sh --quick [PYTEST ARGS...]   the inner loop: no reinstall (unless lcpsim does not
#                                                   import), the Rust unit tests and the fast integration
#                                                   tests listed below, pytest without the tests marked slow
set -euo pipefail
cd "$(dirname "$0")/.."

PYTHON="${PYTHON:-python3}"

quick=0
if [ "${1:-}" = "--quick" ]; then
    quick=1
    shift
fi

# The quick tier's Rust integration tests (crates/*/tests/NAME.rs): fast to build and run, covering
# Lemke and its certificate, PGS / Newton-FB, cone scaling, the contact layout and generators, and the
# simulator's basic scenes, islands and retakes. A name whose file is gone is skipped with a warning.
QUICK_RUST_TESTS=(
    lemke certify pgs_newton scaling contact_layout generate
    cube_on_slope resting pushed stack islands retake
)

if ! command -v cargo >/dev/null 2>&1; then
    echo "scripts/test.sh: error: cargo not found on PATH; install Rust >= 1.80 (https://rustup.rs) first" >&2
    exit 2
fi

if [ "$quick" -eq 0 ] || ! "$PYTHON" -c "import lcpsim" >/dev/null 2>&1; then
    echo "==> building and installing lcpsim with its test extras"
    "$PYTHON" -m pip install --quiet --upgrade "pip>=23" "maturin>=1.16,<2"
    "$PYTHON" -m pip install --quiet -e ".[test]"
fi

rust_args=(--workspace --exclude lcpsim-py)
py_args=(tests)
if [ "$quick" -eq 1 ]; then
    rust_args+=(--lib)
    for name in "${QUICK_RUST_TESTS[@]}"; do
        if compgen -G "crates/*/tests/$name.rs" >/dev/null; then
            rust_args+=(--test "$name")
        else
            echo "scripts/test.sh: warning: quick Rust test '$name' not found under crates/*/tests; skipped" >&2
        fi
    done
    py_args+=(-m "not slow")
fi

# Both suites always run, so one failing does not hide the other's results.
echo "==> Rust tests (cargo test ${rust_args[*]})"
rust_rc=0
cargo test "${rust_args[@]}" || rust_rc=$?

echo "==> Python tests (pytest ${py_args[*]} $*)"
py_rc=0
"$PYTHON" -m pytest "${py_args[@]}" "$@" || py_rc=$?

if [ "$rust_rc" -ne 0 ] || [ "$py_rc" -ne 0 ]; then
    echo "scripts/test.sh: FAILED (cargo test exit $rust_rc, pytest exit $py_rc)" >&2
    # pytest's own code when cargo passed (so .ci/run can tell 5 = no tests), else 1.
    [ "$rust_rc" -eq 0 ] && exit "$py_rc"
    exit 1
fi
echo "scripts/test.sh: all tests passed"
