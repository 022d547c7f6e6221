"""The viewer in a real browser: the viewer page in headless Chromium (Debian's
/usr/bin/chromium driven by Playwright for Python; `.ci/run` installs both).

Each page loads from file:// with no console error and no request beyond the
page itself and the blob: URLs it makes of its inlined three.js; the 3-D
canvas is not blank; the cube's pixels move between the first and the last
frame of a sliding run and stay put for a resting one; the slider changes the
frame drawn; a failed LCP has its marker on the timeline, at its step; joints are
drawn where the page's data puts them, and hiding them changes the picture; a
compound body and a height field are drawn over their whole extent, at their poses.
"""

from __future__ import annotations

import base64
import io
import math
import os
import shutil

import numpy as np
import pytest

from lcpsim import World, scenes
from lcpsim.cli import main
from test_viewer import decode, page_data
from test_viewer_joints import double_pendulum

pytestmark = pytest.mark.slow  # a real browser per test

CHROMIUM = os.environ.get("LCPSIM_CHROMIUM", "/usr/bin/chromium")
# Headless Chromium has no GPU here: WebGL through SwiftShader (software).
CHROMIUM_ARGS = ["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist"]
CLASSIC = {"pivoting": "classic", "piv_tol": 1e-12, "zero_tol": 1e-6}

sync_api = pytest.importorskip(
    "playwright.sync_api", reason="Playwright for Python is not installed (pip install playwright): browser tests skipped"
)
if not (os.path.exists(CHROMIUM) or shutil.which(CHROMIUM)):
    pytest.skip(f"no Chromium at {CHROMIUM} (apt-get install chromium): browser tests skipped", allow_module_level=True)


@pytest.fixture(scope="module")
def browser():
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield b
        b.close()


@pytest.fixture(scope="module")
def pages(tmp_path_factory):
    """The pages under test: a sliding cube (the issue's bar, through `lcpsim view`), a resting
    one, a run with failed LCPs and an empty run."""
    d = tmp_path_factory.mktemp("viewer")
    out = {"slide": d / "slide.html"}
    assert main(["view", "cube_on_slope", "--angle-deg", "45.2", "--mu", "1", "--out", str(out["slide"])]) == 0
    rest = scenes.cube_on_slope(30.0, 1.0)
    out["rest"] = rest.world.run(1000, record_contacts=True).to_html(d / "rest.html")
    fail = scenes.cube_on_slope(45.0001, 1.0, **CLASSIC)
    traj = fail.world.run(300, record_contacts=True)
    out["fail"] = traj.to_html(d / "fail.html")
    out["failed_steps"] = [int(s) + 1 for s in np.nonzero(~traj.ok)[0]]
    out["empty"] = scenes.resting_cube().world.run(0).to_html(d / "empty.html")
    out["joints"] = double_pendulum().run(400).to_html(d / "joints.html")
    w, out["field"], out["compound"] = dumbbell_in_a_bowl()
    out["shapes"] = w.run(300).to_html(d / "shapes.html")
    return out


def dumbbell_in_a_bowl() -> tuple[World, int, int]:
    """A dumbbell (two 0.4 m cubes 1.2 m apart on a capsule bar along x, one compound body)
    dropped into a bowl-shaped height field of 9 × 9 points over 4 × 4 m, 0 m deep at its
    centre and 0.8 m high at its corners. Returns the world, the field and the dumbbell."""
    w = World(dt=2e-3)
    x = np.linspace(-2.0, 2.0, 9)
    gx, gy = np.meshgrid(x, x)
    field = w.add_heightfield(0.1 * (gx**2 + gy**2), (2.0, 2.0), 0.5)
    cube = {"kind": "box", "half_extents": (0.2, 0.2, 0.2)}
    bar = {"kind": "capsule", "radius": 0.05, "half_length": 0.4, "orientation": (math.sqrt(0.5), 0, math.sqrt(0.5), 0)}
    parts = [{**cube, "position": (-0.6, 0, 0)}, {**cube, "position": (0.6, 0, 0)}, bar]
    return w, field, w.add_compound(parts, mass=2.0, position=(0, 0, 0.4))


class Page:
    """A loaded viewer page, with what it logged and requested."""

    def __init__(self, browser, path) -> None:
        self.page = browser.new_page(viewport={"width": 1100, "height": 760})
        self.errors: list[str] = []
        self.requests: list[str] = []
        self.page.on("console", lambda m: self.errors.append(m.text) if m.type in ("error", "warning") else None)
        self.page.on("pageerror", lambda e: self.errors.append(str(e)))
        self.page.on("request", lambda r: self.requests.append(r.url))
        self.url = "file://" + os.fspath(path)
        self.page.goto(self.url)
        self.page.wait_for_selector("body[data-ready]", state="attached", timeout=60_000)
        assert self.page.evaluate("document.body.dataset.ready") == "1", self.errors

    def eval(self, js: str):
        return self.page.evaluate(js)

    def canvas(self) -> np.ndarray:
        """The 3-D canvas's pixels (H, W, 3)."""
        from PIL import Image

        url = self.eval("document.getElementById('scene').toDataURL('image/png')")
        img = Image.open(io.BytesIO(base64.b64decode(url.split(",", 1)[1]))).convert("RGB")
        return np.asarray(img).astype(int)

    def frame(self, f: int) -> np.ndarray:
        self.eval(f"lcpsimViewer.setFrame({f})")
        return self.canvas()

    def hide_contacts(self) -> None:
        for box in ("#show-points", "#show-normal", "#show-friction"):
            self.page.uncheck(box)

    def close(self) -> None:
        self.page.close()


@pytest.fixture
def open_page(browser):
    opened: list[Page] = []

    def _open(path) -> Page:
        opened.append(Page(browser, path))
        return opened[-1]

    yield _open
    for p in opened:
        p.close()


def cube_mask(img: np.ndarray) -> np.ndarray:
    """Pixels of the selected body's orange (0xe8702a, shaded): red well above green and blue."""
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    return (r > g + 40) & (r > b + 70)


def centroid(mask: np.ndarray) -> np.ndarray:
    ys, xs = np.nonzero(mask)
    return np.array([xs.mean(), ys.mean()])


@pytest.mark.parametrize("name", ["slide", "rest", "fail", "empty", "joints", "shapes"])
def test_loads_offline_without_errors(open_page, pages, name):
    p = open_page(pages[name])
    assert p.errors == []
    foreign = [u for u in p.requests if u != p.url and not u.startswith("blob:")]
    assert foreign == [], f"the page requested {foreign}"
    assert p.eval("lcpsimViewer.webgl") is True
    img = p.canvas()
    # Not blank: the ground, the cube and its edges give many colours, the cube a large patch.
    assert len(np.unique(img.reshape(-1, 3), axis=0)) > 50
    assert cube_mask(img).sum() > (100 if name == "joints" else 2000)  # the jointed scene's selected body: a thin bar
    if name == "empty":
        assert p.page.is_visible("#empty-notice")
        assert p.eval("lcpsimViewer.frames") == 1


def test_sliding_cube_moves_down_the_slope_and_resting_cube_does_not(open_page, pages):
    slide = open_page(pages["slide"])
    slide.hide_contacts()
    last = slide.eval("lcpsimViewer.frames") - 1
    a, b = slide.frame(0), slide.frame(last)
    shift = centroid(cube_mask(b)) - centroid(cube_mask(a))
    # 0.097 m down a 45° slope that descends to the right of the screen: right and down.
    assert shift[0] > 3 and shift[1] > 3, shift
    assert (np.abs(a - b).sum(axis=2) > 30).sum() > 500
    assert "step 2000 / 2000" in slide.page.inner_text("#step-readout")
    assert float(slide.page.inner_text("#body-readout").split("down-slope distance:")[1].split()[0]) > 0.09
    # λ, the sliding speed the LCP chose, is g (sin θ − μ cos θ) t at t = 2 s.
    lam = float(slide.page.inner_text("#contact-readout").split("max λ =")[1].split()[0])
    th = math.radians(45.2)
    assert lam == pytest.approx(9.81 * (math.sin(th) - math.cos(th)) * 2.0, rel=0.02)

    rest = open_page(pages["rest"])
    rest.hide_contacts()
    last = rest.eval("lcpsimViewer.frames") - 1
    a, b = rest.frame(0), rest.frame(last)
    assert np.abs(a - b).max() <= 2, "a resting cube's pixels changed"
    assert np.allclose(centroid(cube_mask(a)), centroid(cube_mask(b)), atol=0.05)


def test_slider_changes_the_frame(open_page, pages):
    p = open_page(pages["slide"])
    p.hide_contacts()
    before = p.frame(0)
    assert "initial state" in p.page.inner_text("#step-readout")
    p.page.fill("#slider", "1500")
    assert p.eval("lcpsimViewer.frame") == 1500
    assert "step 1500 / 2000" in p.page.inner_text("#step-readout")
    assert (np.abs(p.canvas() - before).sum(axis=2) > 30).sum() > 200
    # Contacts on again: their points and arrows add pixels.
    bare = p.canvas()
    p.page.check("#show-points")
    p.page.check("#show-normal")
    assert (np.abs(p.canvas() - bare).sum(axis=2) > 30).sum() > 20
    # Play at 0.25× real time: frames advance by themselves; pause stops them.
    p.page.select_option("#speed", "0.25")
    p.eval("lcpsimViewer.setFrame(0)")
    p.page.click("#play")
    p.page.wait_for_timeout(400)
    p.page.click("#play")
    stopped = p.eval("lcpsimViewer.frame")
    assert stopped > 0 and p.eval("lcpsimViewer.playing") is False
    p.page.wait_for_timeout(200)
    assert p.eval("lcpsimViewer.frame") == stopped


def test_failed_steps_have_markers_that_jump_there(open_page, pages):
    p = open_page(pages["fail"])
    failed = pages["failed_steps"]
    assert failed, "the failing scene did not fail"
    markers = p.page.locator(".fail-marker")
    marked = sorted(int(markers.nth(i).get_attribute("data-step")) for i in range(markers.count()))
    assert marked == failed  # steps 2, 7, 11, 16: none adjacent, one marker each
    # The strip is red at a failed step's column and not at a solved one's.
    px = p.eval(
        """(() => { const c = document.getElementById('strip'), g = c.getContext('2d');
            const at = (s) => Array.from(g.getImageData(Math.floor((s - 0.5) / lcpsimViewer.steps * c.width),
                                                         c.height - 2, 1, 1).data);
            return [at(%d), at(250)]; })()""" % failed[0]
    )
    (r, g, b, _), solved = px
    assert r > 150 and g < 80 and b < 80, px
    assert solved[1] > solved[0], px  # green
    strip = p.page.locator("#strip")
    box = strip.bounding_box()
    strip.click(position={"x": box["width"] * 249.5 / 300, "y": box["height"] / 2})
    assert abs(p.eval("lcpsimViewer.step") - 250) <= 2
    markers.nth(1).click()
    assert p.eval("lcpsimViewer.step") == failed[1]
    lcp = p.page.inner_text("#lcp-readout")
    assert "cycling" in lcp or "numerical" in lcp or "max_pivots" in lcp, lcp
    assert "no impulse was applied" in p.page.inner_text("#contact-readout")


def test_joints_are_drawn_at_their_anchors_along_their_axes(open_page, pages):
    p = open_page(pages["joints"])
    d = page_data(open(pages["joints"], encoding="utf-8").read())
    anchor, axis = decode(d["arrays"]["j_anchor"]), decode(d["arrays"]["j_axis"])
    assert p.eval("lcpsimViewer.joints") == 4
    last = p.eval("lcpsimViewer.frames") - 1
    for f in (0, last // 2, last):
        p.eval(f"lcpsimViewer.setFrame({f})")
        for j in range(4):
            at, along = p.eval(f"lcpsimViewer.jointPose({j})")
            np.testing.assert_allclose(at, anchor[f, j], atol=1e-6)
            np.testing.assert_allclose(along, axis[f, j] / np.linalg.norm(axis[f, j]), atol=1e-6)
    # The ball joint between the bars moved (it swung down) and is drawn: hiding the joints
    # changes the picture.
    assert np.linalg.norm(anchor[last, 1] - anchor[0, 1]) > 0.2
    p.hide_contacts()
    shown = p.frame(last)
    p.page.uncheck("#show-joints")
    assert (np.abs(shown - p.canvas()).sum(axis=2) > 30).sum() > 50


def test_a_compound_and_a_height_field_are_drawn_over_their_extent(open_page, pages):
    p = open_page(pages["shapes"])
    field, body = pages["field"], pages["compound"]
    # The field: its grid's x and y extent, its heights from the bowl's bottom to its corners.
    lo, hi = p.eval(f"lcpsimViewer.bodyBounds({field})")
    np.testing.assert_allclose([lo, hi], [[-2, -2, 0], [2, 2, 0.8]], atol=1e-6)
    # The dumbbell at its last pose: the box around both cubes' corners (the bar is inside it).
    d = page_data(open(pages["shapes"], encoding="utf-8").read())
    pose = decode(d["arrays"]["pose"])[-1, 0]  # the one dynamic body: position, then (w, x, y, z)
    w, x, y, z = pose[3:]
    rot = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                    [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                    [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
    corners = np.array([(cx + sx * 0.2, sy * 0.2, sz * 0.2) for cx in (-0.6, 0.6)
                        for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    world = corners @ rot.T + pose[:3]
    p.eval(f"lcpsimViewer.setFrame({p.eval('lcpsimViewer.frames') - 1})")
    lo, hi = p.eval(f"lcpsimViewer.bodyBounds({body})")
    np.testing.assert_allclose([lo, hi], [world.min(axis=0), world.max(axis=0)], atol=1e-5)
    assert 0.0 < pose[2] < 0.4  # it fell into the bowl
    # In the picture: the dumbbell, orange, wider than tall (both cubes), and hiding either body
    # changes many pixels (the field covers much of the view).
    p.hide_contacts()
    shown = p.canvas()
    mask = cube_mask(shown)
    ys, xs = np.nonzero(mask)
    assert mask.sum() > 2000 and np.ptp(xs) > 2 * np.ptp(ys), (mask.sum(), np.ptp(xs), np.ptp(ys))
    for i, least in ((body, 2000), (field, 20000)):
        p.eval(f"lcpsimViewer.showBody({i}, false)")
        assert (np.abs(shown - p.canvas()).sum(axis=2) > 30).sum() > least, i
        p.eval(f"lcpsimViewer.showBody({i}, true)")
