"""One home per concept, Python side: no import-hook machinery and no
deprecated aliases; the command line and the report are built from the experiment registry;
one cone-scale parser and one JSON conversion; the defaults of the world, its
bodies, its stabilization and the scenes are the Rust ones, read from the
compiled module; no file over 800 lines and no function over 120."""

from __future__ import annotations

import ast
import importlib
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import lcpsim
from lcpsim._json import jsonable
from lcpsim.scale import cone_scale_argument, parse_cone_scale, scale_label, scale_value

PACKAGE = Path(lcpsim.__file__).parent


# ---------------------------------------------------------------- modules and entry points


def test_importing_lcpsim_adds_no_import_hook():
    out = subprocess.run(
        [sys.executable, "-c", "import sys; before = list(sys.meta_path); import lcpsim, lcpsim.io, lcpsim.cli, "
         "lcpsim.experiments; print(sys.meta_path == before)"],
        capture_output=True, text=True, env={"PYTHONPATH": str(PACKAGE.parent), "PATH": ""},
    )
    assert out.stdout.strip() == "True", out.stderr
    assert not (PACKAGE / "_deprecated.py").exists()


def test_io_load_lcp_and_capture_loader_have_distinct_names(tmp_path):
    from lcpsim import io
    from lcpsim.io import capture

    assert io.load_lcp is not capture.load_captured_lcp
    assert "load_lcp" not in capture.__all__ and "load_captured_lcp" in capture.__all__


def test_console_script_and_python_m_entry_points():
    pyproject = (PACKAGE.parents[1] / "pyproject.toml").read_text()
    assert 'lcpsim = "lcpsim.cli:main"' in pyproject
    from lcpsim.cli import main

    assert callable(main)
    out = subprocess.run([sys.executable, "-m", "lcpsim", "--version"], capture_output=True, text=True,
                         env={"PYTHONPATH": str(PACKAGE.parent), "PATH": ""})
    assert out.returncode == 0 and out.stdout.startswith("lcpsim "), out.stderr


def test_cli_modules_import_without_a_circle():
    # Each command module imports alone in a fresh interpreter, and the
    # registry module imports nothing else of lcpsim.cli.
    for mod in ("lcpsim.cli.command", "lcpsim.cli.solve", "lcpsim.cli.simulate", "lcpsim.cli.experiments",
                "lcpsim.cli.main"):
        out = subprocess.run([sys.executable, "-W", "error::DeprecationWarning", "-c", f"import {mod}"],
                             capture_output=True, text=True, env={"PYTHONPATH": str(PACKAGE.parent), "PATH": ""})
        assert out.returncode == 0, (mod, out.stderr)
    tree = ast.parse((PACKAGE / "cli" / "command.py").read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            assert node.level == 0, "lcpsim.cli.command must not import the command modules"


# ---------------------------------------------------------------- the experiment registry


def test_cli_and_report_are_built_from_the_registry():
    from lcpsim.cli.command import commands
    from lcpsim.experiments import DEFAULTS, EXPERIMENTS, REGISTRY
    from lcpsim.experiments.experiment import Experiment

    names = [c.name for c in commands()]
    assert names == ["solve", "demo", "simulate", "view", *REGISTRY, "report", "sweep", "export-fclib"]
    assert list(EXPERIMENTS) == list(DEFAULTS) == list(REGISTRY)
    for name, e in REGISTRY.items():
        assert isinstance(e, Experiment) and e.name == name
        mod = importlib.import_module(e.run.__module__)
        assert mod.EXPERIMENT is e and e.defaults is mod.DEFAULTS and e.report is not None


def test_experiment_name_comes_from_its_module():
    from lcpsim.experiments import REGISTRY
    from lcpsim.experiments.experiment import Experiment

    for name, e in REGISTRY.items():
        assert e.run.__module__.rsplit(".", 1)[-1] == name.replace("-", "_")
    push = Experiment.of_module("lcpsim.experiments.push", "the pushed cube", plot=REGISTRY["push"].plot)
    assert (push.name, push.help, push.run) == ("push", "the pushed cube", REGISTRY["push"].run)


# ---------------------------------------------------------------- one cone-scale parser


@pytest.mark.parametrize(
    "given, parsed",
    [
        (None, None), ("none", None), ("None", None), ("unscaled", None), ("", None), ("1", None), (1, None),
        (1.0, None), (np.float64(1.0), None), ("dt", "dt"), ("DT", "dt"), ("h", "dt"), ("timestep", "dt"),
        ("time_step", "dt"), (" 1e-3 ", 1e-3), (1e-3, 1e-3), (np.float32(0.5), 0.5), (np.int64(2), 2.0), (3, 3.0),
    ],
)
def test_cone_scale_spellings(given, parsed):
    assert parse_cone_scale(given) == parsed


@pytest.mark.parametrize("bad", [0, 0.0, -1e-3, "huge", float("inf"), float("nan"), "-1", True, np.bool_(False),
                                 [1e-3], {"s": 1}])
def test_bad_cone_scales_name_the_field_and_value(bad):
    with pytest.raises(ValueError, match=r"cone_scale must be none, dt or a number > 0, got"):
        parse_cone_scale(bad, "cone_scale")
    with pytest.raises(ValueError, match="cone_scale") as e:
        lcpsim.World(cone_scale=bad)
    assert repr(bad) in str(e.value)


def test_cone_scale_argument_labels_and_values():
    import argparse

    assert cone_scale_argument("none") == "none" and cone_scale_argument("1e-3") == 1e-3
    with pytest.raises(argparse.ArgumentTypeError, match="got 'x'"):
        cone_scale_argument("x")
    assert scale_value(None, 1e-3) == 1.0 and scale_value("dt", 1e-3) == 1e-3 and scale_value(0.5, 1e-3) == 0.5
    assert [scale_label(s) for s in (None, "dt", 1e-3)] == ["none", "dt", "0.001"]
    # The World reads the same spellings (and shows "none"/"dt"/the number).
    assert lcpsim.World(cone_scale="unscaled").params["cone_scale"] == "none"
    assert lcpsim.World(cone_scale="time_step").params["cone_scale"] == "dt"
    assert lcpsim.World(cone_scale="2e-3").params["cone_scale"] == 2e-3


# ---------------------------------------------------------------- one JSON conversion


def test_jsonable_edge_cases():
    x = {
        1: np.float64(0.5), "i": np.int32(3), "b": np.bool_(True), "a": np.arange(3), "nan": float("nan"),
        "inf": np.float64("inf"), "-inf": -math.inf, "none": None, "s": "text", "t": (1, 2.5), "set": {4},
        "nested": [{"m": np.array([[1.0, np.nan]])}], "keys": {"k": 1}.keys(), "obj": Path("p"), "bytes": b"x",
    }
    j = jsonable(x)
    assert j == {
        "1": 0.5, "i": 3, "b": True, "a": [0, 1, 2], "nan": "nan", "inf": "inf", "-inf": "-inf", "none": None,
        "s": "text", "t": [1, 2.5], "set": [4], "nested": [{"m": [[1.0, "nan"]]}], "keys": ["k"], "obj": "p",
        "bytes": "b'x'",
    }
    assert type(j["i"]) is int and type(j["b"]) is bool and type(j["1"]) is float
    json.dumps(j, allow_nan=False)  # strict JSON


def test_every_json_writer_uses_the_one_conversion():
    sources = {p: p.read_text() for p in PACKAGE.rglob("*.py")}
    defs = [p.relative_to(PACKAGE) for p, s in sources.items() if "def jsonable(" in s or "def _jsonable(" in s]
    assert defs == [Path("_json.py")]


# ---------------------------------------------------------------- defaults: the Rust ones, declared once


def _keyword_defaults(fn) -> dict:
    import inspect

    return {p.name: p.default for p in inspect.signature(fn).parameters.values() if p.default is not p.empty}


def test_world_defaults_are_the_rust_world_params():
    from lcpsim import Stabilization, World, _core

    d = _core.WORLD_DEFAULTS
    kw = _keyword_defaults(World.__init__)
    for name in ("dt", "friction_dirs", "method", "margin", "velocity_margin", "restitution",
                 "restitution_threshold", "mu_combine", "mu_override", "threads"):
        assert kw[name] == d[name], name
    assert list(kw["gravity"]) == d["gravity"] == [0.0, 0.0, -9.81]
    assert Stabilization().__dict__ == {k: d[k] for k in ("erp", "slop", "speculative", "gap_floor")}
    # A world given nothing has exactly the compiled defaults, from Python and from the glue alike.
    assert {k: v for k, v in World().params.items() if k != "solver_options"} == d == _core.World().params()
    assert d["gap_floor"] == 1e-12 and d["erp"] == 0.2  # the documented values


def test_body_defaults_are_the_rust_body_desc():
    from lcpsim import World, _core

    d = _core.BODY_DEFAULTS
    for fn in (World.add_box, World.add_sphere):
        kw = _keyword_defaults(fn)
        for name in ("mass", "mu", "static"):
            assert kw[name] == d[name], (fn.__name__, name)
        for name in ("position", "orientation", "velocity", "angular_velocity"):
            assert list(kw[name]) == d[name], (fn.__name__, name)
    for fn in (World.add_plane, World.add_ground, World.add_slope):
        assert _keyword_defaults(fn)["mu"] == d["mu"], fn.__name__
    w = World()
    b = w.body(w.add_sphere(0.5))
    assert (b.mass, b.mu, b.is_static) == (d["mass"], d["mu"], d["static"])
    assert w.body(w.add_ground()).mu == d["mu"]


@pytest.mark.parametrize("name", sorted(lcpsim.scenes.SCENES))
def test_scene_defaults_are_the_rust_scene_structs(name):
    from lcpsim import _core
    from lcpsim.scenes import scene_parameters

    params = scene_parameters(name)
    base = "cube_on_slope" if name == "resting_cube" else name
    rust = _core.SCENE_DEFAULTS[base]
    for key, value in rust.items():
        if key in params:
            assert params[key] == value, key
    if name != "resting_cube":
        assert list(params) == _core.SCENES[name]  # the same parameters, in the Rust structs' order


def test_glue_refuses_unknown_world_and_scene_parameters():
    from lcpsim import _core

    with pytest.raises(ValueError, match='unknown parameter "dtt" for World'):
        _core.World({"dtt": 1e-3})
    with pytest.raises(ValueError, match='unknown parameter "size" for scene ball_drop'):
        _core.build_scene("ball_drop", {"size": 1.0}, _core.World())
    with pytest.raises(ValueError, match="scene box_stack needs the parameter n"):
        _core.build_scene("box_stack", {}, _core.World())


# ---------------------------------------------------------------- sizes


def test_no_file_over_800_lines_and_no_function_over_120():
    for path in sorted(PACKAGE.rglob("*.py")):
        text = path.read_text()
        assert text.count("\n") <= 800, f"{path.relative_to(PACKAGE)}: {text.count(chr(10))} lines"
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                length = (node.end_lineno or node.lineno) - node.lineno + 1
                assert length <= 120, f"{path.relative_to(PACKAGE)}:{node.lineno} {node.name}: {length} lines"
