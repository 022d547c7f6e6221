"""``python/lcpsim/_core.pyi`` agrees with the compiled module: every name,
signature and class checked by ``mypy.stubtest`` (which imports the abi3
extension and compares it with the stub)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

import lcpsim

pytest.importorskip("mypy.stubtest", reason="mypy is in the test extras: pip install -e '.[test]'")

ALLOWLIST = Path(__file__).with_name("stubtest_allowlist.txt")


@pytest.mark.slow
def test_core_stub_matches_the_compiled_module(tmp_path):
    package_root = str(Path(lcpsim.__file__).parents[1])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([package_root, os.environ.get("PYTHONPATH", "")])}
    out = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "lcpsim._core", "--allowlist", str(ALLOWLIST)],
        capture_output=True, text=True, env=env, timeout=600, cwd=tmp_path,
    )
    assert out.returncode == 0, out.stdout + out.stderr
