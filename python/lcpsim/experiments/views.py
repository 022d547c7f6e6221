"""The report's viewer pages: each slope test, the pushed cube (staying and
sliding), a stack and a heap, run again from their configs with every step's
contacts recorded and written next to ``index.html`` as self-contained 3-D
pages (:mod:`lcpsim.viewer`), linked from their sections.

A page's run is the experiment's own: the same scene (``make_scene`` of the
experiment's config) for the same number of steps, so what it shows is what
the section's table reports.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

from ..scenes import Scene, box_stack, cube_heap
from . import push, slope
from .document import Doc
from .experiment import ReportContext

__all__ = ["View", "make_views", "add_links", "add_many_body_section", "STACK", "HEAP"]

#: The report's stack and heap: small enough to keep the report quick.
STACK: dict[str, Any] = {"n": 5}
HEAP: dict[str, Any] = {"n": 10, "seed": 0}


@dataclass(frozen=True)
class View:
    """One page: the section it belongs to, its link text, its file (relative to the report)."""

    section: str
    label: str
    path: str
    steps: int
    failures: int


def make_views(res: Mapping[str, Any], ctx: ReportContext) -> list[View]:
    """Writes every viewer page of the report; returns them in section order."""

    def pages() -> list[View]:
        views = [_slope_view(r, ctx) for r in res["slope"]]
        views += [_push_view(r, ctx) for r in res["push"] if r["scale"] == "none" and r["config"]["force"] in (9.79, 9.83)]
        steps = int(round(ctx.seconds / 1e-3))
        views.append(_write(ctx, "many_bodies", f"a stack of {STACK['n']} cubes", "view_stack.html",
                            box_stack(**STACK), steps))
        views.append(_write(ctx, "many_bodies", f"a heap of {HEAP['n']} cubes (seed {HEAP['seed']})",
                            "view_heap.html", cube_heap(**HEAP), steps))
        return views

    return list(ctx.step("viewer pages", pages))


def _slope_view(r: Mapping[str, Any], ctx: ReportContext) -> View:
    c = r["config"]
    label = f"{r['solver']['name']}, {c['angle_deg']:g}°, s = {r['scale']}"
    name = _file_name(f"view_slope_{r['solver']['name']}_{c['angle_deg']:g}_{r['scale']}")
    return _write(ctx, "slope", label, name, slope.make_scene(c), int(r["steps"]),
                  description=f"slope test: outcome {r['outcome']}, slide {r['slide_distance_m']:.4g} m "
                              f"(analytic {r['expected_slide_m']:.4g} m), {r['lcp_failures']} LCP failures")


def _push_view(r: Mapping[str, Any], ctx: ReportContext) -> View:
    c = r["config"]
    label = f"{r['solver']['name']}, F = {c['force']:g} N, s = {r['scale']}"
    steps = int(round(float(c["seconds"]) / float(c["dt"])))
    return _write(ctx, "push", label, _file_name(f"view_push_{r['solver']['name']}_{c['force']:g}_{r['scale']}"),
                  push.make_scene(c), steps,
                  description=f"pushed cube: outcome {r['outcome']} (exact: {r['expected_outcome']}), "
                              f"moved {r['displacement_m']:.3g} m, {r['lcp_failures']} LCP failures")


def _file_name(stem: str) -> str:
    """A plain file name: letters, digits and underscores, then .html."""
    return "".join(ch if ch.isalnum() else "_" for ch in stem) + ".html"


def _write(
    ctx: ReportContext, section: str, label: str, name: str, scene: Scene, steps: int, description: str | None = None
) -> View:
    traj = scene.world.run(steps, record_contacts=True)
    d = scene.direction
    traj.to_html(
        ctx.path(name), title=f"lcpsim report: {section.replace('_', ' ')} — {label}", description=description,
        body=scene.body, direction=d,
        direction_label=None if d is None else "down-slope distance" if d[2] < -1e-12 else "distance along the push",
    )
    return View(section, label, name, len(traj), traj.failures)


def add_links(d: Doc, section: str, views: list[View]) -> None:
    """A paragraph linking the section's viewer pages (nothing if it has none)."""
    mine = [v for v in views if v.section == section]
    if not mine:
        return
    links = ", ".join(f"[{v.label}]({v.path})" + (f" ({v.failures} failed LCP{'s' if v.failures > 1 else ''})" if v.failures else "") for v in mine)
    d.p(f"**Watch it move** (3-D viewer pages, self-contained; the timeline marks failed LCPs): {links}.")


def add_many_body_section(d: Doc, views: list[View], ctx: ReportContext) -> None:
    """The stack and the heap: a short section with their viewer pages."""
    d.h(2, "Many bodies: a stack and a heap")
    d.p(
        f"`lcpsim view box_stack --n {STACK['n']}` and `lcpsim view cube_heap --n {HEAP['n']} --seed {HEAP['seed']}` "
        f"({ctx.seconds:g} s each, robust solver, unscaled): a stack must stand still, exactly; a heap settles. "
        "Each step's contact points, normal and friction impulses are drawn; select any cube to read its pose."
    )
    add_links(d, "many_bodies", views)
