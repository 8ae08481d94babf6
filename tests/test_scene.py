"""A scene is data: a file both methods build from, checked before any compute, run by stages.

- the Adhikary scene survives a round trip through its JSON file, and the DEM model built from
  the file has the boundary sets the case always had (base fixed, sides on rollers) and its
  points;
- every kind of bad input is refused with a message naming the item;
- the stage runner runs gravity, a solve, a strength change, an excavation and cycles on a small
  column, with a record per stage; a strength change moves nothing;
- the continuum builds the same boundaries from the same scene: an elastic column on a fixed
  base with rollers settles as the uniaxial-strain closed form.
"""
import json
import math

import numpy as np
import pytest

from comparisons.scenes import adhikary
from dem_core.geometry import GeometrySpec, rectangle
from dem_core.contact.materials import Material
from dem_core.workflow.scene import Boundary, Scene, build_model
from dem_core.workflow.stages import (ChangeMaterial, Cycle, Excavate, Gravity, RaiseGravity, Solve,
                             run_stages)


def test_the_adhikary_scene_round_trips_and_builds_the_cases_model(tmp_path):
    p = adhikary.AdhikaryParams(edge_length=0.008, relax_iterations=2)
    sc = adhikary.scene(p, stages=[RaiseGravity((40.0, 60.0), watch=("A", "B"))])
    path = tmp_path / "adhikary.json"
    sc.save(path)
    again = Scene.load(path)
    assert again.to_dict() == sc.to_dict()
    assert json.loads(path.read_text())["stages"][0]["kind"] == "raise_gravity"
    m = build_model(again)
    bs = m.blocks
    base = bs.touching("bottom")
    sides = np.setdiff1d(np.union1d(bs.touching("left"), bs.touching("right")), base)
    assert np.all(m.props.fixity[base] == 7)                    # x, y and rotation held
    assert np.all(m.props.fixity[sides] == 1)                   # rollers: x only
    assert np.count_nonzero(m.props.fixity) == base.size + sides.size
    for name, xy in adhikary.monitoring_points(p).items():
        b, _, x0 = m.points[name]
        assert np.allclose(x0, xy)


def column_scene(**changes):
    """A 0.1 x 0.3 m column of two regions (a top part that can be excavated) on a base."""
    geo = GeometrySpec([rectangle("base", 0, -0.02, 0.1, 0), rectangle("rock", 0, 0, 0.1, 0.2),
                        rectangle("top", 0, 0.2, 0.1, 0.3)])
    stiff = Material(kn=1e10, ks=5e9, tensile_strength=1e6, cohesion=2e6, friction=35)
    d = dict(geometry=geo, materials={"*": stiff}, density=2500.0,
             groups={"floor": {"touching": "bottom"}}, boundaries=[Boundary("base")],
             points={"crest": (0.05, 0.19)},
             stages=[Gravity(50.0), Solve(ratio=1e-6, max_steps=20_000),
                     ChangeMaterial("*", {"tensile_strength": 0.9e6}), Cycle(200),
                     Excavate("top"), Solve(ratio=1e-6, max_steps=20_000)])
    d.update(changes)
    return Scene(**d)


def test_the_stage_runner_records_every_stage():
    sc = column_scene()
    m = build_model(sc)
    recs = run_stages(m, sc.stages)
    assert [r.kind for r in recs] == ["gravity", "solve", "change_material", "cycle",
                                      "excavate", "solve"]
    assert recs[1].verdict == "equilibrium" and recs[5].verdict == "equilibrium"
    assert recs[3].steps == 200 and all(r.seconds >= 0 for r in recs)
    # the crest sinks under 50 g, a strength change moves nothing, unloading lifts it back
    sink = recs[1].points["crest"][1]
    assert sink < 0
    assert recs[3].points["crest"][1] == pytest.approx(sink, rel=1e-6)
    assert recs[5].points["crest"][1] > sink
    assert recs[5].cracks == {"tension": 0, "shear": 0}


@pytest.mark.parametrize("edit, words", [
    (lambda d: d.update(colour="red"), "colour"),
    (lambda d: d["materials"]["*"].update(stiffness=1.0), "stiffness"),
    (lambda d: d.update(materials={"flaw:*": d["materials"]["*"]}), "boundary:base|rock"),
    (lambda d: d["materials"]["*"].update(friction=95.0), "friction"),
    (lambda d: d.update(density=-2500.0), "density"),
    (lambda d: d["stages"].append({"kind": "excavate", "group": "roof"}), "roof"),
    (lambda d: d["stages"].append({"kind": "change_material", "material": "granite",
                                   "changes": {"cohesion": 1.0}}), "granite"),
    (lambda d: d["stages"].append({"kind": "blast"}), "blast"),
    (lambda d: d["stages"].append({"kind": "cycle", "steps": 10, "speed": 2}), "speed"),
    (lambda d: d["groups"].update(wall={"touching": "north"}), "north"),
    (lambda d: d["groups"].update(wall={"union": ["floor", "ceiling"]}), "ceiling"),
    (lambda d: d["boundaries"].append({"group": "nowhere"}), "nowhere"),
    (lambda d: d.update(solver={"turbo": True}), "turbo"),
])
def test_bad_scene_files_are_refused_naming_the_item(tmp_path, edit, words):
    d = column_scene().to_dict()
    edit(d)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(d))
    with pytest.raises(ValueError, match=words):
        Scene.load(path)


def test_the_continuum_takes_the_same_boundaries_and_settles_as_uniaxial_strain():
    pytest.importorskip("dolfinx")
    from continuum_ref.from_scene import apply_boundaries, mesh_from_scene, scene_bounds
    from continuum_ref.materials import Elastic
    from continuum_ref.model import ContinuumModel

    geo = GeometrySpec([rectangle("rock", 0, 0, 1.0, 4.0)])
    sc = Scene(geo, {"*": Material(kn=1e10, ks=1e10)}, density=2000.0,
               groups=adhikary.CENTRIFUGE_GROUPS, boundaries=adhikary.CENTRIFUGE_BOUNDARIES,
               points={"top": (0.5, 4.0)})
    E, nu, H = 1e8, 0.25, 4.0
    model = ContinuumModel(mesh_from_scene(sc, 0.5), Elastic(E, nu), sc.density)
    apply_boundaries(model, sc, scene_bounds(sc))
    model.solve_gravity(1.0)
    M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))             # constrained modulus
    settle = sc.density * 9.81 * H ** 2 / (2 * M)
    assert model.displacement_at(["top"])[0, 1] == pytest.approx(-settle, rel=1e-6)
    assert abs(model.displacement_at(["top"])[0, 0]) < 1e-9 * settle


def test_the_stored_adhikary_scene_file_is_the_modules_base_run():
    from pathlib import Path
    stored = Scene.load(Path(adhikary.__file__).with_name("adhikary.json"))
    assert stored.to_dict() == adhikary.base_run().to_dict()


def test_the_lajtai_specimens_are_scenes_that_round_trip(tmp_path):
    from comparisons.scenes import lajtai

    p = lajtai.FlawParams(edge_length=0.01)
    ucs = lajtai.ucs_scene(p, rate=1.5e-7, max_strain=0.02)
    shear = lajtai.shear_scene(p, lajtai.ShearParams("closed", 0.5), normal_stress=1.2e6,
                               rate=3e-7, max_displacement=0.003)
    assert [type(s).__name__ for s in ucs.stages + shear.stages] == ["Load", "ServoLoad", "Load"]
    for sc in (ucs, shear):
        sc.save(tmp_path / "s.json")
        again = Scene.load(tmp_path / "s.json")
        assert again.to_dict() == sc.to_dict()
        m = build_model(again)
        fixed = m.group(sc.boundaries[0].group)
        assert np.all(m.props.fixity[fixed] == 7) and np.count_nonzero(m.props.fixity) == fixed.size
    # the lateral gauge of the compression test: the specimen's blocks on its side faces
    m = build_model(ucs)
    for side, x in (("left side", 0.0), ("right side", lajtai.UCS_WIDTH)):
        idx = m.group(side)
        assert idx.size > 5 and not np.isin(idx, m.group("platens")).any()
        for b in idx:
            v = m.blocks.vertices[m.blocks.vertex_offsets[b]:m.blocks.vertex_offsets[b + 1]]
            assert np.abs(v[:, 0] - x).min() < 1e-9
