#!/usr/bin/env bash
# Sets up the peers for benchmarks/peers/run.py and sim_peers.py in one venv:
#
#   - Siconos 4.4: Debian's python3-siconos, built for Debian's /usr/bin/python3
#     (3.11) and its numpy 1.24 — so the venv is made from /usr/bin/python3 with
#     --system-site-packages and numpy stays below 2 in it;
#   - Drake (PyPI `drake`), MuJoCo (PyPI `mujoco`), PyBullet (PyPI `pybullet`);
#   - lcpsim itself, built from this checkout as an abi3 wheel (maturin), which
#     imports with numpy 1.24 as well as numpy 2 (abi3-py310);
#   - benchmarks/rapier_bench (Rapier, and the broad-phase comparison), a Rust
#     crate outside lcpsim's workspace, built with cargo.
#
# Idempotent; needs root for apt-get (as on these machines). Not part of the
# test suite or CI. Usage:  bash benchmarks/peers/setup.sh  &&  benchmarks/peers/.venv/bin/python benchmarks/peers/run.py
#
# Environment: PEERS_VENV (default benchmarks/peers/.venv), SKIP_APT=1,
# SKIP_WHEEL=1 (reuse the installed lcpsim), SKIP_RAPIER=1 (don't build
# benchmarks/rapier_bench, the Rapier peer of many_bodies.py), DRAKE_SPEC / MUJOCO_SPEC /
# PYBULLET_SPEC (pip requirement strings, default unpinned).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
venv="${PEERS_VENV:-$here/.venv}"

if [ "${SKIP_APT:-0}" != 1 ]; then
    echo "==> apt-get: python3-siconos, python3-venv"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq python3-siconos python3-venv python3-pip >/dev/null
fi
/usr/bin/python3 -c "import siconos.numerics as sn; print('siconos', sn.__file__)"

if [ ! -x "$venv/bin/python" ]; then
    echo "==> venv $venv (Debian python3, system site packages)"
    /usr/bin/python3 -m venv --system-site-packages "$venv"
fi
py="$venv/bin/python"
# Keep Debian's numpy 1.x: Siconos' extension modules are built against it.
# Pinned to the system Python's numpy (not the venv's: a numpy 2 once pulled
# into the venv by a peer would otherwise pin itself and break Siconos), and
# any other numpy in the venv removed so that the system one is used.
constraints="$here/.constraints.txt"
/usr/bin/python3 -c "import numpy; print(f'numpy=={numpy.__version__}')" >"$constraints"
if ! "$py" -m pip freeze --local 2>/dev/null | grep -qxF "$(cat "$constraints")"; then
    "$py" -m pip uninstall --quiet -y numpy >/dev/null 2>&1 || true
fi
echo "==> pip: drake, mujoco, pybullet (numpy pinned to $(cat "$constraints"))"
"$py" -m pip install --quiet --upgrade pip
"$py" -m pip install --quiet -c "$constraints" \
    "${DRAKE_SPEC:-drake}" "${MUJOCO_SPEC:-mujoco}" "${PYBULLET_SPEC:-pybullet}" || {
    echo "setup.sh: warning: a peer failed to install; trying them one by one" >&2
    for spec in "${DRAKE_SPEC:-drake}" "${MUJOCO_SPEC:-mujoco}" "${PYBULLET_SPEC:-pybullet}"; do
        "$py" -m pip install --quiet -c "$constraints" "$spec" || echo "setup.sh: warning: $spec not installed" >&2
    done
}

if [ "${SKIP_WHEEL:-0}" != 1 ]; then
    # Built from the committed HEAD (git archive), so the benchmark measures a
    # commit and not whatever is half-edited in the work tree; LCPSIM_WORKTREE=1
    # builds the work tree as it is. Dependencies are reused from $root/target.
    wheels="$(mktemp -d)"
    if [ "${LCPSIM_WORKTREE:-0}" = 1 ]; then
        src="$root"; rev="$(git -C "$root" rev-parse --short HEAD)+worktree"
    else
        src="$(mktemp -d)"; rev="$(git -C "$root" rev-parse --short HEAD)"
        git -C "$root" archive HEAD | tar -x -C "$src"
    fi
    echo "==> lcpsim wheel from $src ($rev; maturin, release, abi3)"
    "$py" -m pip install --quiet "maturin>=1.16,<2"
    (cd "$src" && CARGO_TARGET_DIR="$root/target" "$venv/bin/maturin" build --release --quiet --out "$wheels")
    "$py" -m pip install --quiet --force-reinstall --no-deps "$wheels"/lcpsim-*.whl
    # lcpsim's own dependencies, without upgrading numpy.
    "$py" -m pip install --quiet -c "$constraints" scipy h5py
    echo "$rev" >"$venv/lcpsim-revision.txt"
    rm -rf "$wheels"
    [ "$src" = "$root" ] || rm -rf "$src"
fi

if [ "${SKIP_RAPIER:-0}" != 1 ]; then
    # Rapier for many_bodies.py: its own crate and workspace (not lcpsim's), its own target dir.
    echo "==> rapier-bench (cargo, release)"
    bench="$root/benchmarks/rapier_bench"
    CARGO_TARGET_DIR="$bench/target" cargo build --quiet --release --manifest-path "$bench/Cargo.toml" \
        || echo "setup.sh: warning: rapier-bench not built (many_bodies.py skips Rapier)" >&2
fi

echo "==> versions"
"$py" - <<'PY'
import importlib, sys
print("python", sys.version.split()[0])
from importlib.metadata import version
for module, dist in [("numpy", "numpy"), ("siconos.numerics", None), ("pydrake.solvers", "drake"),
                     ("mujoco", "mujoco"), ("pybullet", "pybullet"), ("lcpsim", "lcpsim")]:
    try:
        importlib.import_module(module)
        print(module, version(dist) if dist else "(Debian python3-siconos)")
    except Exception as e:  # report, don't fail: run.py skips a missing peer
        print(module, "NOT AVAILABLE:", e)
PY
