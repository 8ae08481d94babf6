"""Examples are tests: each script in examples/ asserts one physical number (shrunk here by
``quick=True``); this runs them all, so an example that stops being true fails the suite."""
import importlib
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
NAMES = sorted(p.stem for p in EXAMPLES.glob("*.py"))


def test_every_example_is_run_here():
    assert {"centrifuge_slope", "sliding_block", "bond_in_tension"} <= set(NAMES)


@pytest.mark.parametrize("name", NAMES)
def test_example(name, monkeypatch):
    monkeypatch.chdir(EXAMPLES.parent)             # the project root, as the README runs them
    monkeypatch.syspath_prepend(str(EXAMPLES))
    module = importlib.import_module(name)
    assert module.main(quick=True) > 0          # each main asserts its own number
    sys.modules.pop(name, None)


def test_the_readme_lines_are_the_centrifuge_example_as_written():
    """The README's "A slope in a few lines" block, line for line, is what
    examples/centrifuge_slope.py runs (and ``test_example`` runs it): the README's own lines
    are tested as written."""
    readme = (EXAMPLES.parent / "README.md").read_text()
    block = readme.split("## A slope in a few lines", 1)[1].split("```python\n", 1)[1]
    lines = [ln for ln in block.split("```", 1)[0].splitlines() if ln.strip()]
    example = [ln.strip() for ln in (EXAMPLES / "centrifuge_slope.py").read_text().splitlines()
               if ln.strip()]
    start = example.index(lines[0].strip())
    assert example[start:start + len(lines)] == [ln.strip() for ln in lines]
    assert len(lines) >= 5


def test_the_field_slope_scene_file_is_the_examples_scene(monkeypatch):
    """examples/field_slope.json is what ``field_slope.write_scene_file`` writes (a stale file
    fails: run it again)."""
    import json

    monkeypatch.syspath_prepend(str(EXAMPLES))
    import field_slope

    written = json.loads((EXAMPLES / "field_slope.json").read_text())
    assert written == json.loads(json.dumps(field_slope.file_scene().to_dict()))
    sys.modules.pop("field_slope", None)


def test_the_field_slope_file_runs_in_both_methods(tmp_path, capsys):
    """``run-scene examples/field_slope.json --method both``: the DEM's factor of safety is
    planar sliding on a bedding joint (limit equilibrium 1.115, examples/field_slope.py); the
    continuum's, through a Hoek-Brown rock mass with no joints, is higher; one report holds
    both columns and both methods' pictures."""
    import json

    from comparisons import cli

    assert cli.main(["run-scene", str(EXAMPLES / "field_slope.json"), "--method", "both",
                     "--out", str(tmp_path), "--quiet"]) == 0
    out = capsys.readouterr().out
    folder = tmp_path / "field_slope"
    dem = json.loads((folder / "summary.json").read_text())["results"]["factor_of_safety"]
    fe = json.loads((folder / "continuum.json").read_text())["stages"][-1]
    assert abs(dem / 1.115 - 1) < 0.05
    assert fe["verdict"] == "limit" and fe["value"] > 1.5 * dem
    assert f"factor of safety {dem:.2f}" in out and f"F = {fe['value']:.4g}" in out
    report = (folder / "report.md").read_text()
    for picture in ("stage11_factor_of_safety.png", "stage11_search.png",
                    "continuum_stage11_factor_of_safety.png", "continuum_stage7_excavate.png"):
        assert (folder / picture).exists() and f"({picture})" in report
