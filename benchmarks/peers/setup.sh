#!/usr/bin/env bash
# Sets up the peers for benchmarks/peers/run.py and sim_peers.py in one venv:
#
#   - Siconos 4.4: Debian's python3-siconos, built for Debian's /usr/bin/python3
#     (3.11) and its numpy 1.24 — so the venv is made from /usr/bin/python3 with
#     --system-site-packages and numpy stays below 2 in it;
#   - Drake (PyPI `drake`), MuJoCo (PyPI `mujoco`), PyBullet (PyPI `pybullet`);
#   - lcpsim itself, built from this checkout as an abi3 wheel (maturin), which
#     imports with numpy 1.24 (DESIGN §6).
#
# Idempotent; needs root for apt-get (as on these machines). Not part of the
# test suite or CI. Usage:  bash benchmarks/peers/setup.sh  [then]  bash benchmarks/peers/run.sh
#
# Environment: PEERS_VENV (default benchmarks/peers/.venv), SKIP_APT=1,
# SKIP_WHEEL=1 (reuse the installed lcpsim), DRAKE_SPEC / MUJOCO_SPEC /
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
constraints="$here/.constraints.txt"
"$py" -c "import numpy; print(f'numpy=={numpy.__version__}')" >"$constraints"
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
    echo "==> lcpsim wheel from $root (maturin, release, abi3)"
    "$py" -m pip install --quiet "maturin>=1.16,<2"
    wheels="$(mktemp -d)"
    (cd "$root" && "$venv/bin/maturin" build --release --quiet --out "$wheels")
    "$py" -m pip install --quiet --force-reinstall --no-deps "$wheels"/lcpsim-*.whl
    # lcpsim's own dependencies, without upgrading numpy.
    "$py" -m pip install --quiet -c "$constraints" scipy h5py
    rm -rf "$wheels"
fi

echo "==> versions"
"$py" - <<'PY'
import importlib, sys
print("python", sys.version.split()[0])
for name in ["numpy", "siconos", "pydrake", "mujoco", "pybullet", "lcpsim"]:
    try:
        m = importlib.import_module(name)
        print(name, getattr(m, "__version__", "?"))
    except Exception as e:  # report, don't fail: run.py skips a missing peer
        print(name, "NOT AVAILABLE:", e)
PY
