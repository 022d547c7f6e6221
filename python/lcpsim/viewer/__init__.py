"""A trajectory as one self-contained HTML page with a 3-D view of the run.

::

    from lcpsim import scenes
    s = scenes.cube_on_slope(45.2, 1.0)
    traj = s.world.run(2000, record_contacts=True)
    traj.to_html("slope.html", body=s.body, direction=s.direction)   # or lcpsim.viewer.write_html(traj, ...)

The page inlines three.js (the pinned build shipped in ``vendor/three`` with
its MIT licence) and the data, so it opens from ``file://`` with no server
and fetches nothing (its content security policy forbids it). It draws boxes,
spheres and planes; plays the run (play/pause, speed, a slider, the step
readout), with an orbit camera; shows the contact points, normal-impulse and
friction-impulse arrows (toggles, scale in the legend) of trajectories run
with ``record_contacts=True``; colours a strip along the timeline by LCP status,
with a marker at each failed step (a click jumps there); and reads out the
selected body's pose, tilt and displacement along the slope.

Long runs are downsampled to fit ``max_bytes`` (default 2,000,000 bytes for
the whole page): every k-th state, the last one and every failed step are
kept, and the page says so. An empty trajectory gives a page that says it is empty.
"""

from __future__ import annotations

import html
import json
import os
import re
from pathlib import Path
from typing import Any, Mapping

from ..trajectory_data import TrajectoryData
from .encode import STATUS_COLORS, payload

__all__ = ["write_html", "render_html", "DEFAULT_MAX_BYTES", "THREE_VERSION"]

#: The default size cap of a page (bytes).
DEFAULT_MAX_BYTES = 2_000_000
#: The bundled three.js release (npm ``three``).
THREE_VERSION = "0.170.0"

_HERE = Path(__file__).parent
_VENDOR = _HERE / "vendor" / "three"
# OrbitControls imports 'three' by name; the page points that name at the inlined build.
_THREE_SPECIFIER = "'three'"


def write_html(traj: TrajectoryData, path: str | os.PathLike[str], **options: Any) -> str:
    """Writes :func:`render_html` of ``traj`` to ``path``; returns the path."""
    text = render_html(traj, **options)
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(text)
    return os.fspath(path)


def render_html(
    traj: TrajectoryData,
    *,
    title: str | None = None,
    description: str | None = None,
    body: int | None = None,
    direction: Any = None,
    direction_label: str | None = None,
    max_bytes: int = DEFAULT_MAX_BYTES,
) -> str:
    """The viewer page of ``traj`` as a string.

    ``title`` and ``description`` head the page (default: the scene and its
    parameters from ``traj.config``). ``body`` is the body selected at first
    (default: the first moving one); ``direction`` the direction its
    displacement is read along (default: down the first tilted plane), named
    ``direction_label``. ``max_bytes`` caps the page's size (downsampling
    states, never dropping a failed step unless they alone overflow a quarter of it)."""
    if isinstance(max_bytes, bool) or not isinstance(max_bytes, int) or max_bytes <= 0:
        raise ValueError(f"max_bytes must be a positive integer, got {max_bytes!r}")
    if body is not None and (isinstance(body, bool) or not isinstance(body, int)):
        raise ValueError(f"body must be a body index (int), got {body!r}")
    from .. import __version__

    three = (_VENDOR / "three.module.min.js").read_text(encoding="utf-8")
    orbit = (_VENDOR / "OrbitControls.js").read_text(encoding="utf-8")
    licence = (_VENDOR / "LICENSE").read_text(encoding="utf-8")
    if orbit.count(_THREE_SPECIFIER) != 1:
        raise RuntimeError("vendored OrbitControls.js: expected one import from 'three'")
    for name, text in (("three.module.min.js", three), ("OrbitControls.js", orbit)):
        if re.search(r"</script|<!--", text, re.IGNORECASE):
            raise RuntimeError(f"vendored {name} cannot be inlined in a <script> element as it is")
    config = traj.config or {}
    title = title or _default_title(config)
    parts = {
        "TITLE": html.escape(title),
        "THREE": three,
        "ORBIT": orbit,
        "VIEWER": (_HERE / "viewer.js").read_text(encoding="utf-8"),
        "THREE_SPECIFIER": json.dumps(_THREE_SPECIFIER),
        "STATUS_LEGEND": "".join(
            f' <span style="background:{c}"></span>{html.escape(s)}' for s, c in STATUS_COLORS.items()
        ),
        "FOOTER": (
            f"Written by lcpsim {html.escape(__version__)}. 3-D drawing by three.js r{THREE_VERSION.split('.')[1]} "
            "(bundled in this page), <details style='display:inline'><summary>its MIT licence</summary><pre>"
            + html.escape(licence) + "</pre></details>"
        ),
    }
    parts["HEADER"] = _header(traj, config, description)
    template = (_HERE / "template.html").read_text(encoding="utf-8")
    fixed = len(_fill(template, {**parts, "DATA": "", "NOTICES": ""}).encode("utf-8"))
    # The frames get what the page, the notices and the JSON around the arrays (16 kB, with up to
    # 500 failed runs) and every step's status (one byte a step, base64) leave.
    budget = max_bytes - fixed - 16_000 - 4 * (len(traj) + 2) // 3
    for _ in range(4):  # an estimate a little short: retry with less
        data = payload(traj, body=body, direction=direction, direction_label=direction_label, budget=budget)
        parts["NOTICES"] = _notices(traj, data)
        # "</" never appears in the JSON text ("<\/" is the same string to JSON.parse).
        parts["DATA"] = json.dumps(data, separators=(",", ":"), allow_nan=False).replace("</", "<\\/")
        page = _fill(template, parts)
        size = len(page.encode("utf-8"))
        if size <= max_bytes:
            return page
        budget -= size - max_bytes + 1_000
    raise ValueError(f"max_bytes={max_bytes} is too small for this trajectory's page ({size} bytes)")


def _fill(template: str, parts: dict[str, str]) -> str:
    """Replaces each @NAME@ of the template (one pass: the inserted text is not scanned)."""
    return re.sub(r"@([A-Z_]+)@", lambda m: parts[m.group(1)], template)


def _default_title(config: Mapping[str, Any]) -> str:
    scene = config.get("scene")
    if not scene:
        return "lcpsim trajectory"
    params = ", ".join(f"{k} = {v}" for k, v in (config.get("scene_params") or {}).items())
    return f"lcpsim: {scene}" + (f" ({params})" if params else "")


def _header(traj: TrajectoryData, config: Mapping[str, Any], description: str | None) -> str:
    p = config.get("params") or {}
    lines = []
    if description:
        lines.append(html.escape(description))
    if p:
        opts = ", ".join(f"{k}={v}" for k, v in (config.get("solver_options") or {}).items())
        scale = p.get("cone_scale")
        s_value = "" if scale in ("none", None) else f" (s = {p.get('scale')})"
        solver = str(config.get("method")) + (f" ({opts})" if opts else "")
        lines.append(html.escape(
            f"dt = {p.get('dt')} s, k = {p.get('friction_dirs')} friction directions, "
            f"cone scale {scale}{s_value}, solver {solver}"
        ))
    stats = traj.lcp_stats()
    fails = ", ".join(f"{k} {v}" for k, v in stats.by_status.items() if k != "solved")
    fails = f" ({fails})" if stats.failures else ""
    lines.append(html.escape(
        f"{len(traj)} steps, {stats.lcps} LCPs, {stats.failures} not solved{fails}; "
        f"max residual {stats.max_residual:.2e} (physical units); pivots median {stats.pivots_median:g}, "
        f"max {stats.pivots_max}"
    ))
    return "\n".join(f"<p>{x}</p>" for x in lines)


def _notices(traj: TrajectoryData, data: dict[str, Any]) -> str:
    out = []
    if len(traj) == 0:
        out.append('<p class="notice empty" id="empty-notice">This trajectory is empty: it has 0 steps, '
                   "so there is no motion to show (only the initial state is drawn).</p>")
    if data["stride"] > 1 or data["frames"] < len(traj) + 1:
        out.append(
            f'<p class="notice" id="downsampled-notice">Downsampled to fit the page: {data["frames"]} of '
            f"{len(traj) + 1} states are kept (one step in {data['stride']}, the last one and every step whose "
            "LCP failed). The status strip below the slider shows every step.</p>"
        )
    if not data["has_contacts"] and len(traj):
        out.append('<p class="notice" id="no-contacts-notice">This trajectory was run without recording contacts '
                   "(World.run(..., record_contacts=True)): no contact points or impulse arrows.</p>")
    return "\n".join(out)
