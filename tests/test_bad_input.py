"""Bad input a new user tries: each is refused with a clear error naming the value,
before any compute; none passes in silence or ends in a traceback from deep inside."""
import math
import os

import numpy as np
import pytest

from comparisons import cli, registry
from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.geometry.simple_blocks import from_polygons

SQUARE = [(0, 0), (1, 0), (1, 1), (0, 1)]


def two_blocks() -> Model:
    bs = from_polygons([[(0, 0), (4, 0), (4, 1), (0, 1)], [(1, 1), (2, 1), (2, 2), (1, 2)]],
                       edge_material="joint:base", groups={"base": [0], "block": [1]})
    m = Model(bs, {"joint:*": Material(kn=1e9, ks=1e9, friction=30)}, density=2000)
    m.fix("base")
    m.set_gravity(1.0)
    return m


def one_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


# ---------------------------------------------------------------------- the command line
def test_an_unknown_case_is_one_line_listing_the_cases(capsys):
    assert cli.main(["run", "nosuchcase", "--quick"]) == 2
    line = one_line(capsys.readouterr().err)
    assert "'nosuchcase'" in line
    assert all(name in line for name in registry.CASES)


@pytest.fixture
def no_compute(monkeypatch):
    """A run of the lajtai case fails the test: the refusal must come before any compute."""
    def boom(*args, **kwargs):
        raise AssertionError("the case ran before its output folder was checked")
    monkeypatch.setattr(registry.case_module("lajtai"), "run", boom)


def test_an_out_folder_that_is_a_file_is_refused_before_any_compute(tmp_path, capsys,
                                                                    no_compute):
    blocker = tmp_path / "results"
    blocker.write_text("a file where the results folder would go")
    assert cli.main(["run", "lajtai", "--quick", "--out", str(blocker)]) == 2
    line = one_line(capsys.readouterr().err)
    assert "cannot write results" in line and str(blocker) in line


@pytest.mark.parametrize("item, words", [
    ("bogus=1", ["--set bogus", "not a setting of lajtai", "zone_size"]),
    ("zone_size", ["KEY=VALUE", "'zone_size'"]),
    ("ucs_edge=[1, 2]", ["--set ucs_edge", "expected a float", "[1, 2]"]),
])
def test_a_bad_variant_setting_is_refused_before_any_compute(tmp_path, capsys, no_compute,
                                                             item, words):
    assert cli.main(["run", "lajtai", "--set", item, "--out", str(tmp_path)]) == 2
    line = one_line(capsys.readouterr().err)
    assert all(w in line for w in words), line


def test_a_variant_setting_makes_a_custom_variant(tmp_path, monkeypatch):
    seen = {}

    def fake_run(variant, seed, progress):
        seen.update(variant)
        raise KeyboardInterrupt        # stop here: only the settings are checked
    monkeypatch.setattr(registry.case_module("adhikary"), "run", fake_run)
    with pytest.raises(KeyboardInterrupt):
        cli.main(["run", "adhikary", "--full", "--set", 'solver={"edge_elements": true}',
                  "--set", "max_steps=50000", "--out", str(tmp_path)])
    full = registry.case_module("adhikary").VARIANTS["full"]
    assert seen == {**full, "solver": {"edge_elements": True}, "max_steps": 50000}


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_a_read_only_out_folder_is_refused_before_any_compute(tmp_path, capsys, no_compute):
    out = tmp_path / "ro"
    out.mkdir()
    out.chmod(0o500)
    try:
        assert cli.main(["run", "lajtai", "--out", str(out)]) == 2
    finally:
        out.chmod(0o700)
    assert "cannot write results" in one_line(capsys.readouterr().err)


# ---------------------------------------------------------------------- model files
@pytest.fixture
def saved(tmp_path):
    path = tmp_path / "model.npz"
    two_blocks().save(path)
    return path


def test_a_truncated_model_file_names_the_file_and_what_it_should_be(saved):
    data = saved.read_bytes()
    saved.write_bytes(data[: len(data) // 2])
    with pytest.raises(ValueError, match="not a model file") as e:
        Model.load(saved)
    assert str(saved) in str(e.value) and "Model.save" in str(e.value)


@pytest.mark.parametrize("content", ["text", "other npz"])
def test_a_file_that_is_not_a_model_names_the_file(tmp_path, content):
    path = tmp_path / "notamodel.npz"
    if content == "text":
        path.write_text("just some text\n")
    else:
        np.savez(path, x=np.arange(3))
    with pytest.raises(ValueError, match="not a model file") as e:
        Model.load(path)
    assert str(path) in str(e.value)


def test_a_missing_model_file_is_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError):
        Model.load(tmp_path / "nothere.npz")


def test_a_saved_model_still_loads(saved):
    assert Model.load(saved).n_blocks == 2


# ---------------------------------------------------------------------- polygons
def test_overlapping_polygons_are_refused_naming_both():
    with pytest.raises(ValueError, match=r"polygons 0 and 2 overlap"):
        from_polygons([SQUARE, [(1, 0), (2, 0), (2, 1), (1, 1)],
                       [(0.5, 0.5), (1.5, 0.5), (1.5, 1.5), (0.5, 1.5)]])


def test_a_self_intersecting_polygon_is_refused_naming_it():
    with pytest.raises(ValueError, match=r"polygon 1 is not a simple polygon"):
        from_polygons([SQUARE, [(1, 0), (2, 1), (2, 0), (1, 1)]])     # a bow tie


@pytest.mark.parametrize("poly, words", [([(0, 0), (1, 0)], "at least 3"),
                                         ([(0, 0), (1, 0), (math.nan, 1)], "finite"),
                                         ([(0, 0), (1, 0), (2, 0)], "polygon 0")])
def test_degenerate_polygons_are_refused(poly, words):
    with pytest.raises(ValueError, match=words):
        from_polygons([poly])


def test_polygons_sharing_edges_and_corners_or_pressed_slightly_in_are_fine():
    bs = from_polygons([SQUARE, [(1, 0), (2, 0), (2, 1), (1, 1)], [(1, 1), (2, 1), (2, 2)]])
    assert bs.n_blocks == 3
    pressed = [(0.2, 1 - 1e-5), (0.8, 1 - 1e-5), (0.8, 1.5), (0.2, 1.5)]   # a contact's depth
    assert from_polygons([SQUARE, pressed]).n_blocks == 2


# ---------------------------------------------------------------------- the model's calls
def test_removing_a_group_twice_names_the_group():
    m = two_blocks()
    m.remove("block")
    with pytest.raises(ValueError, match=r"group 'block' has no blocks left.*removed already"):
        m.remove("block")


@pytest.mark.parametrize("n", [-5, 2.5, math.nan, math.inf, "10", True])
def test_cycle_refuses_a_step_count_that_is_not_a_whole_number(n):
    m = two_blocks()
    with pytest.raises(ValueError, match="whole number") as e:
        m.cycle(n)
    assert repr(n) in str(e.value)
    assert m.step == 0


@pytest.mark.parametrize("n", [0, 3, np.int64(3), 3.0])
def test_cycle_takes_whole_numbers(n):
    m = two_blocks()
    m.cycle(n)
    assert m.step == int(n)
