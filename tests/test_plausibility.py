"""Physical plausibility of a scene file (``dem_core.workflow.plausibility``): a water table
below the whole model is refused; unusual values (a reservoir, unit slips in density,
friction and cohesion) are one warning line each, and ``run-scene --strict`` refuses them."""
import json
import warnings
from pathlib import Path

import pytest

from comparisons import cli
from dem_core.workflow.plausibility import ScenePlausibilityWarning
from dem_core.workflow.scene import Scene

SCENE = Path(__file__).resolve().parents[1] / "comparisons" / "scenes" / "adhikary.json"


def scene_dict(**changes):
    d = json.loads(SCENE.read_text())
    d.update(changes)
    return d


def warned(d) -> list:
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        Scene.from_dict(d)
    return [str(w.message) for w in seen if issubclass(w.category, ScenePlausibilityWarning)]


def test_a_plain_scene_loads_without_a_word():
    assert warned(scene_dict()) == []


@pytest.mark.parametrize("change, words", [
    ({"density": 2.6}, "density 2.6 kg/m^3 is below 500"),
    ({"stages": [{"kind": "water", "surface": 5.0}]}, "above the ground"),
])
def test_an_unusual_scene_value_is_one_warning_naming_it(change, words):
    lines = warned(scene_dict(**change))
    assert len(lines) == 1 and words in lines[0]


@pytest.mark.parametrize("field, value, words", [
    ("friction", 0.6, "friction 0.6 deg is below 5 deg"),
    ("cohesion", 50.0, "cohesion 50 Pa is below 1000 Pa"),
])
def test_a_material_that_looks_like_a_unit_slip_is_warned(field, value, words):
    d = scene_dict()
    name = next(k for k, m in d["materials"].items() if m.get("tensile_strength", 0) >= 1e5)
    d["materials"][name][field] = value
    lines = warned(d)
    assert len(lines) == 1 and words in lines[0] and name in lines[0]


def test_a_water_table_below_the_model_is_refused():
    with pytest.raises(ValueError, match="below the whole model .* no water anywhere"):
        Scene.from_dict(scene_dict(stages=[{"kind": "water", "surface": -5.0}]))


def test_a_water_table_inside_the_slope_is_neither_warned_nor_refused():
    from dem_core.workflow.plausibility import _ground
    xs, top, _ = _ground(Scene.from_dict(scene_dict()))
    inside = [[float(x), 0.5 * float(y)] for x, y in zip(xs[::20], top[::20])]
    assert warned(scene_dict(stages=[{"kind": "water", "surface": inside}])) == []
    # a level above the toe's ground is a reservoir in front of the face
    assert len(warned(scene_dict(stages=[{"kind": "water", "surface": float(top.max())}]))) == 1


def test_run_scene_prints_a_warning_line_and_strict_refuses(tmp_path, capsys, monkeypatch):
    path = tmp_path / "light.json"
    path.write_text(json.dumps(scene_dict(density=2.6)))
    ran = []
    monkeypatch.setattr("comparisons.run_scene.run_prepared",
                        lambda *a, **k: ran.append(1) or ([], None))
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path / "out")]) == 0
    err = capsys.readouterr().err
    assert err.count("warning: density 2.6 kg/m^3") == 1 and ran == [1]
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path / "out"), "--strict"]) == 2
    err = capsys.readouterr().err
    assert "error:" in err and "density 2.6" in err and "--strict" in err and ran == [1]


def test_two_regions_a_hair_apart_are_refused():
    d = scene_dict()
    regions = d["geometry"]["regions"]
    d2 = json.loads(json.dumps(d))
    d2["materials"]["*"] = d2["materials"]["joint:bedding"]     # the lid's contacts
    d2["geometry"]["regions"] = regions + [
        {"name": "lid", "exterior": [[0.0, 0.3955], [0.1, 0.3955], [0.1, 0.45], [0.0, 0.45]]}]
    with pytest.raises(ValueError, match="regions .*'lid'.* apart.* a gap where an edge"):
        Scene.from_dict(d2)
    d2["geometry"]["regions"][-1]["exterior"] = [[0.0, 0.395], [0.1, 0.395], [0.1, 0.45],
                                                 [0.0, 0.45]]
    Scene.from_dict(d2)                           # sharing the edge: no gap


def test_sliver_blocks_are_warned_when_the_blocks_are_built():
    from dem_core.geometry import GeometrySpec
    from dem_core.geometry.regions import rectangle
    from dem_core.contact.materials import Material
    from dem_core.workflow.scene import Boundary, build_model
    geo = GeometrySpec([rectangle("base", 0, 0, 4, 1), rectangle("block", 1, 1, 2, 1.5),
                        rectangle("chip", 2, 1, 2.001, 1.01)])
    sc = Scene(geo, {"*": Material(kn=1e9, ks=1e9)}, density=2500.0,
               boundaries=[Boundary("base")])
    with pytest.warns(ScenePlausibilityWarning, match="1 block.* under 0.0001 of the median"):
        build_model(sc)
