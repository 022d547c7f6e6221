"""The benchmark scripts' writers of benchmarks/RESULTS.md lose nothing."""

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def load(name: str):
    spec = importlib.util.spec_from_file_location(name, ROOT / "benchmarks" / "peers" / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_many_bodies_splice_keeps_the_runs_written_by_hand():
    report = load("many_bodies_report")
    md = ("# Benchmarks\n\n## Slope\n\nslope text\n\n## Many bodies: old title\n\n### Rerun at abc\n\nold table\n\n"
          "### Contact LCPs of heaps\n\nold scaling\n\n### Resting stacks\n\nby hand\n\n## FCLib\n\nfclib text\n")
    section = ["## Many bodies: new title", "", "new table", "", "### Contact LCPs of heaps", "", "new scaling", "",
               "### Broad phase", "", "new broad phase"]
    out = report.splice(md, section)
    assert out.startswith("# Benchmarks\n\n## Slope\n\nslope text\n\n## Many bodies: new title\n\nnew table\n\n")
    assert "old title" not in out and "old scaling" not in out
    # Hand-written subsections kept in place, a generated one replaced in place, a new one after them.
    order = [out.index(s) for s in ("### Rerun at abc\n\nold table", "### Contact LCPs of heaps\n\nnew scaling",
                                    "### Resting stacks\n\nby hand", "### Broad phase\n\nnew broad phase",
                                    "## FCLib\n\nfclib text")]
    assert order == sorted(order)
    assert report.splice(out, section) == out
    # A file without the section gets it at the end.
    assert report.splice("# Benchmarks\n", section).endswith("new broad phase\n")


def test_results_md_has_one_stamped_table_per_benchmark():
    """Every section and subsection of RESULTS.md names the commit its figures were measured at,
    no heading repeats (one current table per benchmark; history lives in git), and the file
    stays short enough to read."""
    import re

    md = (ROOT / "benchmarks" / "RESULTS.md").read_text()
    assert len(md.splitlines()) <= 400
    headings = re.findall(r"^#{2,3} (.+)$", md, flags=re.M)
    assert len(headings) == len(set(headings))
    blocks = re.split(r"^## ", md, flags=re.M)[1:]
    measured = [b for b in blocks if not b.startswith(("How it is measured", "Speed goals", "Problem sets",
                                                       "Simulation"))]
    for block in measured:
        assert re.search(r"\b[0-9a-f]{7}\b", block), block.splitlines()[0]
    assert not re.search(r"issue \d|DESIGN §", md, flags=re.I)


def test_many_bodies_splice_of_the_recorded_run_changes_nothing():
    """Rewriting the "Many bodies" section from the data file behind its table gives the file back."""
    import gzip
    import json
    import sys

    sys.path.insert(0, str(ROOT / "benchmarks" / "peers"))
    sys.path.insert(0, str(ROOT / "benchmarks"))
    report = load("many_bodies_report")
    res = json.loads(gzip.decompress((ROOT / "benchmarks" / "peers" / "many_bodies_6820272.json.gz").read_bytes()))
    res["command"] = ("benchmarks/peers/.venv/bin/python benchmarks/peers/many_bodies.py "
                      "--scenes stack10,towers3,towers10 --out benchmarks/peers/many_bodies_6820272.json.gz")
    scaling = load_top("lcp_scaling")
    lines = report.render(res) + scaling.render(json.loads((ROOT / "benchmarks" / "lcp_scaling.json").read_text()))
    lines += report.render_broadphase(json.loads((ROOT / "benchmarks" / "broadphase.json").read_text()))
    md = (ROOT / "benchmarks" / "RESULTS.md").read_text()
    assert report.splice(md, lines) == md


def load_top(name: str):
    spec = importlib.util.spec_from_file_location(name, ROOT / "benchmarks" / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
