"""Renamed inputs (one name per quantity) still work for one release: the old
spelling gives the same model as the new one, with a DeprecationWarning naming the new key.

Tensile strength is ``tensile_strength`` everywhere: the zones' strength key (was ``tensile``:
``zone_strength`` of a scene file or of ``Model``, ``zones_from_mesh``'s ``strength``) and the
cases' flaw parameter ``flaw_tensile_strength`` (was ``flaw_tensile``: ``XParams(...)``,
``with_``, a sweep member's ``params``).
"""
from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from dem_core.contact.materials import (STRENGTH_COLUMNS, COL_BREAKABLE, COL_RESIDUAL_TENSILE_STRENGTH,
                                        COL_TENSILE_STRENGTH, Material, MaterialTable)
from dem_core.deformable.zone_plasticity import strength_table
from dem_core.geometry import GeometrySpec, rectangle
from dem_core.workflow.scene import Boundary, Scene

NEW = dict(cohesion=1e5, friction=35.0, tensile_strength=1e4)
OLD = dict(cohesion=1e5, friction=35.0, tensile=1e4)


def test_the_zone_strength_key_tensile_still_works_and_warns():
    with pytest.warns(DeprecationWarning, match="'tensile_strength'"):
        old = strength_table(OLD, 3)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        new = strength_table(NEW, 3)
    assert np.array_equal(old, new) and new[0, 3] == 1e4
    with pytest.raises(ValueError, match="not also its old name 'tensile'"):
        strength_table(dict(NEW, tensile=1e4), 1)


def _scene_dict(row):
    geo = GeometrySpec([rectangle("base", 0, -0.02, 0.1, 0), rectangle("rock", 0, 0, 0.1, 0.2)])
    sc = Scene(geo, {"*": Material(kn=1e10, ks=5e9, friction=35)}, density=2500.0,
               block_E=1e9, boundaries=[Boundary("base")],
               solver={"deformable": {"rock": 0.05}, "zone_strength": {"rock": NEW}})
    d = json.loads(json.dumps(sc.to_dict()))
    d["solver"]["zone_strength"]["rock"] = dict(row)
    return d


def test_a_scene_file_with_the_old_zone_strength_key_loads_with_a_warning(tmp_path):
    path = tmp_path / "old.json"
    path.write_text(json.dumps(_scene_dict(OLD)))
    with pytest.warns(DeprecationWarning, match="zone_strength\\['rock'\\].*'tensile_strength'"):
        old = Scene.load(path)
    assert old.solver["zone_strength"]["rock"] == NEW          # saved with the new key
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        new = Scene.from_dict(_scene_dict(NEW))
    assert old.to_dict() == new.to_dict()


def test_the_model_option_with_the_old_zone_strength_key_builds_the_same_zones():
    from dem_core.workflow.scene import build_model
    new = build_model(Scene.from_dict(_scene_dict(NEW)))
    with pytest.warns(DeprecationWarning, match="'tensile_strength'"):
        old = build_model(Scene.from_dict(_scene_dict(NEW)),
                          zone_strength={"rock": dict(OLD)})
    assert np.array_equal(old.zone_state.strength, new.zone_state.strength)


@pytest.mark.parametrize("module, cls", [("adhikary", "AdhikaryParams"),
                                         ("longtan", "LongtanParams"),
                                         ("highwood", "HighwoodParams"),
                                         ("underdip", "UnderdipParams"),
                                         ("coal_buckling", "CoalBucklingParams"),
                                         ("common_toppling", "ToppleParams")])
def test_the_old_flaw_tensile_parameter_still_works_and_warns(module, cls):
    import importlib
    Params = getattr(importlib.import_module(f"comparisons.scenes.{module}"), cls)
    member = {"flaw_tensile": 0.5e6}                    # a sweep member's params, old spelling
    with pytest.warns(DeprecationWarning, match="'flaw_tensile_strength'"):
        old = Params(**member)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        new = Params(flaw_tensile_strength=0.5e6)
    assert old == new
    with pytest.warns(DeprecationWarning, match="'flaw_tensile_strength'"):
        assert Params().with_(flaw_tensile=0.5e6) == new
    with pytest.raises(TypeError, match="not also its old name"):
        Params(flaw_tensile=0.5e6, flaw_tensile_strength=0.5e6)


def test_the_material_table_names_its_strength_columns():
    t = MaterialTable.from_materials(["a", "b"], [
        Material(kn=1.0, ks=1.0, tensile_strength=2.0, residual_tensile_strength=1.0),
        Material(kn=1.0, ks=1.0, tensile_strength=3.0, breakable=False)])
    s = t.strength_array()
    assert s.shape == (2, STRENGTH_COLUMNS) == (2, 10)
    assert list(s[:, COL_TENSILE_STRENGTH]) == list(t.tensile_strength) == [2.0, 3.0]
    assert list(s[:, COL_RESIDUAL_TENSILE_STRENGTH]) == list(t.residual_tensile_strength)
    assert list(s[:, COL_BREAKABLE]) == [1.0, 0.0]
