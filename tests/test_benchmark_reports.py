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
