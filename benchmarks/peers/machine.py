"""The machine and the versions a peers' run reports."""

from __future__ import annotations

import os
import platform
import subprocess
import sys
from pathlib import Path
from typing import Any

from common import ROOT


def loadavg() -> str:
    try:
        return " ".join(Path("/proc/loadavg").read_text().split()[:3])
    except OSError:
        return "?"


def machine() -> dict[str, Any]:
    cpu = "?"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem = "?"
    try:
        kb = int(Path("/proc/meminfo").read_text().split()[1])
        mem = f"{kb / 2**20:.1f} GiB"
    except (OSError, ValueError, IndexError):
        pass
    return {
        "cpu": cpu,
        "cores": os.cpu_count(),
        "cores_usable": len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None,
        "memory": mem,
        "kernel": platform.release(),
        "os": platform.platform(),
    }


def versions() -> dict[str, str]:
    from importlib.metadata import PackageNotFoundError, version

    v: dict[str, str] = {"python": platform.python_version()}
    for dist in ("numpy", "lcpsim", "drake", "mujoco", "pybullet"):
        try:
            v[dist] = version(dist)
        except PackageNotFoundError:
            v[dist] = "not installed"
    try:
        v["siconos"] = subprocess.run(
            ["dpkg-query", "-W", "-f=${Version}", "python3-siconos"], capture_output=True, text=True, check=False
        ).stdout.strip() or "?"
    except OSError:
        v["siconos"] = "?"
    rev = Path(sys.prefix) / "lcpsim-revision.txt"
    if rev.exists():
        v["lcpsim_revision"] = rev.read_text().strip()
    else:
        try:
            v["lcpsim_revision"] = subprocess.run(
                ["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=False
            ).stdout.strip() + " (work tree)"
        except OSError:
            v["lcpsim_revision"] = "?"
    return v
